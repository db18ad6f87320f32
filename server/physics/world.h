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
// integrator.h for the time-stepping scheme. One step (world_step.cpp):
//   1. gravity and accumulated forces change the momenta P and L of awake
//      dynamic bodies; v = P / M, w = I^-1 L;
//   2. broadphase (broadphase in world_contacts.cpp): each awake body's AABB,
//      grown by the distance it can travel this step, is checked against its
//      fat box in a DynamicTree; boxes that escaped are replaced and queried
//      for new pairs; planes are tested against every awake body's box;
//   3. narrowphase (collide.h) updates each pair with an awake body, in
//      parallel; then, in slot order, pairs that no longer overlap are
//      destroyed and touching a sleeping body wakes its island;
//   4. sequential impulses in substeps (contact_solver.h) change v and w;
//      then P = M v and L = I w;
//   5. positions and orientations advance from P and L (integrator.h), plus
//      the solver's correction towards its substep motion;
//   6. islands of bodies connected by touching contacts that have all been
//      slow for time_to_sleep fall asleep (island.cpp).
//
// Static bodies never move; kinematic bodies move with their set velocity
// and are not affected by anything; both have infinite mass. mass(),
// inertia and momenta of static and kinematic bodies read as zero.
//
// Deterministic: the same sequence of calls gives bit-identical results
// (no unordered containers, no pointer-keyed ordering), whatever the thread
// count.
//
// Threads: step() may run the narrowphase's pairs and solve the contact
// groups on helper threads (set_thread_count, worker_team.h); it returns
// when they are done. Not
// thread-safe otherwise: one thread owns a World. Accessors that take a BodyId
// require a valid one (contains(id)); that is asserted, not reported.
// step() does not allocate once the arrays have grown to the scene.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "physics/aabb.h"
#include "physics/body.h"
#include "physics/body_state.h"
#include "physics/contact.h"
#include "physics/contact_solver.h"
#include "physics/dynamic_tree.h"
#include "physics/math.h"
#include "physics/shape.h"
#include "physics/transform.h"
#include "physics/worker_team.h"

namespace tumble::physics {

// The default number of substeps (WorldSettings::substeps): at least
// kSubstepRate a second and at least kMinSubsteps a step.
inline constexpr double kSubstepRate = 240;  // Hz
inline constexpr int kMinSubsteps = 2;

// Tuning of the collision pipeline and the solver. The defaults suit bodies
// of about 0.1 m to 10 m at 60 to 240 steps per second.
struct WorldSettings {
  // The contact solver (contact_solver.h) splits each step into substeps;
  // each substep makes `velocity_iterations` soft passes over the contact
  // rows and `relax_iterations` rigid ones. substeps = 0 (the default) takes
  // enough that a substep is at most 1/kSubstepRate s, and at least
  // kMinSubsteps (at most 64): 4 at 60 steps per second (Box2D v3's default), 2 at 120
  // and at 240. A faster step rate then costs little more solver work a
  // second while the narrowphase runs more often. Measured on a 210-box
  // pyramid over 10 s (largest displacement) and the top of a ten-box
  // column over 30 s (drift): 60 Hz x 4, 33 mm and 3.4 mm; 240 Hz x 2,
  // 8.2 mm and 0.7 mm; 240 Hz x 1, 31 mm and 3.8 mm; 240 Hz x 4, 2.1 mm and
  // under 0.1 mm at twice the solver work of x 2. Any other value: exactly
  // that many.
  int substeps = 0;
  int velocity_iterations = 1;
  int relax_iterations = 1;
  // Frequency of the spring that pushes overlapping bodies apart (Hz); 0
  // means an eighth of the substep rate (Box2D's 30 Hz at 60 steps of 4
  // substeps; 60 Hz at 240 steps of 2), which keeps the push equally stiff
  // relative to the substep whatever the rates. The solver caps it at a
  // quarter of the substep rate.
  double contact_hertz = 0;
  double contact_damping_ratio = 10;   // of that push
  double max_push_speed = 3;           // m/s: the push never separates faster
  double restitution_threshold = 1.0;  // m/s: slower impacts do not bounce
  // Every pair gets contact points up to this separation (m), plus the
  // distance the two bodies can close within the step (speculative contacts).
  double contact_margin = 0.02;
  double aabb_margin = 0.1;  // m: fat boxes in the broadphase tree
  bool sleep_enabled = true;
  // A body is slow when |v| and |w| times its bounding radius are both
  // below sleep_speed; an island sleeps when all its bodies have been slow for
  // time_to_sleep. Only islands that touch something sleep: a free body keeps
  // drifting however slowly it moves.
  double sleep_speed = 0.05;   // m/s
  double time_to_sleep = 0.5;  // s
};

// Counters of the last step, for diagnostics and tests.
struct StepStats {
  std::size_t integrated_bodies = 0;    // awake dynamic and moving kinematic bodies advanced
  std::size_t moved_proxies = 0;        // fat boxes replaced in the broadphase
  std::size_t narrowphase_pairs = 0;    // contacts whose manifold was updated (computed or reused)
  std::size_t manifolds_computed = 0;   // of those, recomputed from the shapes
  std::size_t solved_contacts = 0;      // manifolds with points given to the solver
  std::size_t solved_points = 0;        // their points
  std::size_t islands = 0;              // groups of those that share no dynamic body, solved apart
};

class World {
 public:
  World();

