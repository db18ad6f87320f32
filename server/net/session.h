// One client connection: reads frames, checks them, forwards requests to the
// sim or the publisher, and writes replies and pose frames back. The bytes
// travel over a Transport, a TCP socket or a WebSocket; every rule below is
// the same for both.
//
// Lifecycle: the first frame must be Hello (answered by Welcome); any other
// first message, no Hello within the handshake timeout, a token the server
// does not accept, a frame over the size limit or bytes that are not a
// ClientMessage get an Error and the connection is closed once the Error is
// written. A request that is merely wrong (unknown body, NaN force), over the
// client's rate, or beyond its role gets an Error and the session goes on,
// unless the client draws Errors faster than its error budget allows: then
// one RESOURCE_EXHAUSTED says so and the connection is closed, so a stream of
// junk costs a few replies, not one per request. After Hello, a frame whose
// first byte has arrived must arrive whole within frame_timeout (a client
// idle between frames is not affected), else MALFORMED_FRAME and a close. A
// client that lets more than max_pending_bytes of replies pile up unread, or
// leaves anything undelivered for longer than max_undelivered, is
// disconnected.
//
// Thread: everything runs on the I/O thread; the sim's replies are posted
// to it. The Session is owned by shared_ptrs held by its pending I/O and by
// the Server's registry.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "net/access.h"
#include "net/asio.h"
#include "net/net_counters.h"
#include "net/outbound_queue.h"
#include "net/token_bucket.h"
#include "net/transport.h"
#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::sim {
class Simulation;
}

namespace tumble::net {

class Publisher;

// Limits that apply to every session.
struct SessionLimits {
  std::size_t max_frame_bytes = wire::kDefaultMaxFrameBytes;  // largest inbound frame
  std::size_t max_pending_bytes = std::size_t{8} << 20;       // unsent replies before disconnect
  // How long a reply or frame may wait to be taken by the client before it is disconnected.
  std::chrono::steady_clock::duration max_undelivered = std::chrono::seconds(10);
  // How long a new connection may take to send Hello.
  std::chrono::steady_clock::duration handshake_timeout = std::chrono::seconds(10);
  double commands_per_second = 1000;  // requests after Hello, on average; > 0
  double command_burst = 1000;        // requests at once, before the rate applies; >= 1
  // How long a frame may take to arrive once its first byte has, after Hello.
  std::chrono::steady_clock::duration frame_timeout = std::chrono::seconds(10);
  double errors_per_second = 100;  // Errors a client may draw, on average, before it is closed; > 0
  double error_burst = 100;        // Errors at once, before the rate applies; >= 1
};

// What a session needs from the server that made it.
struct SessionContext {
  boost::asio::io_context& io;
  sim::Simulation& sim;
  Publisher& publisher;
  SessionLimits limits;
  std::string server_version;
  AccessTokens access;
  NetCounters& counters;  // the server's; each session counts itself and what it writes
};

class Session : public std::enable_shared_from_this<Session> {
 public:
  using ClosedFn = std::function<void(std::uint64_t session_id)>;

  Session(std::unique_ptr<Transport> transport, std::uint64_t id, SessionContext& context, ClosedFn on_closed);
  ~Session();

  // Starts reading. Call once, after the Session is owned by a shared_ptr.
  void start();

  // Queues a reply or error; never dropped.
  void send(const tumble::v1::ServerMessage& message);

  // Queues a pose frame of `stream`, replacing an unsent older one.
  void send_frame(std::uint32_t stream, std::shared_ptr<const std::string> bytes);

  // Queues a DELTA stream's frame, replacing an unsent older one; it is
  // encoded against this client's last frame of the stream when written.
  void send_delta_frame(std::uint32_t stream, std::shared_ptr<const QuantizedFrame> frame);

  // Closes the connection now, logging `reason`.
  void close(const std::string& reason);

  // Instead of start(), for a connection the server will not serve: writes
  // an Error of `code` and `text`, then closes, reading no request. Logged
  // at debug level only: the server counts refusals and logs their number.
  void refuse(tumble::v1::ErrorCode code, const std::string& text);

