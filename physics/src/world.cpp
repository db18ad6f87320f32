// World: body creation, removal, accessors and the calls that change a
// body's state. The step pipeline is in world_step.cpp, contacts in
// world_contacts.cpp, sleeping in island.cpp.
#include "world_impl.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cassert>
#include <cmath>

#include "collide.h"
#include "rotation.h"
#include "tumble/physics/convex_hull.h"

namespace tumble::physics {
namespace {

// Contact room reserved a body (World::add_body): slots for pairs whose fat
// boxes overlap, and the touching pairs among them. Measured in a landing
// pile of 900 boxes: up to 4.6 slots in use a body (pairs come and go while
// they bounce) and 1.8 touching; a field of resting spheres: 3 and 1.
constexpr std::size_t kContactSlotsPerBody = 8;
constexpr std::size_t kTouchingContactsPerBody = 2;

double bounding_radius_of(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::sphere:
      return shape.radius;
    case ShapeType::box:
      return shape.half_extents.norm();
    case ShapeType::capsule:
      return shape.half_height + shape.radius;
    case ShapeType::convex_hull:
      return shape.hull ? shape.hull->bounding_radius : 0.0;
    case ShapeType::none:
    case ShapeType::plane:
      return 0.0;
  }
  return 0.0;
}

// Swap-removes element index of v by moving the last element into it.
template <typename T>
void swap_remove(std::vector<T>& v, std::size_t index) {
  if (index + 1 != v.size()) v[index] = std::move(v.back());
  v.pop_back();
}

}  // namespace

World::Impl::Impl() : gravity_(0.0, -9.81, 0.0) {}

void World::Impl::set_gravity(const Vec3& g) {
  gravity_ = g;
  for (std::size_t i = 0; i < records_.size(); ++i) wake_island(static_cast<std::uint32_t>(i));
}

const Vec3& World::Impl::gravity() const { return gravity_; }

void World::Impl::set_settings(const WorldSettings& settings) {
  settings_ = settings;
  // Whether two step boxes are apart depends on the contact margin: every
  // pair looks again at its next update.
  for (ContactLink& link : links_) link.apart = false;
  if (!settings_.sleep_enabled) {
    for (std::size_t i = 0; i < records_.size(); ++i) wake_island(static_cast<std::uint32_t>(i));
  }
}

Aabb World::Impl::shape_aabb(std::size_t i) const {
  const Shape& shape = shapes_[i];
  const Transform& t = transforms_[i];
  switch (shape.type) {
    case ShapeType::sphere:
      return Aabb{t.position.array() - shape.radius, t.position.array() + shape.radius};
    case ShapeType::box: {
      // Half extents of the rotated box: |R| h (Ericson 4.2.6).
      const Vec3 extent = t.rotation.cwiseAbs() * shape.half_extents;
      return Aabb{t.position - extent, t.position + extent};
    }
    case ShapeType::capsule: {
      const Vec3 extent = (shape.half_height * t.rotation.col(1)).cwiseAbs().array() + shape.radius;
      return Aabb{t.position - extent, t.position + extent};
    }
    case ShapeType::convex_hull: {
      const ConvexHull& hull = *shape.hull;
      const Vec3 center = t.apply(0.5 * (hull.local_min + hull.local_max));
      const Vec3 extent = t.rotation.cwiseAbs() * (0.5 * (hull.local_max - hull.local_min));
      return Aabb{center - extent, center + extent};
    }
    case ShapeType::none:
    case ShapeType::plane:
      break;
  }
  return Aabb{t.position, t.position};
}

void World::Impl::set_box(std::size_t i, const Aabb& box) {
  Aabb& current = aabbs_[i];
  if (current.min == box.min && current.max == box.max) return;
  current = box;
  box_passes_[i] = contact_pass_ + 1;  // update_contacts() counts the pass first
}

void World::Impl::refresh_solver_data(std::size_t i) {
  const BodyState& state = states_[i];
  transforms_[i] = Transform{state.position, state.orientation.toRotationMatrix()};
  if (is_dynamic(i)) {
    const Mat3& r = transforms_[i].rotation;
    // A sleeping body is of infinite mass to the solver (put_to_sleep()).
    if (awake_[i]) {
      inverse_masses_[i] = masses_[i].inverse_mass;
      inverse_inertia_[i] = body_to_world_tensor(r, masses_[i].inverse_inertia_body);
    } else {
      inverse_masses_[i] = 0;
      inverse_inertia_[i].setZero();
    }
    velocities_[i] = {state.linear_momentum * masses_[i].inverse_mass, inverse_inertia_[i] * state.angular_momentum};
  } else if (records_[i].motion_type == MotionType::kinematic_body) {
    velocities_[i] = {records_[i].kinematic_linear_velocity, records_[i].kinematic_angular_velocity};
  }
}

