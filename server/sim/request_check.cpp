#include "sim/request_check.h"

#include <cmath>
#include <tuple>

#include "sim/body_limits.h"
#include "sim/body_spec.h"
#include "sim/joint_spec.h"
#include "sim/string_limits.h"

namespace tumble::sim {
namespace {

using tumble::v1::ClientMessage;

// The longest a timed force or torque may last, in seconds of sim time.
constexpr double kMaxDurationSeconds = 1e6;

std::optional<RequestError> invalid(std::string message) {
  return RequestError{tumble::v1::INVALID_ARGUMENT, std::move(message)};
}

std::optional<RequestError> check_vec3(const tumble::v1::Vec3& v, const char* field) {
  if (within_limits(v.x()) && within_limits(v.y()) && within_limits(v.z())) return std::nullopt;
  return invalid(std::string(field) + " must have finite components of at most 1e9 in magnitude, got [" +
                 std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) + "]");
}

// A rotation as it arrives from a client: finite, and unit length up to the
// rounding of hand-typed numbers (the sim normalises it exactly).
std::optional<RequestError> check_quat(const tumble::v1::Quat& q, const char* field) {
  const double norm = std::sqrt(q.w() * q.w() + q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
  if (std::isfinite(norm) && std::abs(norm - 1.0) <= 1e-3) return std::nullopt;
  return invalid(std::string(field) + " must be a unit quaternion [w, x, y, z], got [" + std::to_string(q.w()) + ", " +
                 std::to_string(q.x()) + ", " + std::to_string(q.y()) + ", " + std::to_string(q.z()) + "]");
}

std::optional<RequestError> invalid(const Status& status) {
  if (status.ok()) return std::nullopt;
  return invalid(status.message());
}

// A body's pose or velocity, held to the same ranges as a spawned body's (body_limits.h).
std::optional<RequestError> check_body_vec3(const tumble::v1::Vec3& v, const char* unit, const char* field) {
  return invalid(check_magnitude(v, unit, field));
}

std::optional<RequestError> check_body_ref(const tumble::v1::BodyRef& ref, bool present) {
  if (!present || ref.ref_case() == tumble::v1::BodyRef::REF_NOT_SET) return invalid("body is required");
  if (ref.ref_case() == tumble::v1::BodyRef::kName) {
    if (ref.name().empty()) return invalid("body name must not be empty");
    return invalid(check_text_length(ref.name(), "body.name", kMaxBodyNameBytes));
  }
  return std::nullopt;
}

std::optional<RequestError> check_joint_ref(const tumble::v1::JointRef& ref, bool present) {
  if (!present || ref.ref_case() == tumble::v1::JointRef::REF_NOT_SET) return invalid("joint is required");
  if (ref.ref_case() == tumble::v1::JointRef::kName) {
    if (ref.name().empty()) return invalid("joint name must not be empty");
    return invalid(check_text_length(ref.name(), "joint.name", kMaxJointNameBytes));
  }
  return std::nullopt;
}

// A motor's numbers finite; whether the joint takes it is the sim's to judge (check_joint_motor).
std::optional<RequestError> check_motor_numbers(const tumble::v1::JointMotorSpec& motor) {
  for (const auto& [present, value, field] :
       {std::tuple{motor.has_speed(), motor.speed(), "motor.speed"},
        std::tuple{motor.has_position(), motor.position(), "motor.position"},
        std::tuple{motor.has_hertz(), motor.hertz(), "motor.hertz"},
        std::tuple{motor.has_damping_ratio(), motor.damping_ratio(), "motor.damping_ratio"},
        std::tuple{motor.has_max_torque(), motor.max_torque(), "motor.max_torque"},
        std::tuple{motor.has_max_force(), motor.max_force(), "motor.max_force"}}) {
    if (present && !within_limits(value)) {
      return invalid(std::string(field) + " must be a finite number of at most 1e9 in magnitude, got " +
                     std::to_string(value));
    }
  }
  if (motor.target_case() == tumble::v1::JointMotorSpec::TARGET_NOT_SET) {
    return invalid("motor needs a speed or a position; leave the motor out to turn it off");
  }
  return std::nullopt;
}

// Duration oneofs are alike in every timed message: seconds or ticks.
std::optional<RequestError> check_duration(bool has_seconds, double seconds, bool has_ticks, std::uint32_t ticks) {
  if (has_seconds && !(std::isfinite(seconds) && seconds > 0 && seconds <= kMaxDurationSeconds)) {
    return invalid("duration must be a finite number of seconds in (0, 1e6], got " + std::to_string(seconds));
  }
  if (has_ticks && ticks == 0) return invalid("duration in ticks must be at least 1");
  return std::nullopt;
}

// A Step's own loads act for its ticks: no duration, not persistent.
std::optional<RequestError> check_step(const tumble::v1::Step& m) {
  if (m.ticks() < 1 || m.ticks() > kMaxStepTicks) {
    return invalid("ticks must be from 1 to " + std::to_string(kMaxStepTicks) + ", got " + std::to_string(m.ticks()));
  }
  std::optional<RequestError> error;
  for (int i = 0; i < m.forces_size(); ++i) {
    const auto& f = m.forces(i);
    const std::string where = "forces[" + std::to_string(i) + "]";
    if ((error = check_body_ref(f.body(), f.has_body()))) return invalid(where + "." + error->message);
    if (!f.has_force()) return invalid(where + ".force is required");
    if ((error = check_vec3(f.force(), (where + ".force").c_str()))) return error;
    if ((error = check_vec3(f.point(), (where + ".point").c_str()))) return error;
    if (f.persistent() || f.duration_case() != tumble::v1::ApplyForce::DURATION_NOT_SET) {
      return invalid(where + ": a Step's force acts for the Step's ticks and takes no duration or persistent");
    }
  }
  for (int i = 0; i < m.torques_size(); ++i) {
    const auto& t = m.torques(i);
    const std::string where = "torques[" + std::to_string(i) + "]";
    if ((error = check_body_ref(t.body(), t.has_body()))) return invalid(where + "." + error->message);
    if (!t.has_torque()) return invalid(where + ".torque is required");
    if ((error = check_vec3(t.torque(), (where + ".torque").c_str()))) return error;
    if (t.persistent() || t.duration_case() != tumble::v1::ApplyTorque::DURATION_NOT_SET) {
      return invalid(where + ": a Step's torque acts for the Step's ticks and takes no duration or persistent");
    }
  }
  for (int i = 0; i < m.frame_bodies_size(); ++i) {
    if ((error = check_body_ref(m.frame_bodies(i), true))) {
      return invalid("frame_bodies[" + std::to_string(i) + "]." + error->message);
    }
  }
  if (!tumble::v1::PoseFields_IsValid(m.frame_fields())) {
    return invalid("frame_fields must be POSE_FIELDS_POSE_AND_VELOCITY or POSE_FIELDS_POSE, got " +
                   std::to_string(m.frame_fields()));
  }
  return std::nullopt;
}

}  // namespace

std::optional<RequestError> check_hello(const tumble::v1::Hello& hello) {
  if (Status status = check_text_length(hello.token(), "Hello.token", kMaxTokenBytes); !status.ok()) {
    return RequestError{tumble::v1::UNAUTHENTICATED, status.message()};
  }
  return invalid(check_text_length(hello.client_name(), "Hello.client_name", kMaxClientNameBytes));
}

std::optional<RequestError> check_request(const ClientMessage& message) {
  std::optional<RequestError> error;
  switch (message.kind_case()) {
    case ClientMessage::kHello:
    case ClientMessage::kListBodies:
    case ClientMessage::kListJoints:
    case ClientMessage::kUnsubscribe:
    case ClientMessage::kKeyFrameRequest:
    case ClientMessage::kPause:
    case ClientMessage::kResume:
    case ClientMessage::kReset:
    case ClientMessage::kGetStats:
      return std::nullopt;

    case ClientMessage::kApplyForce: {
      const auto& m = message.apply_force();
      if ((error = check_body_ref(m.body(), m.has_body()))) return error;
      if (!m.has_force()) return invalid("force is required");
      if ((error = check_vec3(m.force(), "force"))) return error;
      if ((error = check_vec3(m.point(), "point"))) return error;
      if (m.persistent() && m.duration_case() != tumble::v1::ApplyForce::DURATION_NOT_SET) {
        return invalid("a persistent force lasts until cleared and takes no duration");
      }
      return check_duration(m.has_seconds(), m.seconds(), m.has_ticks(), m.ticks());
    }
    case ClientMessage::kApplyTorque: {
      const auto& m = message.apply_torque();
      if ((error = check_body_ref(m.body(), m.has_body()))) return error;
      if (!m.has_torque()) return invalid("torque is required");
      if ((error = check_vec3(m.torque(), "torque"))) return error;
      if (m.persistent() && m.duration_case() != tumble::v1::ApplyTorque::DURATION_NOT_SET) {
        return invalid("a persistent torque lasts until cleared and takes no duration");
      }
      return check_duration(m.has_seconds(), m.seconds(), m.has_ticks(), m.ticks());
    }
    case ClientMessage::kApplyImpulse: {
      const auto& m = message.apply_impulse();
      if ((error = check_body_ref(m.body(), m.has_body()))) return error;
      if (!m.has_impulse()) return invalid("impulse is required");
      if ((error = check_vec3(m.impulse(), "impulse"))) return error;
      return check_vec3(m.point(), "point");
    }
    case ClientMessage::kSubscribe: {
      const auto& m = message.subscribe();
      if (!std::isfinite(m.rate_hz()) || m.rate_hz() < 0) {
        return invalid("rate_hz must be a finite number >= 0, got " + std::to_string(m.rate_hz()));
      }
      for (const auto& ref : m.bodies()) {
        if ((error = check_body_ref(ref, true))) return error;
      }
      if (!tumble::v1::PoseFields_IsValid(m.fields())) {
        return invalid("fields must be POSE_FIELDS_POSE_AND_VELOCITY or POSE_FIELDS_POSE, got " +
                       std::to_string(m.fields()));
      }
      if (!tumble::v1::PoseEncoding_IsValid(m.encoding())) {
        return invalid("encoding must be POSE_ENCODING_FULL, _QUANTIZED or _DELTA, got " +
                       std::to_string(m.encoding()));
      }
      for (const int kind : m.events()) {
        if (kind == tumble::v1::WORLD_EVENT_KIND_UNSPECIFIED || !tumble::v1::WorldEventKind_IsValid(kind)) {
          return invalid("events holds " + std::to_string(kind) + ", which is no kind of WorldEvent");
        }
      }
      return std::nullopt;
    }
    case ClientMessage::kSpawnBody:
      // The spec itself is judged by body_desc_from_spec when the sim takes the request.
      if (!message.spawn_body().has_body()) return invalid("body is required");
      return invalid(check_body_name(message.spawn_body().body().name(), "body.name"));
    case ClientMessage::kRemoveBody:
      return check_body_ref(message.remove_body().body(), message.remove_body().has_body());
    case ClientMessage::kSetBodyState: {
      const auto& m = message.set_body_state();
      if ((error = check_body_ref(m.body(), m.has_body()))) return error;
      // SetBodyState changes no mass or shape: those are fixed when a body is made.
      if (m.has_position() && (error = check_body_vec3(m.position(), "m", "position"))) return error;
      if (m.has_orientation() && (error = check_quat(m.orientation(), "orientation"))) return error;
      if (m.has_linear_velocity() && (error = check_body_vec3(m.linear_velocity(), "m/s", "linear_velocity"))) {
        return error;
      }
      if (m.has_angular_velocity() && (error = check_body_vec3(m.angular_velocity(), "rad/s", "angular_velocity"))) {
        return error;
      }
      return std::nullopt;
    }
    case ClientMessage::kAddJoint:
      // The bodies and what the world makes of the spec are judged when the sim takes the request.
      if (!message.add_joint().has_joint()) return invalid("joint is required");
      return invalid(check_joint_spec(message.add_joint().joint(), "joint"));
    case ClientMessage::kRemoveJoint:
      return check_joint_ref(message.remove_joint().joint(), message.remove_joint().has_joint());
    case ClientMessage::kSetJointMotor: {
      const auto& m = message.set_joint_motor();
      if ((error = check_joint_ref(m.joint(), m.has_joint()))) return error;
      return m.has_motor() ? check_motor_numbers(m.motor()) : std::nullopt;
    }
    case ClientMessage::kClearForces: {
      const auto& m = message.clear_forces();
      return m.has_body() ? check_body_ref(m.body(), true) : std::nullopt;
    }
    case ClientMessage::kStep:
      return check_step(message.step());
    case ClientMessage::kSetTickRate: {
      const double rate = message.set_tick_rate().rate_hz();
      if (!(std::isfinite(rate) && rate >= kMinTickRateHz && rate <= kMaxTickRateHz)) {
        return invalid("rate_hz must be from 1 to 10000, got " + std::to_string(rate));
      }
      return std::nullopt;
    }
    case ClientMessage::KIND_NOT_SET:
      break;
  }
  return RequestError{tumble::v1::UNKNOWN_MESSAGE,
                      "the message holds no request this server knows (protocol version 1)"};
}

}  // namespace tumble::sim
