// World: owns a set of rigid bodies and advances them in time.
//
// Bodies are named by BodyId handles. Their data lives in dense arrays
// (one BodyState, BodyMass and Shape per body, in the same order) so a step
// walks contiguous memory; an id -> dense-index table maps handles to slots.
// Removing a body moves the last body into its slot, so dense indices
// (body_id_at) change on removal while ids stay valid.
//
// Units are SI and every vector is in the world frame unless a name says
// otherwise. The dynamics follow Baraff, "An Introduction to Physically Based
// Modeling: Rigid Body Simulation I" (SIGGRAPH course notes); see
// integrator.h for the time-stepping scheme.
//
// Not thread-safe: one thread owns a World. Accessors that take a BodyId
// require a valid one (contains(id)); that is asserted, not reported.
// step() does not allocate.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "physics/body.h"
#include "physics/body_state.h"
#include "physics/math.h"
#include "physics/shape.h"

namespace tumble::physics {

class World {
 public:
  World();

  // Gravitational acceleration applied to every body (m/s^2). Default
  // (0, -9.81, 0).
  void set_gravity(const Vec3& g);
  const Vec3& gravity() const;

  // Creates a body and returns its new id. Requires mass > 0 and a symmetric
  // positive-definite inertia (asserted). The orientation is normalised;
  // P = M v and L = I w are set from the given velocities.
  BodyId add_body(const BodyDesc& desc);
  // Destroys a body. Returns false if the id is unknown. Other ids stay
  // valid; the last body in dense order takes the removed body's index.
  bool remove_body(BodyId id);
  bool contains(BodyId id) const;

  std::size_t body_count() const;
  // Id of the body at a dense index, index < body_count(). The order is that
  // of creation except where remove_body moved a body.
  BodyId body_id_at(std::size_t index) const;

  // State, world frame.
  const Vec3& position(BodyId id) const;          // centre of mass (m)
  const Quat& orientation(BodyId id) const;       // body -> world, unit
  Vec3 linear_velocity(BodyId id) const;          // v = P / M (m/s)
  Vec3 angular_velocity(BodyId id) const;         // w = I^-1 L, I^-1 = R I_body^-1 R^T (rad/s)
  const Vec3& linear_momentum(BodyId id) const;   // P (kg m/s)
  const Vec3& angular_momentum(BodyId id) const;  // L about the centre of mass (kg m^2/s)
  double mass(BodyId id) const;                   // M (kg)
  Mat3 inertia_world(BodyId id) const;            // R I_body R^T (kg m^2)
  const Mat3& inertia_body(BodyId id) const;      // I_body, about the centre of mass, body axes
  const Shape& shape(BodyId id) const;
  double kinetic_energy(BodyId id) const;  // 1/2 (P.v + L.w) (J)

  // Overwrites the kinematic state; P and L are recomputed from the
  // velocities with the body's mass and the new orientation (normalised).
  // Accumulated forces and torques are kept.
  void set_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_velocity,
                 const Vec3& angular_velocity);

  // Force and torque accumulators, world frame, applied and cleared by the
  // next step().
  void add_force(BodyId id, const Vec3& force);  // through the centre of mass (N)
  // A force acting at a world point also adds the torque (r - x) x F.
  void add_force_at_point(BodyId id, const Vec3& force, const Vec3& world_point);
  void add_torque(BodyId id, const Vec3& torque);  // about the centre of mass (N m)
  const Vec3& accumulated_force(BodyId id) const;
  const Vec3& accumulated_torque(BodyId id) const;

  // Instant changes of momentum (N s), world frame.
  void apply_impulse(BodyId id, const Vec3& impulse);  // P += J
  // Also L += (r - x) x J.
  void apply_impulse_at_point(BodyId id, const Vec3& impulse, const Vec3& world_point);

  // Advances every body by dt seconds: applies gravity and the accumulated
  // forces and torques, integrates (integrator.h), clears the accumulators.
  void step(double dt);

 private:
  // Marks a removed id in id_to_dense_.
  static constexpr std::uint32_t kNoIndex = 0xffffffff;

  std::size_t dense_index(BodyId id) const;

  Vec3 gravity_;

  // Dense arrays, one entry per live body, all in the same order.
  std::vector<BodyState> states_;
  std::vector<BodyMass> masses_;
  std::vector<Shape> shapes_;
  std::vector<BodyId> dense_to_id_;

  // Indexed by id; kNoIndex once removed. Its size is the next id to hand out.
  std::vector<std::uint32_t> id_to_dense_;
};

}  // namespace tumble::physics