void World::Impl::set_kinematic_awake(std::size_t i) {
  BodyRecord& record = records_[i];
  awake_[i] = !record.kinematic_linear_velocity.isZero(0) || !record.kinematic_angular_velocity.isZero(0);
  if (!awake_[i]) record.reach = 0;
}

BodyId World::Impl::add_body(const BodyDesc& desc) {
  assert(id_to_dense_.size() < kInvalidBodyId);
  return add_body_with_id(desc, static_cast<BodyId>(id_to_dense_.size()));
}

BodyId World::Impl::add_body_with_id(const BodyDesc& desc, BodyId id) {
  assert(id != kInvalidBodyId && !contains(id));
  // Ids between the next one and `id` are marked unused: they are never
  // handed out, as if their bodies had been removed.
  if (id >= id_to_dense_.size()) id_to_dense_.resize(static_cast<std::size_t>(id) + 1, kNoIndex);
  const MotionType motion = desc.shape.type == ShapeType::plane ? MotionType::static_body : desc.motion_type;
  const bool dynamic = motion == MotionType::dynamic_body;
  const MassProperties& props = desc.mass_properties;
  if (dynamic) {
    assert(props.mass > 0);
    assert(props.inertia.isApprox(props.inertia.transpose()));
    assert(props.inertia.llt().info() == Eigen::Success);  // positive definite
  }
  assert(desc.shape.type != ShapeType::convex_hull || desc.shape.hull != nullptr);

  const std::uint32_t index = static_cast<std::uint32_t>(states_.size());
  id_to_dense_[id] = index;
  dense_to_id_.push_back(id);

  BodyMass mass;
  if (dynamic) {
    mass.mass = props.mass;
    mass.inverse_mass = 1.0 / props.mass;
    mass.inertia_body = props.inertia;
    mass.inverse_inertia_body = props.inertia.inverse();
  }
  masses_.push_back(mass);

  BodyState state;
  state.position = desc.position;
  state.orientation = desc.orientation.normalized();
  if (dynamic) {
    state.linear_momentum = props.mass * desc.linear_velocity;
    state.angular_momentum = body_to_world_tensor(state.orientation, props.inertia) * desc.angular_velocity;
  }
  states_.push_back(state);
  shapes_.push_back(desc.shape);

  BodyRecord record;
  record.motion_type = motion;
  record.bounding_radius = bounding_radius_of(desc.shape);
  record.sleep.rest_position = state.position;
  record.sleep.rest_orientation = state.orientation;
  if (motion == MotionType::kinematic_body) {
    record.kinematic_linear_velocity = desc.linear_velocity;
    record.kinematic_angular_velocity = desc.angular_velocity;
  }
  records_.push_back(record);
  awake_.push_back(dynamic ? 1 : 0);
  if (motion == MotionType::kinematic_body) set_kinematic_awake(index);

  transforms_.emplace_back();
  velocities_.emplace_back();
  external_.emplace_back();
  inverse_inertia_.push_back(Mat3::Zero());
  inverse_masses_.push_back(mass.inverse_mass);
  frictions_.push_back(desc.friction);
  restitutions_.push_back(desc.restitution);
  refresh_solver_data(index);
  aabbs_.push_back(shape_aabb(index));
  box_passes_.push_back(contact_pass_ + 1);
  fat_passes_.push_back(contact_pass_ + 1);
  // A flood of wake_island() or wake_beside_stirring() visits each body
  // once, and update_sleep() lists each at most once, so their scratch never
  // needs more than a slot a body: room for all of them now, growing with
  // the body arrays, keeps waking and sleeping free of allocation.
  if (island_stack_.capacity() < records_.size()) {
    island_stack_.reserve(records_.capacity());
    woken_.reserve(records_.capacity());
    sleep_parent_.reserve(records_.capacity());
    sleep_flags_.reserve(records_.capacity());
    settled_.reserve(records_.capacity());
    stir_reached_.reserve(records_.capacity());
    stir_marks_.reserve(records_.capacity());
  }
  // Contacts: address space for a few a body, reserved as bodies come and
  // written only as slots are used. Otherwise the landing of a pile, whose
  // pairs multiply within a few steps, copies the contact array and the
  // solver's rows into blocks twice the size mid-step, and maps every page
  // of them at once (on this kind of virtual machine 10 us a page: one
  // 12 ms step for 900 boxes).
  if (contacts_.capacity() < kContactSlotsPerBody * records_.size()) {
    contacts_.reserve(kContactSlotsPerBody * records_.capacity());
    links_.reserve(kContactSlotsPerBody * records_.capacity());
    beside_sleepers_.reserve(kContactSlotsPerBody * records_.capacity());
    pairs_.reserve(kContactSlotsPerBody * records_.capacity());
    solver_.reserve(kTouchingContactsPerBody * records_.capacity());
  }

  if (desc.shape.type == ShapeType::plane) {
    planes_.push_back(index);
    // Bodies asleep near the new plane would never meet it.
    for (std::size_t i = 0; i < records_.size(); ++i) wake_island(static_cast<std::uint32_t>(i));
  } else if (desc.shape.type != ShapeType::none) {
    // Pair with everything already overlapping, so that sleeping or
    // resting neighbours (whose boxes do not move) meet the new body.
    DynamicTree& tree = motion == MotionType::static_body ? static_tree_ : movable_tree_;
    const Aabb fat = motion == MotionType::static_body ? aabbs_[index] : aabbs_[index].expanded(settings_.aabb_margin);
    records_[index].proxy = tree.create_proxy(fat, index);
    auto visit = [&](std::uint32_t other) {
      if (other != index && can_collide(index, other)) create_contact(index, other);
    };
    movable_tree_.query(fat, visit);
    if (dynamic) static_tree_.query(fat, visit);
    if (!dynamic) wake_overlapping(fat);
  }
  return id;
}

