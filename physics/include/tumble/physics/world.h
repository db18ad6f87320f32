// World: owns a set of rigid bodies and advances them in time, with
// collision, friction, restitution and sleeping.
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
// src/integrator.h for the time-stepping scheme. One step (src/world_step.cpp):
//   1. gravity and accumulated forces change the momenta P and L of awake
//      dynamic bodies; v = P / M, w = I^-1 L;
//   2. broadphase (src/world_contacts.cpp): each awake body's AABB,
//      grown by the distance it can travel this step, is checked against its
//      fat box in a DynamicTree; boxes that escaped are replaced and queried
//      for new pairs; planes are tested against every awake body's box;
//   3. narrowphase (src/collide.h) updates each pair with an awake body, in
//      parallel; then, in slot order, pairs that no longer overlap are
//      destroyed and touching a sleeping body (or coming within reach of
//      it this step) wakes its group;
//   4. sequential impulses in substeps (src/contact_solver.h) change v and w,
//      the joints' rows (src/joint_solver.h) with the contacts';
//      then P = M v and L = I w;
//   5. positions and orientations advance from P and L (src/integrator.h), plus
//      the solver's correction towards its substep motion;
//   6. groups of bodies connected by joints and by contacts that touch or
//      can touch within the step, that have all been slow for
//      time_to_sleep, fall asleep (src/island.cpp); to an awake body a
//      sleeping one is of infinite mass until they touch;
//   7. joints whose force or torque exceeded their break limits are removed
//      (broken_joints).
// Step 5 also checks each body it moved against
// WorldSettings::max_state_magnitude; diverged_bodies() lists those beyond
// it or no longer finite.
//
// Static bodies never move; kinematic bodies move with their set velocity
// and are not affected by anything; both have infinite mass. mass(),
// inertia and momenta of static and kinematic bodies read as zero.
//
// Deterministic: the same sequence of calls gives bit-identical results
// (no unordered containers, no pointer-keyed ordering), whatever the thread
// count or task system.
//
// Threads: step() may run the narrowphase's pairs and solve the contact
// groups on helper threads (set_thread_count) or on the embedder's
// (set_task_system, task_system.h); it returns when they are done. Not
// thread-safe otherwise: one thread owns a World. Accessors that take a BodyId
// require a valid one (contains(id)); that is asserted, not reported.
// step() does not allocate once the arrays have grown to the scene.
#pragma once

#include <cstddef>
#include <memory>
#include <span>

#include "tumble/physics/body.h"
#include "tumble/physics/joint.h"
#include "tumble/physics/math.h"
#include "tumble/physics/shape.h"
#include "tumble/physics/step_stats.h"
#include "tumble/physics/task_system.h"
#include "tumble/physics/world_settings.h"

namespace tumble::physics {

// A dynamic body's progress towards sleep (WorldSettings, "sleeping"): how
// long it has stayed near the pose where the count started, and how its
// speed has been rising. Part of its state: a restored world sleeps when
// the original would.
struct SleepProgress {
  double time = 0;                           // s near rest_position and rest_orientation
  Vec3 rest_position = Vec3::Zero();         // m, the centre of mass when the count started
  Quat rest_orientation = Quat::Identity();  // the orientation then
  double last_speed = 0;                     // m/s, the sleep test's speed at the last step
  double rise_start_speed = 0;               // m/s, that speed where its current rise began
  std::uint32_t rising_steps = 0;            // steps that speed has risen in a row
};

class World {
 public:
  World();
  ~World();
  World(World&&) noexcept;  // the moved-from World may only be assigned to or destroyed
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // Gravitational acceleration applied to every body (m/s^2). Default
  // (0, -9.81, 0). Changing it wakes every body.
  void set_gravity(const Vec3& g);
  const Vec3& gravity() const;

  void set_settings(const WorldSettings& settings);
  const WorldSettings& settings() const;

  // Threads step() solves contact groups on, the caller included (1, the
  // default: the caller alone). Each group is solved the same way on any
  // thread, so the results are bit-identical for every count. Starts or
  // stops helper threads, which sleep between steps.
  void set_thread_count(int threads);
  // Runs step()'s parallel phases on the embedder's threads instead
  // (task_system.h states the contract); not owned, and it must outlive its
  // use. nullptr goes back to the helpers of set_thread_count. Results are
  // bit-identical for every task system.
  void set_task_system(TaskSystem* tasks);
  // Threads step() runs on: the task system's count when one is set.
  int thread_count() const;

