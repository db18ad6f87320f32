#include "requests.h"

namespace tumble::cli {
namespace {

void set_vec3(const Vector3& from, tumble::v1::Vec3& to) {
  to.set_x(from[0]);
  to.set_y(from[1]);
  to.set_z(from[2]);
}

tumble::v1::Frame point_frame(bool local) { return local ? tumble::v1::FRAME_BODY : tumble::v1::FRAME_WORLD; }

void set_quat(const Quaternion& from, tumble::v1::Quat& to) {
  to.set_w(from[0]);
  to.set_x(from[1]);
  to.set_y(from[2]);
  to.set_z(from[3]);
}

}  // namespace

tumble::v1::ApplyForce make_apply_force(const ForceCommand& command) {
  tumble::v1::ApplyForce request;
  *request.mutable_body() = command.body;
  set_vec3(command.force, *request.mutable_force());
  if (command.at) {
    set_vec3(*command.at, *request.mutable_point());
    request.set_point_frame(point_frame(command.local));
  }
  if (command.duration.seconds) request.set_seconds(*command.duration.seconds);
  if (command.duration.ticks) request.set_ticks(*command.duration.ticks);
  request.set_persistent(command.persistent);
  return request;
}

tumble::v1::ApplyTorque make_apply_torque(const TorqueCommand& command) {
  tumble::v1::ApplyTorque request;
  *request.mutable_body() = command.body;
  set_vec3(command.torque, *request.mutable_torque());
  if (command.duration.seconds) request.set_seconds(*command.duration.seconds);
  if (command.duration.ticks) request.set_ticks(*command.duration.ticks);
  request.set_persistent(command.persistent);
  return request;
}

tumble::v1::ApplyImpulse make_apply_impulse(const ImpulseCommand& command) {
  tumble::v1::ApplyImpulse request;
  *request.mutable_body() = command.body;
  set_vec3(command.impulse, *request.mutable_impulse());
  if (command.at) {
    set_vec3(*command.at, *request.mutable_point());
    request.set_point_frame(point_frame(command.local));
  }
  return request;
}

tumble::v1::Subscribe make_subscribe(const SubscribeCommand& command) {
  tumble::v1::Subscribe request;
  for (const tumble::v1::BodyRef& body : command.bodies) *request.add_bodies() = body;
  request.set_rate_hz(command.rate_hz);
  request.set_fields(command.poses_only ? tumble::v1::POSE_FIELDS_POSE : tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY);
  request.set_joints(command.joints);
  request.set_encoding(command.encoding);
  if (command.events) {
    for (const auto kind :
         {tumble::v1::WORLD_EVENT_BODY_SPAWNED, tumble::v1::WORLD_EVENT_BODY_REMOVED,
          tumble::v1::WORLD_EVENT_BODY_ASLEEP, tumble::v1::WORLD_EVENT_BODY_AWAKE, tumble::v1::WORLD_EVENT_WORLD_RESET,
          tumble::v1::WORLD_EVENT_BODY_DIVERGED, tumble::v1::WORLD_EVENT_JOINT_ADDED,
          tumble::v1::WORLD_EVENT_JOINT_REMOVED, tumble::v1::WORLD_EVENT_JOINT_BROKEN}) {
      request.add_events(kind);
    }
  }
  return request;
}

tumble::v1::BodySpec make_body_spec(const SpawnCommand& command) {
  tumble::v1::BodySpec spec;
  spec.set_name(command.name);
  *spec.mutable_shape() = command.shape;
  spec.set_mass(command.mass);
  set_vec3(command.position, *spec.mutable_position());
  if (command.orientation) set_quat(*command.orientation, *spec.mutable_orientation());
  set_vec3(command.linear_velocity, *spec.mutable_linear_velocity());
  set_vec3(command.angular_velocity, *spec.mutable_angular_velocity());
  spec.set_motion(command.motion);
  if (command.friction) spec.set_friction(*command.friction);
  if (command.restitution) spec.set_restitution(*command.restitution);
  return spec;
}

tumble::v1::SetBodyState make_set_body_state(const SetCommand& command) {
  tumble::v1::SetBodyState request;
  *request.mutable_body() = command.body;
  if (command.position) set_vec3(*command.position, *request.mutable_position());
  if (command.orientation) set_quat(*command.orientation, *request.mutable_orientation());
  if (command.linear_velocity) set_vec3(*command.linear_velocity, *request.mutable_linear_velocity());
  if (command.angular_velocity) set_vec3(*command.angular_velocity, *request.mutable_angular_velocity());
  return request;
}

tumble::v1::ClearForces make_clear_forces(const ClearCommand& command) {
  tumble::v1::ClearForces request;
  if (command.body) *request.mutable_body() = *command.body;
  return request;
}

tumble::v1::Subscribe make_watch_subscribe(const WatchCommand& command) {
  tumble::v1::Subscribe request;
  for (const tumble::v1::BodyRef& body : command.bodies) *request.add_bodies() = body;
  request.set_rate_hz(command.rate_hz);
  request.set_fields(tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY);
  request.set_encoding(command.encoding);
  for (const auto kind : {tumble::v1::WORLD_EVENT_BODY_SPAWNED, tumble::v1::WORLD_EVENT_BODY_REMOVED,
                          tumble::v1::WORLD_EVENT_BODY_ASLEEP, tumble::v1::WORLD_EVENT_BODY_AWAKE}) {
    request.add_events(kind);
  }
  return request;
}

tumble::v1::JointSpec make_joint_spec(const JointAddCommand& command) {
  tumble::v1::JointSpec spec;
  spec.set_name(command.name);
  spec.set_type(command.type);
  spec.set_body_a(command.body_a);
  spec.set_body_b(command.body_b);
  if (command.anchor) set_vec3(*command.anchor, *spec.mutable_anchor());
  if (command.anchor_b) set_vec3(*command.anchor_b, *spec.mutable_anchor_b());
  if (command.axis) set_vec3(*command.axis, *spec.mutable_axis());
  if (command.limits) {
    spec.mutable_limits()->set_lower((*command.limits)[0]);
    spec.mutable_limits()->set_upper((*command.limits)[1]);
  }
  if (command.cone_limit) spec.set_cone_limit(*command.cone_limit);
  if (command.min_length) spec.set_min_length(*command.min_length);
  if (command.max_length) spec.set_max_length(*command.max_length);
  if (command.length) spec.set_length(*command.length);
  if (command.break_force) spec.set_break_force(*command.break_force);
  if (command.break_torque) spec.set_break_torque(*command.break_torque);
  if (command.friction) spec.set_friction(*command.friction);
  spec.set_collide_connected(command.collide_connected);
  return spec;
}

tumble::v1::SetJointMotor make_set_joint_motor(const MotorCommand& command) {
  tumble::v1::SetJointMotor request;
  *request.mutable_joint() = command.joint;
  if (command.motor) *request.mutable_motor() = *command.motor;
  return request;
}

}  // namespace tumble::cli
