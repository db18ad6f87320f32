// Connection: one session with a tumbled server, driven by blocking calls.
//
// A Connection owns its socket. Every call blocks the calling thread until
// it is done, fails, or its timeout passes; there are no background threads.
// It is not thread-safe: use it from one thread at a time. It never prints.
//
// Replies, pose frames and world events share the stream, so while request()
// waits for its reply it queues the frames and events that arrive first;
// next_message() hands them over in order. Replies that match no pending request (the late answer
// to a request that timed out) are dropped.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "tumble/endpoint.h"
#include "tumble/v1/protocol.pb.h"
#include "tumble_client/result.h"

namespace tumble::client {

// How long a call may block. Negative timeouts count as zero.
using Timeout = std::chrono::steady_clock::duration;

// A timeout that never passes.
inline constexpr Timeout kWaitForever = Timeout::max();

// The timeout of a request unless the caller chooses another.
inline constexpr Timeout kDefaultRequestTimeout = std::chrono::seconds(10);

// The largest frame accepted from the server, in bytes (64 MiB): a
// BodyList page of a server with a large --max-pending-bytes is big (1 MiB
// by default). A larger frame breaks the connection.
inline constexpr std::size_t kMaxInboundFrameBytes = std::size_t{64} << 20;

class Connection {
 public:
  // Resolves the endpoint, opens a TCP connection and shakes hands: sends
  // Hello{PROTOCOL_VERSION_CURRENT, client_name, token} and waits for
  // Welcome. `timeout` bounds all of it. Fails with kind connect (cannot
  // resolve or reach), timeout, closed, protocol, or server (the server
  // refused the Hello with an Error: UNAUTHENTICATED for a missing or wrong
  // token, RESOURCE_EXHAUSTED when it is full). `token` is the server's
  // controller or observer token, or empty when it asks for none;
  // welcome().role() tells which role the connection got.
  static Result<Connection> connect(const Endpoint& endpoint, const std::string& client_name, const std::string& token,
                                    Timeout timeout);

  Connection(Connection&& other) noexcept;
  Connection& operator=(Connection&& other) noexcept;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  // Closes the socket. Queued messages are discarded.
  ~Connection();

  // What the server said when it accepted the connection.
  const tumble::v1::Welcome& welcome() const;

  // The endpoint this connection was opened to.
  const Endpoint& endpoint() const;

  // Sends `message` with the next request id (1, 2, 3, ...; whatever
  // request_id it holds is replaced) and waits up to `timeout` for the reply
  // that echoes it. Returns that reply: Ack, BodyList, Subscribed or Stats,
  // checked against the request's kind. Fails with kind server when the reply is an
  // Error, or when a connection-level Error (request_id 0) arrives first;
  // with kind timeout when no reply came in time (the connection stays
  // usable, unless the request itself could not be sent in time); with
  // closed or protocol when the stream ended or broke.
  Result<tumble::v1::ServerMessage> request(tumble::v1::ClientMessage message, Timeout timeout);

  // The requests of the protocol, each returning the reply's payload. Same
  // failures as request().
  Result<tumble::v1::Ack> apply_force(const tumble::v1::ApplyForce& force, Timeout timeout);
  Result<tumble::v1::Ack> apply_torque(const tumble::v1::ApplyTorque& torque, Timeout timeout);
  Result<tumble::v1::Ack> apply_impulse(const tumble::v1::ApplyImpulse& impulse, Timeout timeout);
  // Every body, page after page (ListBodies from each page's next_start_id
  // until it is 0), as one BodyList: bodies in ascending id order, `tick`
  // and `total_bodies` those of the last page, next_start_id 0. `timeout`
  // bounds each page.
  Result<tumble::v1::BodyList> list_bodies(Timeout timeout);
  // One page: the bodies from `start_id` on, at most `max_bodies` (0: as
  // many as the server's page holds).
  Result<tumble::v1::BodyList> list_bodies_page(std::uint32_t start_id, std::uint32_t max_bodies, Timeout timeout);
  Result<tumble::v1::Subscribed> subscribe(const tumble::v1::Subscribe& subscribe, Timeout timeout);
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

  // The next unsolicited message: a PoseFrame or WorldEvent (of any
  // subscription) or a connection-level Error (request_id 0; the server
  // usually closes after it). Returns a queued one at once, else waits up to `timeout`. Fails
  // with kind timeout when nothing came in time (the connection stays
  // usable), closed when the server closed the connection, or protocol.
  Result<tumble::v1::ServerMessage> next_message(Timeout timeout);

  // next_message() without waiting: a queued message, or the next one whose
  // bytes have all arrived. Fails with kind timeout when none is whole yet
  // (the connection stays usable; a partial frame stays buffered), closed
  // or protocol as next_message() does. For a caller that waits on many
  // connections at once (poll(2) on native_handle()): messages may be
  // queued, so call it until it times out before waiting again.
  Result<tumble::v1::ServerMessage> poll_message();

  // The socket's descriptor, to wait on with poll(2) or epoll; the
  // Connection still owns it: do not read from it or close it.
  int native_handle();

 private:
  struct State;
  explicit Connection(std::unique_ptr<State> state);

  std::unique_ptr<State> state_;  // null only in a moved-from Connection
};

}  // namespace tumble::client