  // Gravitational acceleration applied to every body (m/s^2). Default
  // (0, -9.81, 0). Changing it wakes every body.
  void set_gravity(const Vec3& g);
  const Vec3& gravity() const;

  void set_settings(const WorldSettings& settings);
  const WorldSettings& settings() const { return settings_; }

  // Threads step() solves contact groups on, the caller included (1, the
  // default: the caller alone). Each group is solved the same way on any
  // thread, so the results are bit-identical for every count. Starts or
  // stops helper threads, which sleep between steps.
  void set_thread_count(int threads);
  int thread_count() const { return team_ ? team_->thread_count() : 1; }

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
  BodyId next_body_id() const { return static_cast<BodyId>(id_to_dense_.size()); }
  void set_next_body_id(BodyId next);
  // Puts back a body's saved state bit-exactly, right after it was created
  // with add_body_with_id from a desc with the same pose: its pose (orientation taken as given, a unit
  // quaternion), and for a dynamic body the momenta P, L (BodyDesc gives
  // them as velocities, which M v would round) and its sleep state: awake
  // or asleep, with the time it has been slow (s).
  void restore_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_momentum,
                     const Vec3& angular_momentum, bool awake, double sleep_time);
  double sleep_time(BodyId id) const;  // s the body has been slower than sleep_speed

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
  const Vec3& position(BodyId id) const;          // centre of mass (m)
  const Quat& orientation(BodyId id) const;       // body -> world, unit
  Vec3 linear_velocity(BodyId id) const;          // v = P / M (m/s); kinematic: as set; static: 0
  Vec3 angular_velocity(BodyId id) const;         // w = I^-1 L, I^-1 = R I_body^-1 R^T (rad/s)
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

  // Sleeping. wake() wakes a sleeping dynamic body and every sleeping body
  // connected to it by touching contacts (its island).
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
  const StepStats& last_step_stats() const { return stats_; }

  // Advances every body by dt seconds. A dt <= 0 only clears the force and
  // torque accumulators.
  void step(double dt);

 private:
  // Marks a removed id in id_to_dense_.
  static constexpr std::uint32_t kNoIndex = 0xffffffff;

  // Collision and sleep bookkeeping of one body.
  struct BodyRecord {
    MotionType motion_type = MotionType::dynamic_body;
    bool moved = false;    // fat box replaced in this step's broadphase
    double sleep_time = 0;       // s spent slower than sleep_speed
    double bounding_radius = 0;  // m, of the shape about the centre of mass
    double reach = 0;            // m the body can travel this step (0 unless awake_)
    Vec3 kinematic_linear_velocity = Vec3::Zero();
    Vec3 kinematic_angular_velocity = Vec3::Zero();
    std::int32_t proxy = DynamicTree::kNull;  // leaf in static_tree_ or movable_tree_
    ContactKey contact_head = kNullContactKey;
    std::uint32_t contact_count = 0;
  };

  std::size_t dense_index(BodyId id) const;
  bool is_dynamic(std::size_t i) const { return records_[i].motion_type == MotionType::dynamic_body; }

  // Body helpers (world.cpp).
  Aabb shape_aabb(std::size_t i) const;
  // Writes aabbs_[i], stamping box_passes_[i] when the box changed.
  void set_box(std::size_t i, const Aabb& box);
  void refresh_solver_data(std::size_t i);
  void set_kinematic_awake(std::size_t i);
  // linear_velocity() and angular_velocity() of the body at dense index i.
  Vec3 linear_velocity_at(std::size_t i) const;
  Vec3 angular_velocity_at(std::size_t i) const;

