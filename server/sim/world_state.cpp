#include "sim/world_state.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sim/body_limits.h"
#include "sim/body_spec.h"
#include "sim/joint_spec.h"
#include "sim/log.h"
#include "sim/log_text.h"
#include "sim/proto_math.h"
#include "sim/string_limits.h"

namespace tumble::sim {
namespace {

bool finite(const tumble::v1::Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// The spec of `saved` as this server accepts it: the saved one, or, when its
// name breaks a limit of string_limits.h (a file written before there were
// any), a copy in `renamed` without the name, with a warning in the log. The
// body itself is kept: refusing the file would lose the whole world.
const tumble::v1::BodySpec& allowed_name(const tumble::v1::SavedBody& saved, const std::string& where,
                                         tumble::v1::BodySpec* renamed) {
  const Status refused = check_body_name(saved.spec().name(), where + ".spec.name");
  if (refused.ok()) return saved.spec();
  sim_log().warn("{}; body {} is loaded without a name", log_text(refused.message(), kLogMessageBytes), saved.id());
  *renamed = saved.spec();
  renamed->clear_name();
  return *renamed;
}

bool finite(const tumble::v1::Quat& q) {
  return std::isfinite(q.w()) && std::isfinite(q.x()) && std::isfinite(q.y()) && std::isfinite(q.z());
}

bool sleep_progress_finite(const physics::SleepProgress& sleep) {
  return std::isfinite(sleep.time) && sleep.rest_position.allFinite() && sleep.rest_orientation.coeffs().allFinite() &&
         std::isfinite(sleep.last_speed) && std::isfinite(sleep.rise_start_speed);
}

// A saved joint's frame rotation: finite and of unit length (it is put back
// as saved, so only a damaged file fails this).
bool unit(const tumble::v1::Quat& q) {
  return finite(q) && std::abs(std::sqrt(q.w() * q.w() + q.x() * q.x() + q.y() * q.y() + q.z() * q.z()) - 1.0) <= 1e-6;
}

void save_joint(const physics::World& world, const JointDirectory& joints, physics::JointId id,
                tumble::v1::SavedJoint* saved) {
  const physics::JointDesc& desc = world.joint_desc(id);
  saved->set_id(id);
  if (const JointEntry* entry = joints.find(id)) saved->set_name(entry->name);
  saved->set_type(wire_joint_type(desc.type));
  saved->set_body_a(desc.body_a);
  saved->set_body_b(desc.body_b);
  set_vec3(desc.local_anchor_a, saved->mutable_local_anchor_a());
  set_vec3(desc.local_anchor_b, saved->mutable_local_anchor_b());
  set_quat(desc.local_basis_a, saved->mutable_local_basis_a());
  set_quat(desc.local_basis_b, saved->mutable_local_basis_b());
  saved->set_limits_enabled(desc.limits_enabled);
  saved->set_lower(desc.lower);
  saved->set_upper(desc.upper);
  saved->set_cone_limit(desc.cone_limit);
  saved->set_length(desc.length);
  saved->set_min_length(desc.min_length);
  saved->set_max_length(desc.max_length);
  saved->set_spring_hertz(desc.spring_hertz);
  saved->set_spring_damping_ratio(desc.spring_damping_ratio);
  saved->set_motor_mode(static_cast<std::uint32_t>(desc.motor.mode));
  saved->set_motor_target(desc.motor.target);
  saved->set_motor_max_force(desc.motor.max_force);
  saved->set_motor_hertz(desc.motor.hertz);
  saved->set_motor_damping_ratio(desc.motor.damping_ratio);
  saved->set_break_force(desc.break_force);
  saved->set_break_torque(desc.break_torque);
  saved->set_collide_connected(desc.collide_connected);
  saved->set_friction(desc.friction);
  const physics::JointImpulses& impulses = world.joint_impulses(id);
  set_vec3(impulses.linear, saved->mutable_linear_impulse());
  set_vec3(impulses.angular, saved->mutable_angular_impulse());
  saved->set_lower_impulse(impulses.lower);
  saved->set_upper_impulse(impulses.upper);
  saved->set_motor_impulse(impulses.motor);
  saved->set_spring_impulse(impulses.spring);
  set_vec3(impulses.friction, saved->mutable_friction_impulse());
}

// The saved joint as the engine's desc and impulses, checked as far as a
// file needs beyond World::joint_desc_error: a known type and motor mode,
// unit frame rotations, finite impulses. `where` names it, e.g. "joints[1]".
Status joint_from_saved(const tumble::v1::SavedJoint& saved, const std::string& where, physics::JointDesc* desc,
                        physics::JointImpulses* impulses) {
  if (!physics_joint_type(saved.type(), &desc->type)) {
    return Status::error(where + ".type: " + std::to_string(saved.type()) + " is no type of joint");
  }
  if (saved.motor_mode() > static_cast<std::uint32_t>(physics::JointMotor::Mode::position)) {
    return Status::error(where + ".motor_mode: " + std::to_string(saved.motor_mode()) + " is no motor mode");
  }
  if (!finite(saved.local_anchor_a()) || !finite(saved.local_anchor_b())) {
    return Status::error(where + ": its anchors must be finite");
  }
  if (!unit(saved.local_basis_a()) || !unit(saved.local_basis_b())) {
    return Status::error(where + ": its frames' rotations must be unit quaternions");
  }
  desc->body_a = saved.body_a();
  desc->body_b = saved.body_b();
  desc->local_anchor_a = to_vec3(saved.local_anchor_a());
  desc->local_anchor_b = to_vec3(saved.local_anchor_b());
  desc->local_basis_a = to_quat(saved.local_basis_a());
  desc->local_basis_b = to_quat(saved.local_basis_b());
  desc->limits_enabled = saved.limits_enabled();
  desc->lower = saved.lower();
  desc->upper = saved.upper();
  desc->cone_limit = saved.cone_limit();
  desc->length = saved.length();
  desc->min_length = saved.min_length();
  desc->max_length = saved.max_length();
  desc->spring_hertz = saved.spring_hertz();
  desc->spring_damping_ratio = saved.spring_damping_ratio();
  desc->motor.mode = static_cast<physics::JointMotor::Mode>(saved.motor_mode());
  desc->motor.target = saved.motor_target();
  desc->motor.max_force = saved.motor_max_force();
  desc->motor.hertz = saved.motor_hertz();
  desc->motor.damping_ratio = saved.motor_damping_ratio();
  desc->break_force = saved.break_force();
  desc->break_torque = saved.break_torque();
  desc->collide_connected = saved.collide_connected();
  desc->friction = saved.friction();
  const bool finite_impulses = finite(saved.linear_impulse()) && finite(saved.angular_impulse()) &&
                               finite(saved.friction_impulse()) && std::isfinite(saved.lower_impulse()) &&
                               std::isfinite(saved.upper_impulse()) && std::isfinite(saved.motor_impulse()) &&
                               std::isfinite(saved.spring_impulse());
  if (!finite_impulses) return Status::error(where + ": its impulses must be finite");
  impulses->linear = to_vec3(saved.linear_impulse());
  impulses->angular = to_vec3(saved.angular_impulse());
  impulses->lower = saved.lower_impulse();
  impulses->upper = saved.upper_impulse();
  impulses->motor = saved.motor_impulse();
  impulses->spring = saved.spring_impulse();
  impulses->friction = to_vec3(saved.friction_impulse());
  return {};
}

bool within_magnitude(const physics::Vec3& v) {
  return std::abs(v.x()) <= kMaxMagnitude && std::abs(v.y()) <= kMaxMagnitude && std::abs(v.z()) <= kMaxMagnitude;
}

// Whether restore_world would take the body's state back: the pose and
// velocities its spec checks (body_spec.h), and finite momenta and sleep
// time. Mass and shape were checked when the body was made and never change.
bool restorable(const physics::World& world, physics::BodyId id) {
  const physics::Quat& q = world.orientation(id);
  return within_magnitude(world.position(id)) && within_magnitude(world.linear_velocity(id)) &&
         within_magnitude(world.angular_velocity(id)) && q.coeffs().allFinite() && std::abs(q.norm() - 1.0) <= 1e-3 &&
         world.linear_momentum(id).allFinite() && world.angular_momentum(id).allFinite() &&
         sleep_progress_finite(world.sleep_progress(id));
}

}  // namespace

void body_spec_now(const physics::World& world, const BodyDirectory& directory, physics::BodyId id,
                   tumble::v1::BodySpec* out) {
  tumble::v1::BodySpec& spec = *out;
  if (const BodyEntry* entry = directory.find(id)) {
    spec.set_name(entry->name);
    *spec.mutable_shape() = entry->shape;
    spec.set_mass(entry->mass);
  }
  spec.set_motion(wire_motion(world.motion_type(id)));
  spec.set_friction(world.friction(id));
  spec.set_restitution(world.restitution(id));
  set_vec3(world.position(id), spec.mutable_position());
  set_quat(world.orientation(id), spec.mutable_orientation());
  set_vec3(world.linear_velocity(id), spec.mutable_linear_velocity());
  set_vec3(world.angular_velocity(id), spec.mutable_angular_velocity());
}

std::size_t capture_world(const physics::World& world, const BodyDirectory& directory, const JointDirectory& joints,
                          const BodyLoads& loads, tumble::v1::WorldState* state) {
  state->set_format_version(kWorldStateFormat);
  set_vec3(world.gravity(), state->mutable_gravity());
  state->set_next_body_id(world.next_body_id());
  state->clear_bodies();
  state->mutable_bodies()->Reserve(static_cast<int>(world.body_count()));
  std::vector<physics::BodyId> left_out;
  for (std::size_t i = 0; i < world.body_count(); ++i) {
    const physics::BodyId id = world.body_id_at(i);
    if (!restorable(world, id)) {
      left_out.push_back(id);
      continue;
    }
    tumble::v1::SavedBody* saved = state->add_bodies();
    saved->set_id(id);
    body_spec_now(world, directory, id, saved->mutable_spec());
    set_vec3(world.linear_momentum(id), saved->mutable_linear_momentum());
    set_vec3(world.angular_momentum(id), saved->mutable_angular_momentum());
    saved->set_asleep(world.motion_type(id) == physics::MotionType::dynamic_body && !world.is_awake(id));
    const physics::SleepProgress sleep = world.sleep_progress(id);
    saved->set_sleep_time(sleep.time);
    set_vec3(sleep.rest_position, saved->mutable_rest_position());
    set_quat(sleep.rest_orientation, saved->mutable_rest_orientation());
    saved->set_last_speed(sleep.last_speed);
    saved->set_rise_start_speed(sleep.rise_start_speed);
    saved->set_rising_steps(sleep.rising_steps);
  }
  state->clear_loads();
  for (const BodyLoad& load : loads.loads()) {
    if (std::find(left_out.begin(), left_out.end(), load.body) != left_out.end()) continue;
    tumble::v1::SavedLoad* saved = state->add_loads();
    saved->set_body(load.body);
    set_vec3(load.force, saved->mutable_force());
    set_vec3(load.local_point, saved->mutable_local_point());
    set_vec3(load.torque, saved->mutable_torque());
    saved->set_ticks_left(load.ticks_left);
  }
  state->set_next_joint_id(world.next_joint_id());
  state->clear_joints();
  const auto is_left_out = [&](physics::BodyId id) {
    return std::find(left_out.begin(), left_out.end(), id) != left_out.end();
  };
  for (std::size_t i = 0; i < world.joint_count(); ++i) {
    const physics::JointId id = world.joint_id_at(i);
    const physics::JointDesc& desc = world.joint_desc(id);
    if (is_left_out(desc.body_a) || is_left_out(desc.body_b)) continue;
    save_joint(world, joints, id, state->add_joints());
  }
  return left_out.size();
}

Status restore_world(const tumble::v1::WorldState& state, physics::World* world, BodyDirectory* directory,
                     JointDirectory* joints, BodyLoads* loads) {
  if (state.format_version() != kWorldStateFormat) {
    return Status::error("format_version: expected " + std::to_string(kWorldStateFormat) + ", got " +
                         std::to_string(state.format_version()));
  }
  if (!state.has_gravity() || !finite(state.gravity())) {
    return Status::error("gravity: missing or not finite");
  }
  world->set_gravity(to_vec3(state.gravity()));
  if (state.next_body_id() > kMaxBodyIds) {
    return Status::error("next_body_id: " + std::to_string(state.next_body_id()) + " is more than the " +
                         std::to_string(kMaxBodyIds) + " ids a world may hand out");
  }

  tumble::v1::BodySpec renamed;  // the spec of a body whose saved name is refused, without it
  for (int i = 0; i < state.bodies_size(); ++i) {
    const tumble::v1::SavedBody& saved = state.bodies(i);
    const std::string where = "bodies[" + std::to_string(i) + "]";
    if (saved.id() >= state.next_body_id()) {
      return Status::error(where + ".id: " + std::to_string(saved.id()) + " is not below next_body_id");
    }
    if (world->contains(saved.id())) {
      return Status::error(where + ".id: " + std::to_string(saved.id()) + " is used by another body");
    }
    const tumble::v1::BodySpec& spec =
        saved.spec().name().empty() ? saved.spec() : allowed_name(saved, where, &renamed);
    if (!spec.name().empty() && directory->id_of(spec.name()) != physics::kInvalidBodyId) {
      return Status::error(where + ".spec.name: '" + log_text(spec.name()) + "' is used by another body");
    }
    // The saved pose must be exact: no normalisation beyond what the spec
    // check does, and then the saved quaternion itself is put back.
    physics::BodyDesc desc;
    if (Status status = body_desc_from_spec(spec, where + ".spec", &desc); !status.ok()) return status;
    if (!finite(saved.linear_momentum()) || !finite(saved.angular_momentum()) || !std::isfinite(saved.sleep_time())) {
      return Status::error(where + ": momenta and sleep_time must be finite");
    }
    if (!finite(saved.rest_position()) || !std::isfinite(saved.last_speed()) ||
        !std::isfinite(saved.rise_start_speed()) || (saved.has_rest_orientation() && !unit(saved.rest_orientation()))) {
      return Status::error(
          where +
          ": rest_position, last_speed and rise_start_speed must be finite, rest_orientation a unit quaternion");
    }
    world->add_body_with_id(desc, saved.id());
    if (spec.shape().kind_case() != tumble::v1::Shape::kPlane) {
      // A spec without an orientation means the identity (desc has it), not
      // the zero quaternion protobuf's defaults would give.
      const auto& q = spec.orientation();
      const physics::Quat orientation =
          spec.has_orientation() ? physics::Quat(q.w(), q.x(), q.y(), q.z()) : desc.orientation;
      physics::SleepProgress sleep;
      sleep.time = saved.sleep_time();
      sleep.rest_position = saved.has_rest_position() ? to_vec3(saved.rest_position()) : desc.position;
      sleep.rest_orientation = saved.has_rest_orientation() ? to_quat(saved.rest_orientation()) : orientation;
      sleep.last_speed = saved.last_speed();
      sleep.rise_start_speed = saved.rise_start_speed();
      sleep.rising_steps = saved.rising_steps();
      world->restore_state(saved.id(), desc.position, orientation, to_vec3(saved.linear_momentum()),
                           to_vec3(saved.angular_momentum()), !saved.asleep(), sleep);
      // The momenta are checked through the velocities they give (v = p / m,
      // w = I^-1 L), held to the same ranges as a spawned body's: a file
      // that loads must save again to a file that loads.
      if (!restorable(*world, saved.id())) {
        const physics::Vec3 v = world->linear_velocity(saved.id());
        const physics::Vec3 w = world->angular_velocity(saved.id());
        return Status::error(where + ": its momenta give a velocity of [" + std::to_string(v.x()) + ", " +
                             std::to_string(v.y()) + ", " + std::to_string(v.z()) + "] m/s and [" +
                             std::to_string(w.x()) + ", " + std::to_string(w.y()) + ", " + std::to_string(w.z()) +
                             "] rad/s, outside -1e9 .. 1e9 in some component");
      }
    }
    directory->add(saved.id(), BodyEntry{spec.name(), spec.shape(), world->mass(saved.id())});
  }
  world->set_next_body_id(state.next_body_id());

  if (state.next_joint_id() > kMaxJointIds) {
    return Status::error("next_joint_id: " + std::to_string(state.next_joint_id()) + " is more than the " +
                         std::to_string(kMaxJointIds) + " ids a world may hand out");
  }
  for (int i = 0; i < state.joints_size(); ++i) {
    const tumble::v1::SavedJoint& saved = state.joints(i);
    const std::string where = "joints[" + std::to_string(i) + "]";
    if (saved.id() >= state.next_joint_id()) {
      return Status::error(where + ".id: " + std::to_string(saved.id()) + " is not below next_joint_id");
    }
    if (world->contains_joint(saved.id())) {
      return Status::error(where + ".id: " + std::to_string(saved.id()) + " is used by another joint");
    }
    if (Status status = check_joint_name(saved.name(), where + ".name"); !status.ok()) return status;
    if (!saved.name().empty() && joints->id_of(saved.name()) != physics::kInvalidJointId) {
      return Status::error(where + ".name: '" + log_text(saved.name()) + "' is used by another joint");
    }
    if (saved.body_a() != physics::kWorldBodyId && !world->contains(saved.body_a())) {
      return Status::error(where + ".body_a: no body " + std::to_string(saved.body_a()));
    }
    if (!world->contains(saved.body_b()))
      return Status::error(where + ".body_b: no body " + std::to_string(saved.body_b()));
    physics::JointDesc desc;
    physics::JointImpulses impulses;
    if (Status status = joint_from_saved(saved, where, &desc, &impulses); !status.ok()) return status;
    if (const char* error = world->joint_desc_error(desc)) return Status::error(where + "." + error);
    world->add_joint_with_id(desc, saved.id());
    world->restore_joint_impulses(saved.id(), impulses);
    joints->add(saved.id(), JointEntry{saved.name(), desc.body_a, desc.body_b});
  }
  world->set_next_joint_id(state.next_joint_id());

  for (int i = 0; i < state.loads_size(); ++i) {
    const tumble::v1::SavedLoad& saved = state.loads(i);
    const std::string where = "loads[" + std::to_string(i) + "]";
    if (!world->contains(saved.body())) {
      return Status::error(where + ".body: no body " + std::to_string(saved.body()));
    }
    if (!finite(saved.force()) || !finite(saved.local_point()) || !finite(saved.torque())) {
      return Status::error(where + ": force, local_point and torque must be finite");
    }
    if (saved.ticks_left() == 0) return Status::error(where + ".ticks_left: must be at least 1");
    loads->add(BodyLoad{saved.body(), to_vec3(saved.force()), to_vec3(saved.local_point()), to_vec3(saved.torque()),
                        saved.ticks_left()});
  }
  return {};
}

tumble::v1::Scene restorable_scene(const tumble::v1::Scene& scene) {
  tumble::v1::Scene allowed = scene;
  for (int i = 0; i < allowed.bodies_size(); ++i) {
    tumble::v1::BodySpec& body = *allowed.mutable_bodies(i);
    const Status refused = check_body_name(body.name(), "scene.bodies[" + std::to_string(i) + "].name");
    if (refused.ok()) continue;
    sim_log().warn("{}; Reset will bring the body back without a name", log_text(refused.message(), kLogMessageBytes));
    body.clear_name();
  }
  return allowed;
}

}  // namespace tumble::sim
