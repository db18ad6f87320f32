#include "tumble_client/transport.h"

#include <utility>

namespace tumble::client {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

namespace {

// Moves one payload out of a reply, e.g. the Ack out of an Ack reply.
template <typename Payload>
Result<Payload> take_payload(Result<ServerMessage> reply, Payload* (ServerMessage::*payload)()) {
  if (!reply) return reply.failure();
  return std::move(*((reply.value()).*payload)());
}

}  // namespace

// The name of the message an envelope's `kind` oneof holds, e.g. "ListBodies".
std::string kind_name(const google::protobuf::Message& envelope) {
  const auto* oneof = envelope.GetDescriptor()->FindOneofByName("kind");
  const auto* field = oneof ? envelope.GetReflection()->GetOneofFieldDescriptor(envelope, oneof) : nullptr;
  if (field == nullptr || field->message_type() == nullptr) return "an empty message";
  return field->message_type()->name();
}

// The reply kind the protocol pairs with a request kind; KIND_NOT_SET when
// any reply that echoes the request id will do.
ServerMessage::KindCase expected_reply(ClientMessage::KindCase request) {
  switch (request) {
    case ClientMessage::kApplyForce:
    case ClientMessage::kApplyTorque:
    case ClientMessage::kApplyImpulse:
    case ClientMessage::kUnsubscribe:
    case ClientMessage::kKeyFrameRequest:
    case ClientMessage::kSpawnBody:
    case ClientMessage::kRemoveBody:
    case ClientMessage::kSetBodyState:
    case ClientMessage::kClearForces:
    case ClientMessage::kPause:
    case ClientMessage::kResume:
    case ClientMessage::kStep:
    case ClientMessage::kReset:
    case ClientMessage::kSetTickRate:
    case ClientMessage::kAddJoint:
    case ClientMessage::kRemoveJoint:
    case ClientMessage::kSetJointMotor:
      return ServerMessage::kAck;
    case ClientMessage::kListBodies:
      return ServerMessage::kBodyList;
    case ClientMessage::kListJoints:
      return ServerMessage::kJointList;
    case ClientMessage::kSubscribe:
      return ServerMessage::kSubscribed;
    case ClientMessage::kGetStats:
      return ServerMessage::kStats;
    default:
      return ServerMessage::KIND_NOT_SET;
  }
}

// The request id a reply echoes; 0 for messages that are not replies.
std::uint64_t echoed_request_id(const ServerMessage& message) {
  switch (message.kind_case()) {
    case ServerMessage::kAck:
      return message.ack().request_id();
    case ServerMessage::kError:
      return message.error().request_id();
    case ServerMessage::kBodyList:
      return message.body_list().request_id();
    case ServerMessage::kJointList:
      return message.joint_list().request_id();
    case ServerMessage::kSubscribed:
      return message.subscribed().request_id();
    case ServerMessage::kStats:
      return message.stats().request_id();
    default:
      return 0;
  }
}

Result<tumble::v1::Ack> Transport::apply_force(const tumble::v1::ApplyForce& force, Timeout timeout) {
  ClientMessage message;
  *message.mutable_apply_force() = force;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::apply_torque(const tumble::v1::ApplyTorque& torque, Timeout timeout) {
  ClientMessage message;
  *message.mutable_apply_torque() = torque;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::apply_impulse(const tumble::v1::ApplyImpulse& impulse, Timeout timeout) {
  ClientMessage message;
  *message.mutable_apply_impulse() = impulse;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::BodyList> Transport::list_bodies(Timeout timeout) {
  auto all = list_bodies_page(0, 0, timeout);
  if (!all) return all;
  while (all->next_start_id() != 0) {
    auto page = list_bodies_page(all->next_start_id(), 0, timeout);
    if (!page) return page;
    // Ids only grow from page to page; a server that answers otherwise would loop forever.
    if (page->next_start_id() != 0 && page->next_start_id() <= all->next_start_id()) {
      return Failure{FailureKind::protocol, "the server's BodyList pages do not advance: next_start_id " +
                                                std::to_string(page->next_start_id()) + " after " +
                                                std::to_string(all->next_start_id())};
    }
    for (auto& body : *page->mutable_bodies()) *all->add_bodies() = std::move(body);
    all->set_tick(page->tick());
    all->set_total_bodies(page->total_bodies());
    all->set_next_start_id(page->next_start_id());
  }
  return all;
}

Result<tumble::v1::BodyList> Transport::list_bodies_page(std::uint32_t start_id, std::uint32_t max_bodies,
                                                         Timeout timeout) {
  ClientMessage message;
  message.mutable_list_bodies()->set_start_id(start_id);
  message.mutable_list_bodies()->set_max_bodies(max_bodies);
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_body_list);
}

Result<tumble::v1::JointList> Transport::list_joints(Timeout timeout) {
  auto all = list_joints_page(0, 0, timeout);
  if (!all) return all;
  while (all->next_start_id() != 0) {
    auto page = list_joints_page(all->next_start_id(), 0, timeout);
    if (!page) return page;
    // As list_bodies: a server whose pages do not advance would loop forever.
    if (page->next_start_id() != 0 && page->next_start_id() <= all->next_start_id()) {
      return Failure{FailureKind::protocol, "the server's JointList pages do not advance: next_start_id " +
                                                std::to_string(page->next_start_id()) + " after " +
                                                std::to_string(all->next_start_id())};
    }
    for (auto& joint : *page->mutable_joints()) *all->add_joints() = std::move(joint);
    all->set_tick(page->tick());
    all->set_total_joints(page->total_joints());
    all->set_next_start_id(page->next_start_id());
  }
  return all;
}

Result<tumble::v1::JointList> Transport::list_joints_page(std::uint32_t start_id, std::uint32_t max_joints,
                                                          Timeout timeout) {
  ClientMessage message;
  message.mutable_list_joints()->set_start_id(start_id);
  message.mutable_list_joints()->set_max_joints(max_joints);
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_joint_list);
}

Result<tumble::v1::Ack> Transport::add_joint(const tumble::v1::JointSpec& joint, Timeout timeout) {
  ClientMessage message;
  *message.mutable_add_joint()->mutable_joint() = joint;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::remove_joint(const tumble::v1::JointRef& joint, Timeout timeout) {
  ClientMessage message;
  *message.mutable_remove_joint()->mutable_joint() = joint;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::set_joint_motor(const tumble::v1::SetJointMotor& motor, Timeout timeout) {
  ClientMessage message;
  *message.mutable_set_joint_motor() = motor;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Subscribed> Transport::subscribe(const tumble::v1::Subscribe& subscribe, Timeout timeout) {
  ClientMessage message;
  *message.mutable_subscribe() = subscribe;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_subscribed);
}

Result<tumble::v1::Ack> Transport::unsubscribe(std::uint32_t subscription_id, Timeout timeout) {
  ClientMessage message;
  message.mutable_unsubscribe()->set_subscription_id(subscription_id);
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::request_key_frame(std::uint32_t subscription_id, Timeout timeout) {
  ClientMessage message;
  message.mutable_key_frame_request()->set_subscription_id(subscription_id);
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::spawn_body(const tumble::v1::BodySpec& body, Timeout timeout) {
  ClientMessage message;
  *message.mutable_spawn_body()->mutable_body() = body;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::remove_body(const tumble::v1::BodyRef& body, Timeout timeout) {
  ClientMessage message;
  *message.mutable_remove_body()->mutable_body() = body;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::set_body_state(const tumble::v1::SetBodyState& state, Timeout timeout) {
  ClientMessage message;
  *message.mutable_set_body_state() = state;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::clear_forces(const tumble::v1::ClearForces& clear, Timeout timeout) {
  ClientMessage message;
  *message.mutable_clear_forces() = clear;
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::pause(Timeout timeout) {
  ClientMessage message;
  message.mutable_pause();
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::resume(Timeout timeout) {
  ClientMessage message;
  message.mutable_resume();
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::step(std::uint32_t ticks, Timeout timeout) {
  ClientMessage message;
  message.mutable_step()->set_ticks(ticks);
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::reset(Timeout timeout) {
  ClientMessage message;
  message.mutable_reset();
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Ack> Transport::set_tick_rate(double rate_hz, Timeout timeout) {
  ClientMessage message;
  message.mutable_set_tick_rate()->set_rate_hz(rate_hz);
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_ack);
}

Result<tumble::v1::Stats> Transport::get_stats(Timeout timeout) {
  ClientMessage message;
  message.mutable_get_stats();
  return take_payload(request(std::move(message), timeout), &ServerMessage::mutable_stats);
}

}  // namespace tumble::client