  // Contacts and collision (world_contacts.cpp).
  bool can_collide(std::size_t a, std::size_t b) const;
  bool has_contact(std::uint32_t a, std::uint32_t b) const;
  void create_contact(std::uint32_t a, std::uint32_t b);
  void destroy_contact(std::uint32_t c);
  void destroy_contacts_of(std::uint32_t body, bool wake_others);
  void relabel_body(std::uint32_t from, std::uint32_t to);
  void update_broadphase(double dt);
  void update_contacts();
  // True when the pair was apart when last updated and neither step box has
  // changed since: neither the fat boxes (they move only when a step box
  // leaves them) nor the answer can have changed.
  bool still_apart(const ContactLink& link) const {
    return link.apart && box_passes_[link.body_a] <= link.updated_pass && box_passes_[link.body_b] <= link.updated_pass;
  }
  // The narrowphase of one pair: refreshes its manifold and its link's
  // flags, and says what the world must do about it (ContactUpdate bits,
  // world_contacts.cpp). Writes only links_[slot] and contacts_[slot], so
  // pairs may be updated on several threads at once.
  std::uint8_t update_contact(std::uint32_t slot);
  // What update_contact() left to do, on the owning thread: destroys the
  // pair or, when it touches, wakes its bodies and lists it in active_.
  void finish_contact_update(std::uint32_t slot, std::uint8_t update);
  // Returns true when the manifold was computed afresh, false when reused.
  bool update_manifold(Contact& contact, std::uint32_t index);
  void wake_overlapping(const Aabb& box);

  // Step phases (world_step.cpp).
  void integrate_velocities(double dt);
  void solve_contacts(double dt);
  void integrate_positions(double dt);

  // Sleep (island.cpp).
  void update_sleep(double dt);
  void wake_island(std::uint32_t body);
  void put_to_sleep(std::uint32_t body);

  WorldSettings settings_;
  Vec3 gravity_;

  // Dense arrays, one entry per live body, all in the same order.
  std::vector<BodyState> states_;
  std::vector<BodyMass> masses_;
  std::vector<Shape> shapes_;
  std::vector<BodyId> dense_to_id_;
  std::vector<BodyRecord> records_;
  std::vector<Transform> transforms_;       // pose with R(q), current for every body
  std::vector<SolverVelocity> velocities_;  // v, w of the step (zero for static and sleeping bodies)
  std::vector<SolverVelocity> external_;    // change of v, w from gravity and forces this step
  std::vector<Mat3> inverse_inertia_;       // world frame, of the step (zero unless awake dynamic)
  std::vector<double> inverse_masses_;      // 1/M for dynamic bodies, else 0
  std::vector<double> frictions_;
  std::vector<double> restitutions_;
  std::vector<Aabb> aabbs_;                 // box grown by reach, this step (awake bodies)
  // 1 while the body is stepped: dynamic and not asleep, or kinematic and
  // moving. Apart from the records so that the passes over every body that
  // skip those at rest read a byte a body, not a record (a world of 10,000
  // mostly sleeping bodies: 10 kB a pass instead of 1.1 MB).
  std::vector<std::uint8_t> awake_;
  // The contact pass (contact_pass_) that first sees aabbs_[i] as it is:
  // a contact updated in a later pass has seen this box (set_box).
  std::vector<std::uint64_t> box_passes_;

  // Indexed by id; kNoIndex once removed. Its size is the next id to hand out.
  std::vector<std::uint32_t> id_to_dense_;

  std::vector<std::uint32_t> planes_;  // dense indices of the plane bodies

  // Broadphase: static bodies in one tree, dynamic and kinematic in another.
  DynamicTree static_tree_;
  DynamicTree movable_tree_;
  std::vector<std::uint32_t> moved_;

  // Contacts: slots with a free list; active_ lists those touching this
  // step. links_[k] is the hot part of contacts_[k] (contact.h).
  std::vector<Contact> contacts_;
  std::vector<ContactLink> links_;
  std::vector<std::uint32_t> free_contacts_;
  std::vector<std::uint32_t> active_;
  // Scratch of update_contacts(): the slots updated in parallel and what
  // each asks for (ContactUpdate bits), index for index.
  std::vector<std::uint32_t> updating_;
  std::vector<std::uint8_t> updates_;
  std::uint64_t contact_pass_ = 0;  // counts update_contacts() calls; see ContactLink::updated_pass

  ContactSolver solver_;
  // Helper threads, made by the first set_thread_count above 1; behind a
  // pointer so the World stays movable while the helpers keep their team.
  std::unique_ptr<WorkerTeam> team_;

  // Scratch of wake_island()'s flood.
  std::vector<std::uint32_t> island_stack_;
  std::vector<std::uint32_t> woken_;  // bodies wake_island() woke during update_contacts()
  bool collecting_woken_ = false;     // in update_contacts(): wake_island() adds to woken_

  StepStats stats_;
};

}  // namespace tumble::physics
