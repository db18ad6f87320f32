// World::Impl: the state and the step pipeline behind World (world.h).
// Its public methods do what World's methods of the same name do; World
// forwards to them (world_api.cpp). Defined in world.cpp (bodies and
// accessors), world_step.cpp (the step), world_contacts.cpp (broadphase and
// narrowphase) and island.cpp (sleeping).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "aabb.h"
#include "body_state.h"
#include "contact.h"
#include "contact_solver.h"
#include "dynamic_tree.h"
#include "joint_solver.h"
#include "pair_set.h"
#include "transform.h"
#include "tumble/physics/body.h"
#include "tumble/physics/math.h"
#include "tumble/physics/shape.h"
#include "tumble/physics/step_stats.h"
#include "tumble/physics/task_system.h"
#include "tumble/physics/world.h"
#include "tumble/physics/world_settings.h"
#include "worker_team.h"

namespace tumble::physics {

class World::Impl {
 public:
  Impl();

  void set_gravity(const Vec3& g);
  const Vec3& gravity() const;
  void set_settings(const WorldSettings& settings);
  const WorldSettings& settings() const { return settings_; }
  void set_thread_count(int threads);
  void set_task_system(TaskSystem* tasks) { task_system_ = tasks; }
  int thread_count() const { return tasks() != nullptr ? tasks()->thread_count() : 1; }
  BodyId add_body(const BodyDesc& desc);
  BodyId add_body_with_id(const BodyDesc& desc, BodyId id);
  BodyId next_body_id() const { return static_cast<BodyId>(id_to_dense_.size()); }
  void set_next_body_id(BodyId next);
  void restore_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_momentum,
                     const Vec3& angular_momentum, bool awake, const SleepProgress& sleep);
  SleepProgress sleep_progress(BodyId id) const;
  bool remove_body(BodyId id);
  bool contains(BodyId id) const;
  std::size_t body_count() const;
  BodyId body_id_at(std::size_t index) const;
  const Vec3& position(BodyId id) const;
  const Quat& orientation(BodyId id) const;
  Vec3 linear_velocity(BodyId id) const;
  Vec3 angular_velocity(BodyId id) const;
  void copy_poses(BodyId* ids, double* positions, double* orientations, double* linear_velocities,
                  double* angular_velocities) const;
  const Vec3& linear_momentum(BodyId id) const;
  const Vec3& angular_momentum(BodyId id) const;
  double mass(BodyId id) const;
  Mat3 inertia_world(BodyId id) const;
  const Mat3& inertia_body(BodyId id) const;
  const Shape& shape(BodyId id) const;
  double kinetic_energy(BodyId id) const;
  MotionType motion_type(BodyId id) const;
  double friction(BodyId id) const;
  double restitution(BodyId id) const;
  void set_friction(BodyId id, double friction);
  void set_restitution(BodyId id, double restitution);
  void set_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_velocity,
                 const Vec3& angular_velocity);
  void add_force(BodyId id, const Vec3& force);
  void add_force_at_point(BodyId id, const Vec3& force, const Vec3& world_point);
  void add_torque(BodyId id, const Vec3& torque);
  const Vec3& accumulated_force(BodyId id) const;
  const Vec3& accumulated_torque(BodyId id) const;
  void apply_impulse(BodyId id, const Vec3& impulse);
  void apply_impulse_at_point(BodyId id, const Vec3& impulse, const Vec3& world_point);
  JointId add_joint(const JointDesc& desc);
  JointId add_joint_with_id(const JointDesc& desc, JointId id);
  JointId next_joint_id() const { return static_cast<JointId>(joint_id_to_dense_.size()); }
  void set_next_joint_id(JointId next);
  const char* joint_desc_error(const JointDesc& desc) const;
  void set_joint_frames(JointDesc& desc, const Vec3& anchor_a, const Vec3& anchor_b, const Vec3& axis) const;
  bool remove_joint(JointId id);
  bool contains_joint(JointId id) const { return id < joint_id_to_dense_.size() && joint_id_to_dense_[id] != kNoIndex; }
  std::size_t joint_count() const { return joints_.size(); }
  JointId joint_id_at(std::size_t index) const { return joints_[index].id; }
  const JointDesc& joint_desc(JointId id) const { return joint(id).desc; }
  void set_joint_motor(JointId id, const JointMotor& motor);
  JointState joint_state(JointId id) const;
  const JointImpulses& joint_impulses(JointId id) const { return joint(id).impulses; }
  void restore_joint_impulses(JointId id, const JointImpulses& impulses);
  std::span<const JointId> body_joints(BodyId id) const;
  std::span<const JointId> broken_joints() const { return broken_; }
  void wake(BodyId id);
  bool is_awake(BodyId id) const;
  std::size_t awake_body_count() const;
  std::size_t sleeping_body_count() const;
  std::size_t contact_count() const;
  std::size_t contact_point_count() const;
  double max_penetration() const;
  const StepStats& last_step_stats() const { return stats_; }
  std::span<const BodyId> diverged_bodies() const { return diverged_; }
  void step(double dt);

 private:
  // Marks a removed id in id_to_dense_.
  static constexpr std::uint32_t kNoIndex = 0xffffffff;

  // Collision and sleep bookkeeping of one body.
  struct BodyRecord {
    MotionType motion_type = MotionType::dynamic_body;
    bool moved = false;          // fat box replaced in this step's broadphase
    SleepProgress sleep;         // towards sleep (island.cpp)
    double bounding_radius = 0;  // m, of the shape about the centre of mass
    double reach = 0;            // m the body can travel this step (0 unless awake_)
    Vec3 kinematic_linear_velocity = Vec3::Zero();
    Vec3 kinematic_angular_velocity = Vec3::Zero();
    std::int32_t proxy = DynamicTree::kNull;  // leaf in static_tree_ or movable_tree_
    ContactKey contact_head = kNullContactKey;
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
  // The slot of the contact between bodies a and b, or kNoIndex.
  std::uint32_t find_contact(std::uint32_t a, std::uint32_t b) const;
  // Body i's fat box in its broadphase tree (the static or the movable
  // one); i must have a proxy.
  const Aabb& fat_box(std::uint32_t i) const {
    const DynamicTree& tree = records_[i].motion_type == MotionType::static_body ? static_tree_ : movable_tree_;
    return tree.fat_aabb(records_[i].proxy);
  }
  bool has_contact(std::uint32_t a, std::uint32_t b) const { return find_contact(a, b) != kNoIndex; }
  void create_contact(std::uint32_t a, std::uint32_t b);
  // Contacts alive: the slots in use.
  std::size_t live_pair_count() const { return links_.size() - free_contacts_.size(); }
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
  // True when the state of the body at dense index i has a component
  // beyond `limit` in magnitude or not finite (WorldSettings::max_state_magnitude).
  bool diverged(std::size_t i, double limit) const;

  // Joints (world_joints.cpp).
  const Joint& joint(JointId id) const;
  // Dense index of a joint's side, kNoJointBody for the world.
  std::uint32_t joint_body(BodyId id) const { return id == kWorldBodyId ? kNoJointBody : id_to_dense_[id]; }
  // Whether a joint that turns off their collision connects the bodies at
  // dense indices a and b.
  bool jointed(std::size_t a, std::size_t b) const;
  // joint_edges_ for this step: each joint with an awake dynamic body
  // (waking a sleeping body jointed to an awake one first).
  void collect_joint_edges();
  // Removes the joints whose force or torque of this step exceeded their
  // limits, listing them in broken_.
  void break_joints();
  // After a joint between bodies a and b stopped keeping them apart: pairs
  // them if their boxes overlap, as the broadphase would have.
  void pair_if_overlapping(std::uint32_t a, std::uint32_t b);

  // Sleep (island.cpp).
  void update_sleep(double dt);
  bool accelerating(const SleepProgress& sleep) const;
  bool ready_to_sleep(const BodyRecord& record) const;
  // Why a group wakes. A body asleep that another comes to touch has not
  // moved yet: the group keeps its progress towards sleep, and sleeps again
  // as soon as whatever woke it is still (a landing heap is struck over and
  // over while its last cubes settle). Anything else restarts the count.
  enum class WakeCause : std::uint8_t { disturbed, touched };
  void wake_island(std::uint32_t body, WakeCause cause = WakeCause::disturbed);
  // Calls visit(other) for each body joined to `body` by a contact that may
  // touch, then by each of its joints (not for the world).
  template <typename Visit>
  void for_each_neighbour(std::uint32_t body, Visit&& visit) const;
  void put_to_sleep(std::uint32_t body);
  // A dynamic body that sleeps.
  bool asleep(std::uint32_t body) const { return !awake_[body] && is_dynamic(body); }
  // Whether an awake body may disturb a sleeping one it rests against: a
  // kinematic body in motion, or a dynamic one that is not settling (its
  // count just started over, it is at or above the sleep speed, or it is
  // speeding up).
  bool stirring(std::uint32_t body) const;
  // Wakes each sleeping body of beside_sleepers_ whose awake neighbour is
  // joined, by contacts that may touch and by joints, to a stirring body.
  void wake_beside_stirring();
  // Whether the contact in `slot` touches, or its bodies can close its gap
  // within this step: a point within kTouchSlop plus both bodies' reach.
  bool may_touch(std::uint32_t slot) const;

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
  std::vector<Aabb> aabbs_;  // box grown by reach, this step (awake bodies)
  // 1 while the body is stepped: dynamic and not asleep, or kinematic and
  // moving. Apart from the records so that the passes over every body that
  // skip those at rest read a byte a body, not a record (a world of 10,000
  // mostly sleeping bodies: 10 kB a pass instead of 1.1 MB).
  std::vector<std::uint8_t> awake_;
  // The contact pass (contact_pass_) that first sees aabbs_[i] as it is:
  // a contact updated in a later pass has seen this box (set_box).
  std::vector<std::uint64_t> box_passes_;
  // The same for body i's fat box in its broadphase tree: a pair whose
  // bodies' fat boxes are both older than its last update still overlaps.
  std::vector<std::uint64_t> fat_passes_;

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
  PairSet pairs_;  // each alive contact's bodies, with its slot
  std::vector<std::uint32_t> free_contacts_;
  std::vector<std::uint32_t> active_;
  // Scratch of update_contacts(): the slots updated in parallel and what
  // each asks for (ContactUpdate bits), index for index.
  std::vector<std::uint32_t> updating_;
  std::vector<std::uint8_t> updates_;
  std::uint64_t contact_pass_ = 0;  // counts update_contacts() calls; see ContactLink::updated_pass

  // Joints: dense, in creation order but for swap-removals; the id ->
  // dense table (kNoIndex once removed; its size is the next id); each
  // body's joints by BodyId (bodies' ids never move, unlike their dense
  // indices); this step's joints to solve.
  std::vector<Joint> joints_;
  std::vector<std::uint32_t> joint_id_to_dense_;
  std::vector<std::vector<JointId>> body_joints_;
  std::vector<JointConstraint> joint_edges_;
  std::vector<JointId> broken_;  // broken_joints() of the last step

  ContactSolver solver_;
  // Helper threads, made by the first set_thread_count above 1; behind a
  // pointer so the helpers keep their team wherever the Impl is.
  std::unique_ptr<WorkerTeam> team_;
  TaskSystem* task_system_ = nullptr;  // the embedder's (set_task_system), not owned; used instead of team_
  // Where step() runs its parallel phases: the embedder's task system, else
  // the built-in team, else nowhere (every task on the calling thread).
  TaskSystem* tasks() const { return task_system_ != nullptr ? task_system_ : team_.get(); }

  // Scratch of wake_island()'s flood.
  std::vector<std::uint32_t> island_stack_;
  // Scratch of update_sleep(): by body, its parent in the forest of an
  // island's sleep groups, and at a group's root what the group holds.
  std::vector<std::uint32_t> sleep_parent_;
  std::vector<std::uint8_t> sleep_flags_;
  std::vector<std::uint32_t> settled_;  // of update_sleep(): an island's ready bodies that may sleep apart
  std::vector<std::uint32_t> woken_;    // bodies wake_island() woke during update_contacts()
  // Slots of this step's contacts that may touch, between an awake body and
  // a sleeping one that were in touch at the last update as well.
  std::vector<std::uint32_t> beside_sleepers_;
  // Scratch of wake_beside_stirring(): the awake bodies its floods reached,
  // and by body its verdict on them (all 0 between calls; apart from
  // sleep_flags_, which update_sleep() leaves as its groups were).
  std::vector<std::uint32_t> stir_reached_;
  std::vector<std::uint8_t> stir_marks_;
  bool collecting_woken_ = false;  // in update_contacts(): wake_island() adds to woken_

  StepStats stats_;
  std::vector<BodyId> diverged_;  // diverged_bodies() of the last step
};

}  // namespace tumble::physics
