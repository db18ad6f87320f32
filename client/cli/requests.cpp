#include "requests.h"

namespace tumble::cli {
namespace {

void set_vec3(const Vector3& from, tumble::v1::Vec3& to) {
  to.set_x(from[0]);
  to.set_y(from[1]);
  to.set_z(from[2]);
}

tumble::v1::Frame point_frame(bool local) { return local ? tumble::v1::FRAME_BODY : tumble::v1::FRAME_WORLD; }

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
  return request;
}

tumble::v1::ApplyTorque make_apply_torque(const TorqueCommand& command) {
  tumble::v1::ApplyTorque request;
  *request.mutable_body() = command.body;
  set_vec3(command.torque, *request.mutable_torque());
  if (command.duration.seconds) request.set_seconds(*command.duration.seconds);
  if (command.duration.ticks) request.set_ticks(*command.duration.ticks);
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
  return request;
}

}  // namespace tumble::cli