bool World::Impl::remove_body(BodyId id) {
  if (!contains(id)) return false;
  const std::uint32_t index = id_to_dense_[id];
  const std::uint32_t last = static_cast<std::uint32_t>(states_.size() - 1);

  // Its joints go first (waking what they held).
  if (id < body_joints_.size()) {
    while (!body_joints_[id].empty()) remove_joint(body_joints_[id].back());
  }
  destroy_contacts_of(index, true);
  BodyRecord& record = records_[index];
  if (record.proxy != DynamicTree::kNull) {
    (record.motion_type == MotionType::static_body ? static_tree_ : movable_tree_).destroy_proxy(record.proxy);
  }
  const auto plane = std::find(planes_.begin(), planes_.end(), index);
  if (plane != planes_.end()) planes_.erase(plane);

  if (index != last) relabel_body(last, index);
  swap_remove(states_, index);
  swap_remove(masses_, index);
  swap_remove(shapes_, index);
  swap_remove(dense_to_id_, index);
  swap_remove(records_, index);
  swap_remove(awake_, index);
  swap_remove(transforms_, index);
  swap_remove(velocities_, index);
  swap_remove(external_, index);
  swap_remove(inverse_inertia_, index);
  swap_remove(inverse_masses_, index);
  swap_remove(frictions_, index);
  swap_remove(restitutions_, index);
  swap_remove(aabbs_, index);
  swap_remove(box_passes_, index);
  swap_remove(fat_passes_, index);
  if (index != last) id_to_dense_[dense_to_id_[index]] = index;
  id_to_dense_[id] = kNoIndex;
  return true;
}

bool World::Impl::contains(BodyId id) const { return id < id_to_dense_.size() && id_to_dense_[id] != kNoIndex; }

std::size_t World::Impl::body_count() const { return states_.size(); }

BodyId World::Impl::body_id_at(std::size_t index) const {
  assert(index < dense_to_id_.size());
  return dense_to_id_[index];
}

std::size_t World::Impl::dense_index(BodyId id) const {
  assert(contains(id));
  return id_to_dense_[id];
}

const Vec3& World::Impl::position(BodyId id) const { return states_[dense_index(id)].position; }

const Quat& World::Impl::orientation(BodyId id) const { return states_[dense_index(id)].orientation; }

Vec3 World::Impl::linear_velocity(BodyId id) const { return linear_velocity_at(dense_index(id)); }

Vec3 World::Impl::angular_velocity(BodyId id) const { return angular_velocity_at(dense_index(id)); }

Vec3 World::Impl::linear_velocity_at(std::size_t i) const {
  if (records_[i].motion_type == MotionType::kinematic_body) return records_[i].kinematic_linear_velocity;
  return states_[i].linear_momentum * inverse_masses_[i];  // 1/M, kept flat beside the states
}

Vec3 World::Impl::angular_velocity_at(std::size_t i) const {
  if (records_[i].motion_type == MotionType::kinematic_body) return records_[i].kinematic_angular_velocity;
  // Sleeping and static bodies have L = 0: no tensor to build (a resting
  // world is read every tick for its frames).
  const Vec3& l = states_[i].angular_momentum;
  if (l.x() == 0 && l.y() == 0 && l.z() == 0) return Vec3::Zero();
  // w = R I_body^-1 R^T L (Baraff, "Angular Momentum").
  return body_to_world_tensor(states_[i].orientation, masses_[i].inverse_inertia_body) * l;
}

