// World: joints (joint.h). Their bookkeeping, which bodies they keep from
// colliding, the joints the solver takes each step, breaking, and the
// state a joint reports. The rows are solved in joint_solver.cpp.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "world_impl.h"

namespace tumble::physics {
namespace {

bool finite(const Vec3& v) { return v.allFinite(); }

// A basis given as a quaternion must be a rotation.
bool unit(const Quat& q) { return q.coeffs().allFinite() && std::abs(q.squaredNorm() - 1.0) < 1e-9; }

const char* motor_error(JointType type, const JointMotor& motor) {
  if (motor.mode == JointMotor::Mode::off) return nullptr;
  if (type != JointType::hinge && type != JointType::slider) return "motor: only a hinge or a slider has a motor";
  if (!std::isfinite(motor.target)) return "motor: target not finite";
  if (!(motor.max_force >= 0) || !std::isfinite(motor.max_force)) return "motor: max force not a finite number >= 0";
  if (motor.mode == JointMotor::Mode::position) {
    if (!(motor.hertz > 0) || !std::isfinite(motor.hertz)) return "motor: hertz not a finite number > 0";
    if (!(motor.damping_ratio >= 0) || !std::isfinite(motor.damping_ratio)) {
      return "motor: damping_ratio not a finite number >= 0";
    }
  }
  return nullptr;
}

}  // namespace

const Joint& World::Impl::joint(JointId id) const {
  assert(contains_joint(id));
  return joints_[joint_id_to_dense_[id]];
}

const char* World::Impl::joint_desc_error(const JointDesc& desc) const {
  auto known = [&](BodyId body) { return body == kWorldBodyId || contains(body); };
  if (!known(desc.body_a)) return "body_a: unknown body";
  if (!known(desc.body_b)) return "body_b: unknown body";
  if (desc.body_a == desc.body_b) return "body_b: the same body as body_a";
  auto dynamic = [&](BodyId body) { return body != kWorldBodyId && motion_type(body) == MotionType::dynamic_body; };
  if (!dynamic(desc.body_a) && !dynamic(desc.body_b)) return "body_b: neither body is dynamic";
  if (!finite(desc.local_anchor_a) || !finite(desc.local_anchor_b)) return "anchor: not finite";
  if (!unit(desc.local_basis_a) || !unit(desc.local_basis_b)) return "axis: not a rotation";
  const bool axial = desc.type == JointType::hinge || desc.type == JointType::slider;
  if (desc.limits_enabled) {
    if (!axial) return "limits: only a hinge or a slider has limits";
    if (!std::isfinite(desc.lower) || !std::isfinite(desc.upper)) return "limits: not finite";
    if (desc.lower > desc.upper) return "limits: lower above upper";
    if (desc.type == JointType::hinge && (desc.lower < -std::numbers::pi || desc.upper > std::numbers::pi)) {
      return "limits: a hinge's limits lie within [-pi, pi]";
    }
  }
  if (!(std::isinf(desc.cone_limit) && desc.cone_limit > 0)) {
    if (desc.type != JointType::ball) return "cone_limit: only a ball joint has a cone";
    if (!(desc.cone_limit > 0 && desc.cone_limit <= std::numbers::pi)) return "cone_limit: not within (0, pi]";
  }
  if (desc.type == JointType::distance) {
    if (!std::isfinite(desc.min_length) || !std::isfinite(desc.length) || !std::isfinite(desc.max_length)) {
      return "length: not finite";
    }
    if (desc.min_length < 0) return "min_length: negative";
    if (desc.min_length > desc.max_length) return "max_length: below min_length";
    if (desc.length < desc.min_length || desc.length > desc.max_length) {
      return "length: outside [min_length, max_length]";
    }
    if (!(desc.spring_hertz >= 0) || !std::isfinite(desc.spring_hertz)) return "spring: hertz not a finite number >= 0";
    if (!(desc.spring_damping_ratio >= 0) || !std::isfinite(desc.spring_damping_ratio)) {
      return "spring: damping_ratio not a finite number >= 0";
    }
  }
  if (const char* error = motor_error(desc.type, desc.motor)) return error;
  if (!(desc.friction >= 0) || !std::isfinite(desc.friction)) return "friction: not a finite number >= 0";
  if (desc.friction > 0 && !(axial || desc.type == JointType::ball)) {
    return "friction: only a ball joint, a hinge or a slider has friction";
  }
  if (!(desc.break_force > 0)) return "break_force: not > 0";
  if (!(desc.break_torque > 0)) return "break_torque: not > 0";
  return nullptr;
}

void World::Impl::set_joint_frames(JointDesc& desc, const Vec3& anchor_a, const Vec3& anchor_b,
                                   const Vec3& axis) const {
  assert(axis.squaredNorm() > 0);
  // The world basis both frames start as: x along the axis, y across it
  // (chosen from the coordinate axis least aligned with it), z = x cross y.
  const Vec3 x = axis.normalized();
  const Vec3 helper = std::abs(x.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 y = (helper - helper.dot(x) * x).normalized();
  Mat3 basis;
  basis.col(0) = x;
  basis.col(1) = y;
  basis.col(2) = x.cross(y);
  const Quat world_basis(basis);
  auto side = [&](BodyId body, const Vec3& anchor, Vec3& local_anchor, Quat& local_basis) {
    if (body == kWorldBodyId) {
      local_anchor = anchor;
      local_basis = world_basis;
      return;
    }
    const Quat q = orientation(body);
    local_anchor = q.conjugate() * (anchor - position(body));
    local_basis = (q.conjugate() * world_basis).normalized();
  };
  side(desc.body_a, anchor_a, desc.local_anchor_a, desc.local_basis_a);
  side(desc.body_b, anchor_b, desc.local_anchor_b, desc.local_basis_b);
}

JointId World::Impl::add_joint(const JointDesc& desc) {
  const JointId id = add_joint_with_id(desc, next_joint_id());
  for (BodyId body : {desc.body_a, desc.body_b}) {
    if (body != kWorldBodyId) wake_island(id_to_dense_[body]);
  }
  return id;
}

JointId World::Impl::add_joint_with_id(const JointDesc& desc, JointId id) {
  assert(joint_desc_error(desc) == nullptr);
  assert(id != kInvalidJointId && !contains_joint(id));
  if (id >= joint_id_to_dense_.size()) joint_id_to_dense_.resize(static_cast<std::size_t>(id) + 1, kNoIndex);
  joint_id_to_dense_[id] = static_cast<std::uint32_t>(joints_.size());
  Joint joint;
  joint.id = id;
  joint.desc = desc;
  joints_.push_back(joint);
  // The step's scratch grows with the joints, not during a step.
  joint_edges_.reserve(joints_.capacity());
  broken_.reserve(joints_.capacity());

  for (BodyId body : {desc.body_a, desc.body_b}) {
    if (body == kWorldBodyId) continue;
    if (body >= body_joints_.size()) body_joints_.resize(static_cast<std::size_t>(body) + 1);
    body_joints_[body].push_back(id);
  }
  // Jointed bodies stop colliding: a contact they have now goes.
  if (!desc.collide_connected && desc.body_a != kWorldBodyId && desc.body_b != kWorldBodyId) {
    const std::uint32_t a = id_to_dense_[desc.body_a], b = id_to_dense_[desc.body_b];
    const std::uint32_t slot = find_contact(a, b);
    if (slot != kNoIndex) destroy_contact(slot);
  }
  return id;
}

void World::Impl::set_next_joint_id(JointId next) {
  if (next > joint_id_to_dense_.size()) joint_id_to_dense_.resize(next, kNoIndex);
}

bool World::Impl::remove_joint(JointId id) {
  if (!contains_joint(id)) return false;
  const std::uint32_t index = joint_id_to_dense_[id];
  const JointDesc desc = joints_[index].desc;
  for (BodyId body : {desc.body_a, desc.body_b}) {
    if (body == kWorldBodyId) continue;
    std::vector<JointId>& list = body_joints_[body];
    list.erase(std::find(list.begin(), list.end(), id));
  }
  if (index + 1 != joints_.size()) {
    joints_[index] = joints_.back();
    joint_id_to_dense_[joints_[index].id] = index;
  }
  joints_.pop_back();
  joint_id_to_dense_[id] = kNoIndex;

  const std::uint32_t a = joint_body(desc.body_a), b = joint_body(desc.body_b);
  if (a != kNoJointBody) wake_island(a);
  if (b != kNoJointBody) wake_island(b);
  if (!desc.collide_connected && a != kNoJointBody && b != kNoJointBody) pair_if_overlapping(a, b);
  return true;
}

void World::Impl::pair_if_overlapping(std::uint32_t a, std::uint32_t b) {
  if (!can_collide(a, b) || has_contact(a, b)) return;
  // A plane pairs with what may reach it; the narrowphase drops the pair
  // when it does not.
  if (shapes_[a].type == ShapeType::plane || shapes_[b].type == ShapeType::plane) {
    create_contact(a, b);
    return;
  }
  if (records_[a].proxy == DynamicTree::kNull || records_[b].proxy == DynamicTree::kNull) return;
  if (fat_box(a).overlaps(fat_box(b))) create_contact(a, b);
}

bool World::Impl::jointed(std::size_t a, std::size_t b) const {
  const BodyId id_a = dense_to_id_[a], id_b = dense_to_id_[b];
  if (id_a >= body_joints_.size() || id_b >= body_joints_.size()) return false;
  const std::vector<JointId>& list_a = body_joints_[id_a];
  const std::vector<JointId>& list_b = body_joints_[id_b];
  if (list_a.empty() || list_b.empty()) return false;
  const bool a_shorter = list_a.size() <= list_b.size();
  const BodyId other = a_shorter ? id_b : id_a;
  for (JointId id : a_shorter ? list_a : list_b) {
    const JointDesc& desc = joints_[joint_id_to_dense_[id]].desc;
    if (!desc.collide_connected && (desc.body_a == other || desc.body_b == other)) return true;
  }
  return false;
}

std::span<const JointId> World::Impl::body_joints(BodyId id) const {
  if (id >= body_joints_.size()) return {};
  return body_joints_[id];
}

void World::Impl::set_joint_motor(JointId id, const JointMotor& motor) {
  Joint& j = joints_[joint_id_to_dense_[id]];
  assert(motor_error(j.desc.type, motor) == nullptr);
  j.desc.motor = motor;
  if (motor.mode == JointMotor::Mode::off) j.impulses.motor = 0;
  const std::uint32_t a = joint_body(j.desc.body_a), b = joint_body(j.desc.body_b);
  if (a != kNoJointBody) wake_island(a);
  if (b != kNoJointBody) wake_island(b);
}

void World::Impl::restore_joint_impulses(JointId id, const JointImpulses& impulses) {
  joints_[joint_id_to_dense_[id]].impulses = impulses;
}

void World::Impl::collect_joint_edges() {
  joint_edges_.clear();
  auto asleep = [&](std::uint32_t i) { return i != kNoJointBody && is_dynamic(i) && !awake_[i]; };
  auto moving = [&](std::uint32_t i) { return i != kNoJointBody && awake_[i] != 0; };
  for (std::uint32_t k = 0; k < joints_.size(); ++k) {
    const JointDesc& desc = joints_[k].desc;
    const std::uint32_t a = joint_body(desc.body_a), b = joint_body(desc.body_b);
    if (!moving(a) && !moving(b)) continue;
    // A body jointed to one that moves moves with it (its island wakes as
    // a contact's would).
    if (asleep(a)) wake_island(a);
    if (asleep(b)) wake_island(b);
    const bool dynamic_side = (a != kNoJointBody && is_dynamic(a)) || (b != kNoJointBody && is_dynamic(b));
    if (dynamic_side) joint_edges_.push_back({a, b, k});
  }
}

void World::Impl::break_joints() {
  for (const Joint& j : joints_) {
    if (j.force.norm() > j.desc.break_force || j.torque.norm() > j.desc.break_torque) broken_.push_back(j.id);
  }
  for (JointId id : broken_) remove_joint(id);
}

JointState World::Impl::joint_state(JointId id) const {
  const Joint& j = joint(id);
  const JointDesc& desc = j.desc;
  // Each side's pose and velocity now; the world's is the identity at rest.
  struct Side {
    Vec3 position = Vec3::Zero();
    Quat orientation = Quat::Identity();
    Vec3 linear = Vec3::Zero();
    Vec3 angular = Vec3::Zero();
  };
  auto side = [&](BodyId body) {
    Side s;
    if (body == kWorldBodyId) return s;
    const std::size_t i = id_to_dense_[body];
    s.position = states_[i].position;
    s.orientation = states_[i].orientation;
    s.linear = linear_velocity_at(i);
    s.angular = angular_velocity_at(i);
    return s;
  };
  const Side a = side(desc.body_a), b = side(desc.body_b);
  const Vec3 r_a = a.orientation * desc.local_anchor_a, r_b = b.orientation * desc.local_anchor_b;
  const Mat3 frame_a = (a.orientation * desc.local_basis_a).toRotationMatrix();
  const Mat3 frame_b = (b.orientation * desc.local_basis_b).toRotationMatrix();
  const Vec3 d = (b.position + r_b) - (a.position + r_a);
  // Velocity of anchor B relative to anchor A.
  const Vec3 dv = b.linear + b.angular.cross(r_b) - a.linear - a.angular.cross(r_a);
  const Vec3 dw = b.angular - a.angular;

  JointState state;
  switch (desc.type) {
    case JointType::hinge: {
      const Vec3 ya = frame_a.col(1), yb = frame_b.col(1);
      state.position = std::atan2(ya.cross(yb).dot(frame_a.col(0)), ya.dot(yb));
      state.speed = frame_a.col(0).dot(dw);
      break;
    }
    case JointType::slider:
      // d/dt (d.a) with a turning with body A.
      state.position = d.dot(frame_a.col(0));
      state.speed = dv.dot(frame_a.col(0)) + d.dot(a.angular.cross(frame_a.col(0)));
      break;
    case JointType::distance:
      state.position = d.norm();
      state.speed = state.position > 0 ? dv.dot(d) / state.position : 0.0;
      break;
    case JointType::ball: {
      const Vec3 n = frame_a.col(0).cross(frame_b.col(0));
      state.position = std::atan2(n.norm(), frame_a.col(0).dot(frame_b.col(0)));
      state.speed = n.norm() > 1e-9 ? (n / n.norm()).dot(dw) : 0.0;
      break;
    }
    case JointType::fixed:
      break;
  }
  state.force = j.force;
  state.torque = j.torque;
  state.motor_impulse = j.motor_impulse;
  return state;
}

}  // namespace tumble::physics