  // Creates a body and returns its new id. A dynamic body requires mass > 0
  // and a symmetric positive-definite inertia (asserted). The orientation is
  // normalised; P = M v and L = I w are set from the given velocities. A
  // plane shape makes a static body whatever desc.motion_type says. Bodies
  // start awake; a new static body wakes the sleeping bodies it overlaps.
  BodyId add_body(const BodyDesc& desc);
  // Restoring a saved world: creates a body under a given id, which must not
  // be in use and may exceed the next id (the ids in between are never
  // handed out). Otherwise as add_body.
  BodyId add_body_with_id(const BodyDesc& desc, BodyId id);
  // The id the next add_body hands out; set_next_body_id raises it (never
  // lowers it), so a restored world keeps the ids of removed bodies unused.
  BodyId next_body_id() const;
  void set_next_body_id(BodyId next);
  // Puts back a body's saved state bit-exactly, right after it was created
  // with add_body_with_id from a desc with the same pose: its pose (orientation taken as given, a unit
  // quaternion), and for a dynamic body the momenta P, L (BodyDesc gives
  // them as velocities, which M v would round) and its sleep state: awake
  // or asleep, with its progress towards sleep.
  void restore_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_momentum,
                     const Vec3& angular_momentum, bool awake, const SleepProgress& sleep);
  SleepProgress sleep_progress(BodyId id) const;

  // Destroys a body and its contacts, waking the bodies it touched. Returns
  // false if the id is unknown. Other ids stay valid; the last body in dense
  // order takes the removed body's index.
  bool remove_body(BodyId id);
  bool contains(BodyId id) const;

  std::size_t body_count() const;
  // Id of the body at a dense index, index < body_count(). The order is that
  // of creation except where remove_body moved a body.
  BodyId body_id_at(std::size_t index) const;

  // State, world frame.
  const Vec3& position(BodyId id) const;     // centre of mass (m)
  const Quat& orientation(BodyId id) const;  // body -> world, unit
  Vec3 linear_velocity(BodyId id) const;     // v = P / M (m/s); kinematic: as set; static: 0
  Vec3 angular_velocity(BodyId id) const;    // w = I^-1 L, I^-1 = R I_body^-1 R^T (rad/s)
  // Every body's id, position, orientation (w, x, y, z) and velocities, in
  // dense order (body_id_at), into flat arrays of body_count() entries:
  // ids[i], vectors at 3i, orientations at 4i. The values the accessors
  // above return, in one pass over the dense arrays instead of a lookup a
  // body (a frame of a 10,000-body world is taken this way every few ticks).
  void copy_poses(BodyId* ids, double* positions, double* orientations, double* linear_velocities,
                  double* angular_velocities) const;
  const Vec3& linear_momentum(BodyId id) const;   // P (kg m/s)
  const Vec3& angular_momentum(BodyId id) const;  // L about the centre of mass (kg m^2/s)
  double mass(BodyId id) const;                   // M (kg); 0 for static and kinematic bodies
  Mat3 inertia_world(BodyId id) const;            // R I_body R^T (kg m^2)
  const Mat3& inertia_body(BodyId id) const;      // I_body, about the centre of mass, body axes
  const Shape& shape(BodyId id) const;
  double kinetic_energy(BodyId id) const;  // 1/2 (P.v + L.w) (J)
  MotionType motion_type(BodyId id) const;
  double friction(BodyId id) const;
  double restitution(BodyId id) const;
  void set_friction(BodyId id, double friction);
  void set_restitution(BodyId id, double restitution);

