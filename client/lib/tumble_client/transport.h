// Transport: the requests and messages of one world, whichever way they
// travel. A Connection carries them over tumbled's own TCP protocol; a
// NatsConnection over NATS subjects. The `tumble` commands are written
// against this interface only, so each runs unchanged over either.
//
// Every call blocks the calling thread until it is done, fails, or its
// timeout passes. Not thread-safe: use a transport from one thread at a
// time. It never prints.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include "tumble/v1/protocol.pb.h"
#include "tumble_client/result.h"

namespace tumble::client {

// How long a call may block. Negative timeouts count as zero.
using Timeout = std::chrono::steady_clock::duration;

// A timeout that never passes.
inline constexpr Timeout kWaitForever = Timeout::max();

// The timeout of a request unless the caller chooses another.
inline constexpr Timeout kDefaultRequestTimeout = std::chrono::seconds(10);

class Transport {
 public:
  virtual ~Transport() = default;

  // Where requests go, for messages: "127.0.0.1:7400", or "world demo over
  // NATS".
  virtual std::string describe() const = 0;

  // Sends `message` with the transport's next request id (whatever
  // request_id it holds is replaced) and waits up to `timeout` for the reply
  // that echoes it: Ack, BodyList, JointList, Subscribed or Stats, checked against the
  // request's kind. Fails with kind server when the reply is an Error (or
  // the request was refused before it reached a server: PERMISSION_DENIED),
  // timeout when no reply came in time, connect when nothing serves the
  // world, closed or protocol when the link ended or broke.
  virtual Result<tumble::v1::ServerMessage> request(tumble::v1::ClientMessage message, Timeout timeout) = 0;

  // Starts the pose frames (and, when it asks for them, the world events)
  // that next_message() hands over; the reply says which subscription id
  // they carry. Over TCP a Subscribe request; see NatsConnection for NATS.
  virtual Result<tumble::v1::Subscribed> subscribe(const tumble::v1::Subscribe& subscribe, Timeout timeout);

  // The next unsolicited message: a PoseFrame or WorldEvent of a
  // subscription, or an Error that ends the link. Fails with kind timeout
  // when nothing came in time (the transport stays usable), closed when the
  // link ended, or protocol.
  virtual Result<tumble::v1::ServerMessage> next_message(Timeout timeout) = 0;

  // The requests of the protocol, each returning the reply's payload. Same
  // failures as request().
  Result<tumble::v1::Ack> apply_force(const tumble::v1::ApplyForce& force, Timeout timeout);
  Result<tumble::v1::Ack> apply_torque(const tumble::v1::ApplyTorque& torque, Timeout timeout);
  Result<tumble::v1::Ack> apply_impulse(const tumble::v1::ApplyImpulse& impulse, Timeout timeout);
  // Every body, page after page (ListBodies from each page's next_start_id
  // until it is 0), as one BodyList: bodies in ascending id order, `tick`
  // and `total_bodies` those of the last page, next_start_id 0. `timeout`
  // bounds each page. Fails with kind protocol when the pages do not advance.
  Result<tumble::v1::BodyList> list_bodies(Timeout timeout);
  // One page: the bodies from `start_id` on, at most `max_bodies` (0: as
  // many as the server's page holds).
  Result<tumble::v1::BodyList> list_bodies_page(std::uint32_t start_id, std::uint32_t max_bodies, Timeout timeout);
  Result<tumble::v1::Ack> unsubscribe(std::uint32_t subscription_id, Timeout timeout);
  // A DELTA subscription's next frame is a key frame.
  Result<tumble::v1::Ack> request_key_frame(std::uint32_t subscription_id, Timeout timeout);
  // The Ack's body_id is the new body's id.
  Result<tumble::v1::Ack> spawn_body(const tumble::v1::BodySpec& body, Timeout timeout);
  Result<tumble::v1::Ack> remove_body(const tumble::v1::BodyRef& body, Timeout timeout);
  Result<tumble::v1::Ack> set_body_state(const tumble::v1::SetBodyState& state, Timeout timeout);
  Result<tumble::v1::Ack> clear_forces(const tumble::v1::ClearForces& clear, Timeout timeout);
  Result<tumble::v1::Ack> pause(Timeout timeout);
  Result<tumble::v1::Ack> resume(Timeout timeout);
  // Answered once the ticks are stepped: allow for them in `timeout`.
  Result<tumble::v1::Ack> step(std::uint32_t ticks, Timeout timeout);
  Result<tumble::v1::Ack> reset(Timeout timeout);
  Result<tumble::v1::Ack> set_tick_rate(double rate_hz, Timeout timeout);
  Result<tumble::v1::Stats> get_stats(Timeout timeout);
  // Every joint, page after page, as list_bodies does for bodies.
  Result<tumble::v1::JointList> list_joints(Timeout timeout);
  Result<tumble::v1::JointList> list_joints_page(std::uint32_t start_id, std::uint32_t max_joints, Timeout timeout);
  // The Ack's joint_id is the new joint's id.
  Result<tumble::v1::Ack> add_joint(const tumble::v1::JointSpec& joint, Timeout timeout);
  Result<tumble::v1::Ack> remove_joint(const tumble::v1::JointRef& joint, Timeout timeout);
  // SetJointMotor without a motor turns it off.
  Result<tumble::v1::Ack> set_joint_motor(const tumble::v1::SetJointMotor& motor, Timeout timeout);

 protected:
  Transport() = default;
  Transport(const Transport&) = default;
  Transport(Transport&&) = default;
  Transport& operator=(const Transport&) = default;
  Transport& operator=(Transport&&) = default;
};

// The name of the message an envelope's `kind` oneof holds, e.g.
// "ListBodies"; "an empty message" when none.
std::string kind_name(const google::protobuf::Message& envelope);

// The reply kind the protocol pairs with a request kind; KIND_NOT_SET when
// any reply that echoes the request id will do.
tumble::v1::ServerMessage::KindCase expected_reply(tumble::v1::ClientMessage::KindCase request);

// The request id a reply echoes; 0 for messages that are not replies.
std::uint64_t echoed_request_id(const tumble::v1::ServerMessage& message);

}  // namespace tumble::client
