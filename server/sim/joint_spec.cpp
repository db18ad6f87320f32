#include "sim/joint_spec.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "sim/body_limits.h"
#include "sim/log_text.h"
#include "sim/proto_math.h"
#include "sim/string_limits.h"

namespace tumble::sim {
namespace {

using tumble::v1::JointSpec;
using tumble::v1::JointType;

// A length, angle, speed or force a joint may hold: finite, within kMaxMagnitude.
Status check_number(double value, const std::string& path) {
  if (std::isfinite(value) && std::abs(value) <= kMaxMagnitude) return {};
  return Status::error(path + ": " + format_number(value) + " is not a finite number within -1e9 .. 1e9");
}

Status check_at_least_zero(double value, const std::string& path) {
  if (Status status = check_number(value, path); !status.ok()) return status;
  if (value < 0) return Status::error(path + ": " + format_number(value) + " is below 0");
  return {};
}

// "a hinge joint", for messages about what a type takes.
std::string a_joint(JointType type) {
  const std::string name = joint_type_name(type);
  return "a " + name + " joint";
}

// The field `present` is not one `type` takes, unless `allowed`.
Status check_takes(bool present, bool allowed, JointType type, const std::string& path, const char* what) {
  if (!present || allowed) return {};
  return Status::error(path + ": " + a_joint(type) + " has no " + what);
}

}  // namespace

bool physics_joint_type(tumble::v1::JointType type, physics::JointType* out) {
  switch (type) {
    case tumble::v1::JOINT_TYPE_BALL:
      *out = physics::JointType::ball;
      return true;
    case tumble::v1::JOINT_TYPE_HINGE:
      *out = physics::JointType::hinge;
      return true;
    case tumble::v1::JOINT_TYPE_SLIDER:
      *out = physics::JointType::slider;
      return true;
    case tumble::v1::JOINT_TYPE_FIXED:
      *out = physics::JointType::fixed;
      return true;
    case tumble::v1::JOINT_TYPE_DISTANCE:
      *out = physics::JointType::distance;
      return true;
    default:
      return false;
  }
}

const char* joint_type_name(JointType type) {
  switch (type) {
    case tumble::v1::JOINT_TYPE_BALL:
      return "ball";
    case tumble::v1::JOINT_TYPE_HINGE:
      return "hinge";
    case tumble::v1::JOINT_TYPE_SLIDER:
      return "slider";
    case tumble::v1::JOINT_TYPE_FIXED:
      return "fixed";
    case tumble::v1::JOINT_TYPE_DISTANCE:
      return "distance";
    default:
      return "";
  }
}

JointType joint_type_named(std::string_view name) {
  for (const JointType type : {tumble::v1::JOINT_TYPE_BALL, tumble::v1::JOINT_TYPE_HINGE, tumble::v1::JOINT_TYPE_SLIDER,
                               tumble::v1::JOINT_TYPE_FIXED, tumble::v1::JOINT_TYPE_DISTANCE}) {
    if (name == joint_type_name(type)) return type;
  }
  return tumble::v1::JOINT_TYPE_UNSPECIFIED;
}

JointType wire_joint_type(physics::JointType type) {
  switch (type) {
    case physics::JointType::ball:
      return tumble::v1::JOINT_TYPE_BALL;
    case physics::JointType::hinge:
      return tumble::v1::JOINT_TYPE_HINGE;
    case physics::JointType::slider:
      return tumble::v1::JOINT_TYPE_SLIDER;
    case physics::JointType::fixed:
      return tumble::v1::JOINT_TYPE_FIXED;
    case physics::JointType::distance:
      return tumble::v1::JOINT_TYPE_DISTANCE;
  }
  return tumble::v1::JOINT_TYPE_UNSPECIFIED;
}

Status check_joint_motor(const tumble::v1::JointMotorSpec& motor, JointType type, const std::string& where) {
  const bool hinge = type == tumble::v1::JOINT_TYPE_HINGE;
  if (!hinge && type != tumble::v1::JOINT_TYPE_SLIDER)
    return Status::error(where + ": " + a_joint(type) + " has no motor");
  Status status;
  switch (motor.target_case()) {
    case tumble::v1::JointMotorSpec::kSpeed:
      if (!(status = check_number(motor.speed(), where + ".speed")).ok()) return status;
      if (motor.has_hertz() || motor.has_damping_ratio()) {
        return Status::error(where + ": a speed motor has no spring; hertz and damping_ratio go with a position");
      }
      break;
    case tumble::v1::JointMotorSpec::kPosition:
      if (!(status = check_number(motor.position(), where + ".position")).ok()) return status;
      if (motor.has_hertz()) {
        if (!(status = check_number(motor.hertz(), where + ".hertz")).ok()) return status;
        if (motor.hertz() <= 0)
          return Status::error(where + ".hertz: " + format_number(motor.hertz()) + " is not above 0");
      }
      if (motor.has_damping_ratio() &&
          !(status = check_at_least_zero(motor.damping_ratio(), where + ".damping_ratio")).ok()) {
        return status;
      }
      break;
    case tumble::v1::JointMotorSpec::TARGET_NOT_SET:
      return Status::error(where + ": expected exactly one of speed, position");
  }
  // A hinge's motor drives an angle with a torque, a slider's a position with a force.
  const char* wanted = hinge ? "max_torque" : "max_force";
  const char* other = hinge ? "max_force" : "max_torque";
  if (hinge ? motor.has_max_force() : motor.has_max_torque()) {
    return Status::error(where + "." + other + ": " + a_joint(type) + "'s motor takes " + wanted);
  }
  if (!(hinge ? motor.has_max_torque() : motor.has_max_force())) {
    return Status::error(where + ": missing field '" + wanted + "'");
  }
  return check_at_least_zero(hinge ? motor.max_torque() : motor.max_force(), where + "." + wanted);
}

physics::JointMotor physics_motor(const tumble::v1::JointMotorSpec& motor) {
  physics::JointMotor out;
  if (motor.has_speed()) {
    out.mode = physics::JointMotor::Mode::speed;
    out.target = motor.speed();
  } else if (motor.has_position()) {
    out.mode = physics::JointMotor::Mode::position;
    out.target = motor.position();
    if (motor.has_hertz()) out.hertz = motor.hertz();
    if (motor.has_damping_ratio()) out.damping_ratio = motor.damping_ratio();
  }
  out.max_force = motor.has_max_torque() ? motor.max_torque() : motor.max_force();
  return out;
}

void wire_motor(const physics::JointMotor& motor, physics::JointType type, tumble::v1::JointMotorSpec* out) {
  switch (motor.mode) {
    case physics::JointMotor::Mode::off:
      return;
    case physics::JointMotor::Mode::speed:
      out->set_speed(motor.target);
      break;
    case physics::JointMotor::Mode::position:
      out->set_position(motor.target);
      out->set_hertz(motor.hertz);
      out->set_damping_ratio(motor.damping_ratio);
      break;
  }
  if (type == physics::JointType::hinge) {
    out->set_max_torque(motor.max_force);
  } else {
    out->set_max_force(motor.max_force);
  }
}

Status check_joint_spec(const JointSpec& spec, const std::string& where) {
  const JointType type = spec.type();
  if (type == tumble::v1::JOINT_TYPE_UNSPECIFIED || !tumble::v1::JointType_IsValid(type)) {
    return Status::error(where + ".type: expected one of ball, hinge, slider, fixed, distance");
  }
  Status status = check_joint_name(spec.name(), where + ".name");
  if (!status.ok()) return status;
  for (const auto& [ref, field] : {std::pair{&spec.body_a(), ".body_a"}, std::pair{&spec.body_b(), ".body_b"}}) {
    if (ref->empty()) return Status::error(where + field + ": missing; name a body");
    if (!(status = check_text_length(*ref, where + field, kMaxBodyNameBytes)).ok()) return status;
  }
  if (spec.body_b() == kWorldBodyName) {
    return Status::error(where + ".body_b: only body_a may be the world");
  }
  if (spec.body_a() == spec.body_b()) {
    return Status::error(where + ".body_b: '" + log_text(spec.body_b()) +
                         "' is body_a too; a joint joins two different bodies");
  }

  const bool distance = type == tumble::v1::JOINT_TYPE_DISTANCE;
  const bool hinge_or_slider = type == tumble::v1::JOINT_TYPE_HINGE || type == tumble::v1::JOINT_TYPE_SLIDER;
  // Scene files name a distance joint's first point anchor_a.
  const std::string anchor = where + (distance ? ".anchor_a" : ".anchor");
  if (!spec.has_anchor() && type != tumble::v1::JOINT_TYPE_FIXED) {
    return Status::error(where + ": missing field '" + (distance ? "anchor_a" : "anchor") + "'");
  }
  if (spec.has_anchor() && !(status = check_magnitude(spec.anchor(), "m", anchor)).ok()) return status;
  if (distance && !spec.has_anchor_b()) return Status::error(where + ": missing field 'anchor_b'");
  if (!(status = check_takes(spec.has_anchor_b(), distance, type, where + ".anchor_b", "second anchor")).ok()) {
    return status;
  }
  if (spec.has_anchor_b() && !(status = check_magnitude(spec.anchor_b(), "m", where + ".anchor_b")).ok()) return status;
  const bool has_axis = hinge_or_slider || type == tumble::v1::JOINT_TYPE_BALL;
  if (!(status = check_takes(spec.has_axis(), has_axis, type, where + ".axis", "axis")).ok()) return status;
  if (spec.has_axis()) {
    if (!(status = check_magnitude(spec.axis(), "", where + ".axis")).ok()) return status;
    if (to_vec3(spec.axis()).norm() < 1e-9) return Status::error(where + ".axis: must not be zero");
  }

  if (!(status = check_takes(spec.has_limits(), hinge_or_slider, type, where + ".limits", "limits")).ok()) {
    return status;
  }
  if (spec.has_limits()) {
    const tumble::v1::JointLimits& limits = spec.limits();
    if (!(status = check_number(limits.lower(), where + ".limits[0]")).ok()) return status;
    if (!(status = check_number(limits.upper(), where + ".limits[1]")).ok()) return status;
    if (limits.lower() > limits.upper()) {
      return Status::error(where + ".limits: the lower limit " + format_number(limits.lower()) +
                           " is above the upper limit " + format_number(limits.upper()));
    }
  }
  const bool ball = type == tumble::v1::JOINT_TYPE_BALL;
  if (!(status = check_takes(spec.has_cone_limit(), ball, type, where + ".cone_limit", "cone limit")).ok()) {
    return status;
  }
  if (spec.has_cone_limit() && !(status = check_number(spec.cone_limit(), where + ".cone_limit")).ok()) return status;
  if (!(status = check_takes(spec.has_friction(), ball || hinge_or_slider, type, where + ".friction", "friction"))
           .ok()) {
    return status;
  }
  if (spec.has_friction() && !(status = check_at_least_zero(spec.friction(), where + ".friction")).ok()) return status;

  const struct {
    bool present;
    double value;
    const char* field;
  } lengths[] = {{spec.has_length(), spec.length(), ".length"},
                 {spec.has_min_length(), spec.min_length(), ".min_length"},
                 {spec.has_max_length(), spec.max_length(), ".max_length"}};
  for (const auto& length : lengths) {
    if (!(status = check_takes(length.present, distance, type, where + length.field, "length")).ok()) return status;
    if (length.present && !(status = check_at_least_zero(length.value, where + length.field)).ok()) return status;
  }
  if (spec.has_min_length() && spec.has_max_length() && spec.min_length() > spec.max_length()) {
    return Status::error(where + ".min_length: " + format_number(spec.min_length()) + " m is above max_length " +
                         format_number(spec.max_length()) + " m");
  }
  if (!(status = check_takes(spec.has_spring(), distance, type, where + ".spring", "spring")).ok()) return status;
  if (spec.has_spring()) {
    if (!(status = check_number(spec.spring().hertz(), where + ".spring.hertz")).ok()) return status;
    if (spec.spring().hertz() <= 0) {
      return Status::error(where + ".spring.hertz: " + format_number(spec.spring().hertz()) + " is not above 0");
    }
    if (!(status = check_at_least_zero(spec.spring().damping_ratio(), where + ".spring.damping_ratio")).ok()) {
      return status;
    }
  }
  if (spec.has_motor() && !(status = check_joint_motor(spec.motor(), type, where + ".motor")).ok()) return status;
  if (spec.has_break_force() && !(status = check_at_least_zero(spec.break_force(), where + ".break_force")).ok()) {
    return status;
  }
  if (spec.has_break_torque() && !(status = check_at_least_zero(spec.break_torque(), where + ".break_torque")).ok()) {
    return status;
  }
  return {};
}

physics::BodyId resolve_joint_body(std::string_view ref, const physics::World& world, const BodyDirectory& directory) {
  if (ref == kWorldBodyName) return physics::kWorldBodyId;
  const bool digits_only = !ref.empty() && ref.find_first_not_of("0123456789") == std::string_view::npos;
  if (!digits_only) return directory.id_of(std::string(ref));
  physics::BodyId id = 0;
  const auto [end, error] = std::from_chars(ref.data(), ref.data() + ref.size(), id);
  if (error != std::errc() || end != ref.data() + ref.size() || !world.contains(id)) return physics::kInvalidBodyId;
  return id;
}

Status joint_desc_from_spec(const JointSpec& spec, const std::string& where, const physics::World& world,
                            const BodyDirectory& directory, physics::JointDesc* desc) {
  *desc = physics::JointDesc{};
  if (Status status = check_joint_spec(spec, where); !status.ok()) return status;
  desc->body_a = resolve_joint_body(spec.body_a(), world, directory);
  if (desc->body_a == physics::kInvalidBodyId) {
    return Status::error(where + ".body_a: no body '" + log_text(spec.body_a()) + "' in the world");
  }
  desc->body_b = resolve_joint_body(spec.body_b(), world, directory);
  if (desc->body_b == physics::kInvalidBodyId) {
    return Status::error(where + ".body_b: no body '" + log_text(spec.body_b()) + "' in the world");
  }
  if (desc->body_a == desc->body_b) {
    return Status::error(where + ".body_b: '" + log_text(spec.body_b()) + "' is body " + std::to_string(desc->body_b) +
                         ", body_a too; a joint joins two different bodies");
  }

  // check_joint_spec has refused the types that map to none.
  physics_joint_type(spec.type(), &desc->type);
  const physics::Vec3 centre_b = world.position(desc->body_b);
  const physics::Vec3 anchor_a = spec.has_anchor() ? to_vec3(spec.anchor()) : centre_b;
  const physics::Vec3 anchor_b = spec.has_anchor_b() ? to_vec3(spec.anchor_b()) : anchor_a;
  physics::Vec3 axis = physics::Vec3::UnitX();
  if (spec.has_axis()) {
    axis = to_vec3(spec.axis());
  } else if (spec.type() == tumble::v1::JOINT_TYPE_BALL && (centre_b - anchor_a).norm() > 1e-9) {
    axis = centre_b - anchor_a;  // the cone opens towards body B
  }
  world.set_joint_frames(*desc, anchor_a, anchor_b, axis);

  if (spec.has_limits()) {
    desc->limits_enabled = true;
    desc->lower = spec.limits().lower();
    desc->upper = spec.limits().upper();
  }
  if (spec.has_cone_limit()) desc->cone_limit = spec.cone_limit();
  if (spec.type() == tumble::v1::JOINT_TYPE_DISTANCE) {
    // Rigid at the anchors' distance unless the spec says otherwise.
    const double apart = spec.has_length() ? spec.length() : (anchor_b - anchor_a).norm();
    if (!spec.has_min_length() && !spec.has_max_length()) {
      desc->length = desc->min_length = desc->max_length = apart;
    } else {
      desc->min_length = spec.has_min_length() ? spec.min_length() : 0;
      desc->max_length = spec.has_max_length() ? spec.max_length() : std::max(apart, desc->min_length);
      desc->length = spec.has_length() ? spec.length() : std::clamp(apart, desc->min_length, desc->max_length);
    }
    if (spec.has_spring()) {
      desc->spring_hertz = spec.spring().hertz();
      desc->spring_damping_ratio = spec.spring().damping_ratio();
    }
  }
  if (spec.has_motor()) desc->motor = physics_motor(spec.motor());
  if (spec.has_break_force()) desc->break_force = spec.break_force();
  if (spec.has_break_torque()) desc->break_torque = spec.break_torque();
  if (spec.has_friction()) desc->friction = spec.friction();
  desc->collide_connected = spec.collide_connected();
  if (const char* error = world.joint_desc_error(*desc)) return Status::error(where + "." + error);
  return {};
}

void fill_joint_state(const physics::World& world, physics::JointId id, tumble::v1::JointState* out) {
  const physics::JointState state = world.joint_state(id);
  out->set_id(id);
  out->set_position(state.position);
  out->set_speed(state.speed);
  set_vec3(state.force, out->mutable_force());
  set_vec3(state.torque, out->mutable_torque());
  out->set_motor_impulse(state.motor_impulse);
}

}  // namespace tumble::sim