void World::Impl::copy_poses(BodyId* ids, double* positions, double* orientations, double* linear_velocities,
                             double* angular_velocities) const {
  for (std::size_t i = 0; i < states_.size(); ++i) {
    const BodyState& state = states_[i];
    ids[i] = dense_to_id_[i];
    std::copy(state.position.data(), state.position.data() + 3, positions + 3 * i);
    double* o = orientations + 4 * i;
    o[0] = state.orientation.w();
    o[1] = state.orientation.x();
    o[2] = state.orientation.y();
    o[3] = state.orientation.z();
    const Vec3 v = linear_velocity_at(i);
    const Vec3 w = angular_velocity_at(i);
    std::copy(v.data(), v.data() + 3, linear_velocities + 3 * i);
    std::copy(w.data(), w.data() + 3, angular_velocities + 3 * i);
  }
}

const Vec3& World::Impl::linear_momentum(BodyId id) const { return states_[dense_index(id)].linear_momentum; }

const Vec3& World::Impl::angular_momentum(BodyId id) const { return states_[dense_index(id)].angular_momentum; }

double World::Impl::mass(BodyId id) const { return masses_[dense_index(id)].mass; }

Mat3 World::Impl::inertia_world(BodyId id) const {
  const std::size_t i = dense_index(id);
  return body_to_world_tensor(states_[i].orientation, masses_[i].inertia_body);
}

const Mat3& World::Impl::inertia_body(BodyId id) const { return masses_[dense_index(id)].inertia_body; }

const Shape& World::Impl::shape(BodyId id) const { return shapes_[dense_index(id)]; }

double World::Impl::kinetic_energy(BodyId id) const {
  // 1/2 (P.v + L.w) = 1/2 M v.v + 1/2 w^T I w.
  return 0.5 * (linear_momentum(id).dot(linear_velocity(id)) + angular_momentum(id).dot(angular_velocity(id)));
}

MotionType World::Impl::motion_type(BodyId id) const { return records_[dense_index(id)].motion_type; }

double World::Impl::friction(BodyId id) const { return frictions_[dense_index(id)]; }

double World::Impl::restitution(BodyId id) const { return restitutions_[dense_index(id)]; }

void World::Impl::set_friction(BodyId id, double friction) { frictions_[dense_index(id)] = friction; }

void World::Impl::set_restitution(BodyId id, double restitution) { restitutions_[dense_index(id)] = restitution; }

void World::Impl::set_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_velocity,
                            const Vec3& angular_velocity) {
  const std::uint32_t i = static_cast<std::uint32_t>(dense_index(id));
  BodyState& state = states_[i];
  BodyRecord& record = records_[i];
  const Aabb old_box = aabbs_[i];
  state.position = position;
  state.orientation = orientation.normalized();
  switch (record.motion_type) {
    case MotionType::dynamic_body:
      state.linear_momentum = masses_[i].mass * linear_velocity;
      state.angular_momentum = body_to_world_tensor(state.orientation, masses_[i].inertia_body) * angular_velocity;
      wake_island(i);
      break;
    case MotionType::kinematic_body:
      record.kinematic_linear_velocity = linear_velocity;
      record.kinematic_angular_velocity = angular_velocity;
      set_kinematic_awake(i);
      break;
    case MotionType::static_body:
      break;
  }
  refresh_solver_data(i);
  set_box(i, shape_aabb(i));

  if (shapes_[i].type == ShapeType::plane) {
    for (std::size_t k = 0; k < records_.size(); ++k) wake_island(static_cast<std::uint32_t>(k));
    return;
  }
  if (record.proxy == DynamicTree::kNull) return;
  // A teleport: replace the fat box now and pair with what is there.
  const bool is_static = record.motion_type == MotionType::static_body;
  DynamicTree& tree = is_static ? static_tree_ : movable_tree_;
  const Aabb fat = is_static ? aabbs_[i] : aabbs_[i].expanded(settings_.aabb_margin);
  tree.move_proxy(record.proxy, fat);
  fat_passes_[i] = contact_pass_ + 1;
  auto visit = [&](std::uint32_t other) {
    if (other != i && can_collide(i, other) && !has_contact(i, other)) create_contact(i, other);
  };
  movable_tree_.query(fat, visit);
  if (is_dynamic(i)) static_tree_.query(fat, visit);
  if (!is_dynamic(i)) {
    // Whatever rested on it or lies where it went must notice.
    wake_overlapping(old_box);
    wake_overlapping(fat);
  }
}

