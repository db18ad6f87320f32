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
#include "tumble_client/transport.h"

namespace tumble::client {

// The largest frame accepted from the server, in bytes (64 MiB): a
// BodyList page of a server with a large --max-pending-bytes is big (1 MiB
// by default). A larger frame breaks the connection.
inline constexpr std::size_t kMaxInboundFrameBytes = std::size_t{64} << 20;

class Connection final : public Transport {
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
  ~Connection() override;

  // What the server said when it accepted the connection.
  const tumble::v1::Welcome& welcome() const;

  // The endpoint this connection was opened to.
  const Endpoint& endpoint() const;

  // "HOST:PORT".
  std::string describe() const override;

  // Sends `message` with the next request id (1, 2, 3, ...) and waits for
  // the reply that echoes it, as Transport::request() says. A timed-out
  // request leaves the connection usable, unless the request itself could
  // not be sent in time; a connection-level Error (request_id 0) arriving
  // first fails it with kind server.
  Result<tumble::v1::ServerMessage> request(tumble::v1::ClientMessage message, Timeout timeout) override;

  // The next unsolicited message: a PoseFrame or WorldEvent (of any
  // subscription) or a connection-level Error (request_id 0; the server
  // usually closes after it). Returns a queued one at once, else waits up to `timeout`. Fails
  // with kind timeout when nothing came in time (the connection stays
  // usable), closed when the server closed the connection, or protocol.
  Result<tumble::v1::ServerMessage> next_message(Timeout timeout) override;

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