  // Disconnects the client if a deadline has passed at `now`: no Hello
  // within the handshake timeout (HANDSHAKE_REQUIRED), a frame begun longer
  // than frame_timeout ago and still incomplete (MALFORMED_FRAME), or a
  // reply or frame undelivered for longer than max_undelivered. The server
  // calls it periodically.
  void enforce_deadlines(std::chrono::steady_clock::time_point now);

  std::uint64_t id() const { return id_; }
  const std::string& peer() const { return peer_; }

 private:
  void read_more();
  void on_read(const boost::system::error_code& error, std::size_t bytes);
  // False when the connection must stop reading.
  bool handle_frame(std::string_view body);
  // False (and the request answered with an Error) when it is over the
  // client's rate or beyond its role.
  bool admit(const tumble::v1::ClientMessage& message);
  void handle_request(tumble::v1::ClientMessage message);
  // Sends the sim's reply to a request, adding the network's figures to a Stats.
  void send_reply(tumble::v1::ServerMessage reply);
  void handle_hello(const tumble::v1::ClientMessage& message);
  void handle_subscribe(const tumble::v1::ClientMessage& message);
  void handle_unsubscribe(const tumble::v1::ClientMessage& message);
  void handle_key_frame_request(const tumble::v1::ClientMessage& message);
  // Answers a request with an Error, charged to the client's error budget;
  // over budget, the session fails with RESOURCE_EXHAUSTED instead.
  void send_error(std::uint64_t request_id, tumble::v1::ErrorCode code, const std::string& text);
  // Takes one Error from the budget; false (and the session failing) when it is spent.
  bool charge_error();
  // Queues an Error whatever the budget.
  void queue_error(std::uint64_t request_id, tumble::v1::ErrorCode code, const std::string& text);
  // Logs, sends an error, stops reading and closes once everything queued is written.
  void fail(tumble::v1::ErrorCode code, const std::string& text, std::uint64_t request_id = 0);
  // fail() without its log line.
  void stop_with_error(tumble::v1::ErrorCode code, const std::string& text, std::uint64_t request_id);
  void write_more();
  void on_written(const boost::system::error_code& error);
  // After a refusal: the Error is written, so half-close and read until the
  // peer closes (or a grace period ends). Closing with unread input would
  // send a reset that can destroy the Error before the client reads it.
  void linger();
  void linger_read();

  std::unique_ptr<Transport> transport_;
  const std::uint64_t id_;
  SessionContext& context_;
  ClosedFn on_closed_;
  std::string peer_;
  std::string client_name_;

  wire::FrameReader reader_;
  std::array<char, 64 * 1024> read_buffer_{};
  bool greeted_ = false;
  bool reading_stopped_ = false;
  bool read_in_flight_ = false;  // a read is under way (its handler has not run)
  bool closed_ = false;
  const std::chrono::steady_clock::time_point connected_at_;
  tumble::v1::Role role_ = tumble::v1::ROLE_UNSPECIFIED;  // set by the Hello
  TokenBucket command_budget_;                            // requests this client may still send now
  bool rate_limited_ = false;       // the last request was refused for its rate (logged once per episode)
  TokenBucket error_budget_;        // Errors this client may still draw now
  bool closed_for_errors_ = false;  // the budget ran out: the session is closing, and sends no more Errors
  // When the first byte of the frame reader_ holds in part arrived; empty between frames.
  std::optional<std::chrono::steady_clock::time_point> frame_begun_at_;

  OutboundQueue outbound_;
  OutboundQueue::Batch in_flight_;
  std::vector<boost::asio::const_buffer> write_buffers_;
  bool writing_ = false;
  std::chrono::steady_clock::time_point queued_since_;     // when the oldest entry in outbound_ was queued
  std::chrono::steady_clock::time_point in_flight_since_;  // when the oldest entry in in_flight_ was queued
  bool close_when_flushed_ = false;
  bool shut_down_ = false;  // linger() has ended the sending side: nothing more is written
  std::string close_reason_;
  tumble::v1::ErrorCode close_code_ = tumble::v1::ERROR_CODE_UNSPECIFIED;  // the Error a failed session ended with
  boost::asio::steady_timer linger_timer_;
};

}  // namespace tumble::net