void World::Impl::add_force(BodyId id, const Vec3& force) {
  const std::uint32_t i = static_cast<std::uint32_t>(dense_index(id));
  if (!is_dynamic(i)) return;
  wake_island(i);
  states_[i].force += force;
}

void World::Impl::add_force_at_point(BodyId id, const Vec3& force, const Vec3& world_point) {
  const std::uint32_t i = static_cast<std::uint32_t>(dense_index(id));
  if (!is_dynamic(i)) return;
  wake_island(i);
  BodyState& state = states_[i];
  state.force += force;
  // tau = (r - x) x F (Baraff, "Force and Torque").
  state.torque += (world_point - state.position).cross(force);
}

void World::Impl::add_torque(BodyId id, const Vec3& torque) {
  const std::uint32_t i = static_cast<std::uint32_t>(dense_index(id));
  if (!is_dynamic(i)) return;
  wake_island(i);
  states_[i].torque += torque;
}

const Vec3& World::Impl::accumulated_force(BodyId id) const { return states_[dense_index(id)].force; }

const Vec3& World::Impl::accumulated_torque(BodyId id) const { return states_[dense_index(id)].torque; }

void World::Impl::apply_impulse(BodyId id, const Vec3& impulse) {
  const std::uint32_t i = static_cast<std::uint32_t>(dense_index(id));
  if (!is_dynamic(i)) return;
  wake_island(i);
  states_[i].linear_momentum += impulse;
}

void World::Impl::apply_impulse_at_point(BodyId id, const Vec3& impulse, const Vec3& world_point) {
  const std::uint32_t i = static_cast<std::uint32_t>(dense_index(id));
  if (!is_dynamic(i)) return;
  wake_island(i);
  BodyState& state = states_[i];
  state.linear_momentum += impulse;
  // The angular impulse about the centre of mass, (r - x) x J.
  state.angular_momentum += (world_point - state.position).cross(impulse);
}

void World::Impl::set_next_body_id(BodyId next) {
  assert(next >= id_to_dense_.size() && next != kInvalidBodyId);
  id_to_dense_.resize(next, kNoIndex);
}

void World::Impl::restore_state(BodyId id, const Vec3& position, const Quat& orientation, const Vec3& linear_momentum,
                                const Vec3& angular_momentum, bool awake, const SleepProgress& sleep) {
  const std::uint32_t i = static_cast<std::uint32_t>(dense_index(id));
  BodyState& state = states_[i];
  // Taken as given, not re-normalised: normalising a unit quaternion again
  // can change its last bits.
  state.position = position;
  state.orientation = orientation;
  if (is_dynamic(i)) {
    state.linear_momentum = linear_momentum;
    state.angular_momentum = angular_momentum;
    if (awake) {
      wake_island(i);
    } else {
      put_to_sleep(i);
    }
    records_[i].sleep = sleep;
  }
  refresh_solver_data(i);
  set_box(i, shape_aabb(i));
}

SleepProgress World::Impl::sleep_progress(BodyId id) const { return records_[dense_index(id)].sleep; }

void World::Impl::wake(BodyId id) { wake_island(static_cast<std::uint32_t>(dense_index(id))); }

bool World::Impl::is_awake(BodyId id) const { return awake_[dense_index(id)] != 0; }

std::size_t World::Impl::awake_body_count() const {
  std::size_t n = 0;
  for (const std::uint8_t awake : awake_) n += awake;
  return n;
}

std::size_t World::Impl::sleeping_body_count() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < records_.size(); ++i) n += is_dynamic(i) && !awake_[i] ? 1u : 0u;
  return n;
}

std::size_t World::Impl::contact_count() const {
  std::size_t n = 0;
  for (const ContactLink& link : links_) n += link.alive && link.touching ? 1 : 0;
  return n;
}

std::size_t World::Impl::contact_point_count() const {
  std::size_t n = 0;
  for (std::size_t k = 0; k < contacts_.size(); ++k) {
    n += links_[k].alive ? static_cast<std::size_t>(contacts_[k].manifold.point_count) : 0;
  }
  return n;
}

double World::Impl::max_penetration() const {
  double deepest = 0;
  for (std::size_t slot = 0; slot < contacts_.size(); ++slot) {
    if (!links_[slot].alive) continue;
    const Contact& c = contacts_[slot];
    for (int k = 0; k < c.manifold.point_count; ++k) deepest = std::max(deepest, -c.manifold.points[k].separation);
  }
  return deepest;
}

}  // namespace tumble::physics
