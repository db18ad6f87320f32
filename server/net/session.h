// One client connection: reads frames, checks them, forwards requests to the
// sim or the publisher, and writes replies and pose frames back.
//
// Lifecycle: the first frame must be Hello (answered by Welcome); any other
// first message, a frame over the size limit or bytes that are not a
// ClientMessage get an Error and the connection is closed once the Error is
// written. A request that is merely wrong (unknown body, NaN force) gets an
// Error and the session goes on. A client that lets more than
// max_pending_bytes of replies pile up unread is disconnected.
//
// Thread: everything runs on the I/O thread; the sim's replies are posted
// to it. The Session is owned by shared_ptrs held by its pending I/O and by
// the Server's registry.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "net/asio.h"
#include "net/outbound_queue.h"
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
};

// What a session needs from the server that made it.
struct SessionContext {
  boost::asio::io_context& io;
  sim::Simulation& sim;
  Publisher& publisher;
  SessionLimits limits;
  std::string server_version;
};

class Session : public std::enable_shared_from_this<Session> {
 public:
  using ClosedFn = std::function<void(std::uint64_t session_id)>;

  Session(boost::asio::ip::tcp::socket socket, std::uint64_t id, SessionContext& context, ClosedFn on_closed);

  // Starts reading. Call once, after the Session is owned by a shared_ptr.
  void start();

  // Queues a reply or error; never dropped.
  void send(const tumble::v1::ServerMessage& message);

  // Queues a pose frame of `stream`, replacing an unsent older one.
  void send_frame(std::uint32_t stream, std::shared_ptr<const std::string> bytes);

  // Closes the connection now, logging `reason`.
  void close(const std::string& reason);

  std::uint64_t id() const { return id_; }
  const std::string& peer() const { return peer_; }

 private:
  void read_more();
  void on_read(const boost::system::error_code& error, std::size_t bytes);
  // False when the connection must stop reading.
  bool handle_frame(std::string_view body);
  void handle_request(tumble::v1::ClientMessage message);
  void handle_hello(const tumble::v1::ClientMessage& message);
  void handle_subscribe(const tumble::v1::ClientMessage& message);
  void handle_unsubscribe(const tumble::v1::ClientMessage& message);
  void send_error(std::uint64_t request_id, tumble::v1::ErrorCode code, const std::string& text);
  // Sends an error, stops reading and closes once everything queued is written.
  void fail(tumble::v1::ErrorCode code, const std::string& text, std::uint64_t request_id = 0);
  void write_more();
  void on_written(const boost::system::error_code& error);
  // After a refusal: the Error is written, so half-close and read until the
  // peer closes (or a grace period ends). Closing with unread input would
  // send a reset that can destroy the Error before the client reads it.
  void linger();
  void linger_read();

  boost::asio::ip::tcp::socket socket_;
  const std::uint64_t id_;
  SessionContext& context_;
  ClosedFn on_closed_;
  std::string peer_;
  std::string client_name_;

  wire::FrameReader reader_;
  std::array<char, 64 * 1024> read_buffer_{};
  bool greeted_ = false;
  bool reading_stopped_ = false;
  bool closed_ = false;

  OutboundQueue outbound_;
  OutboundQueue::Batch in_flight_;
  std::vector<boost::asio::const_buffer> write_buffers_;
  bool writing_ = false;
  bool close_when_flushed_ = false;
  std::string close_reason_;
  boost::asio::steady_timer linger_timer_;
};

}  // namespace tumble::net