  // Overwrites the kinematic state; P and L are recomputed from the
  // velocities with the body's mass and the new orientation (normalised).
  // Accumulated forces and torques are kept. A kinematic body keeps the
  // velocities as its motion; a static body ignores them. Wakes the body
  // (and, for a static body, the bodies around it).
  void set_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_velocity,
                 const Vec3& angular_velocity);

  // Force and torque accumulators, world frame, applied and cleared by the
  // next step(). Each call wakes the body. Static and kinematic bodies
  // ignore forces, torques and impulses.
  void add_force(BodyId id, const Vec3& force);  // through the centre of mass (N)
  // A force acting at a world point also adds the torque (r - x) x F.
  void add_force_at_point(BodyId id, const Vec3& force, const Vec3& world_point);
  void add_torque(BodyId id, const Vec3& torque);  // about the centre of mass (N m)
  const Vec3& accumulated_force(BodyId id) const;
  const Vec3& accumulated_torque(BodyId id) const;

  // Instant changes of momentum (N s), world frame. Each call wakes the body.
  void apply_impulse(BodyId id, const Vec3& impulse);  // P += J
  // Also L += (r - x) x J.
  void apply_impulse_at_point(BodyId id, const Vec3& impulse, const Vec3& world_point);

  // Joints (joint.h). add_joint requires a desc joint_desc_error accepts
  // (asserted); it wakes both bodies, and unless desc.collide_connected the
  // two stop colliding. remove_body removes the body's joints too.
  JointId add_joint(const JointDesc& desc);
  // Restoring a saved world: as add_joint under a given id (as
  // add_body_with_id), but it wakes neither body, so bodies restored asleep
  // stay asleep.
  JointId add_joint_with_id(const JointDesc& desc, JointId id);
  JointId next_joint_id() const;
  void set_next_joint_id(JointId next);
  // Why desc cannot make a joint in this world, as "field: reason" (the
  // fields as scene files name them), or nullptr when it can: bodies known
  // and distinct, not both fixed (static or the world), finite frames,
  // limits in order, a cone in (0, pi], lengths in order, a motor only on
  // a hinge or slider, non-negative forces.
  const char* joint_desc_error(const JointDesc& desc) const;
  // Sets desc's frames from world points on each body (anchor_a, anchor_b:
  // the same point for all but a distance joint) and a world axis (a unit
  // vector or not, nonzero), at the bodies' current poses: the frames'
  // x axes along `axis`, their y axes the same world direction, so a
  // hinge's angle and a slider's position start at 0. body_a and body_b
  // must be set, and known.
  void set_joint_frames(JointDesc& desc, const Vec3& anchor_a, const Vec3& anchor_b, const Vec3& axis) const;
  // Removes a joint and wakes its bodies; false if the id is unknown.
  bool remove_joint(JointId id);
  bool contains_joint(JointId id) const;
  std::size_t joint_count() const;
  JointId joint_id_at(std::size_t index) const;  // index < joint_count(), in creation order but for removals
  const JointDesc& joint_desc(JointId id) const;
  // Changes a hinge's or slider's motor (asserted) and wakes its bodies.
  void set_joint_motor(JointId id, const JointMotor& motor);
  JointState joint_state(JointId id) const;
  const JointImpulses& joint_impulses(JointId id) const;
  // Puts back saved warm-start impulses, right after add_joint_with_id.
  void restore_joint_impulses(JointId id, const JointImpulses& impulses);
  // The joints of a body, in the order they were added.
  std::span<const JointId> body_joints(BodyId id) const;
  // The joints the last step() broke (their force or torque beyond the
  // desc's limits) and removed, in joint order; valid
  // until the next step().
  std::span<const JointId> broken_joints() const;

  // Sleeping. wake() wakes a sleeping dynamic body and every sleeping body
  // connected to it by joints and touching contacts (its group).
  void wake(BodyId id);
  // Dynamic: not sleeping. Kinematic: moving. Static: false.
  bool is_awake(BodyId id) const;
  std::size_t awake_body_count() const;     // dynamic bodies awake plus kinematic bodies moving
  std::size_t sleeping_body_count() const;  // dynamic bodies asleep

  // Contacts, as of the end of the last step.
  std::size_t contact_count() const;        // pairs with at least one manifold point
  std::size_t contact_point_count() const;  // manifold points, speculative ones included
  // Deepest overlap among the current manifold points (m), 0 when none
  // overlaps.
  double max_penetration() const;
  const StepStats& last_step_stats() const;

  // The bodies whose state the last step() left beyond
  // settings().max_state_magnitude or not finite (NaN or infinite), in
  // dense order; empty after almost every step. The World goes on stepping
  // them, and a NaN spreads to whatever such a body touches, so the caller
  // should remove them (remove_body) before the next step. Valid until the
  // next step() or remove_body(). Only bodies that moved in the step are
  // checked; set_state and the other setters are not.
  std::span<const BodyId> diverged_bodies() const;

  // Advances every body by dt seconds. A dt <= 0 only clears the force and
  // torque accumulators.
  void step(double dt);

 private:
  // The bodies, broadphase trees, contacts, solver and helper threads
  // (src/world_impl.h).
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tumble::physics
