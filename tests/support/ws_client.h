// A WebSocket client for protocol tests, with Boost.Beast's client side:
// connects to ws://127.0.0.1:PORT/ws, sends bytes in binary (or text)
// messages, and reads the payloads of the server's messages as one byte
// stream of protocol frames, as RawClient reads TCP. Runs on a private
// io_context so that every wait has a deadline.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/websocket/stream.hpp>

#include "frame_client.h"
#include "net/asio.h"
#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::test {

class WsClient : public FrameClient {
 public:
  // Connects and makes the opening handshake for /ws, with an Origin
  // header when `origin` is not empty; check connected().
  explicit WsClient(std::uint16_t port, const std::string& origin = "");
  ~WsClient();
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  // True once the server accepted the WebSocket handshake.
  bool connected() const { return connected_; }
  // The HTTP status of the server's answer to the handshake (101 when accepted; 0 when none came).
  unsigned handshake_status() const { return handshake_status_; }

  // Sends `bytes` as one binary message; false if the connection is gone.
  bool send_bytes(const std::string& bytes) override;
  using FrameClient::send;
  // Sends `text` as one text message.
  bool send_text(const std::string& text);

  // Sends Hello (with `token` when not empty) and returns the server's reply.
  std::optional<tumble::v1::ServerMessage> handshake(const std::string& name = "ws-test",
                                                     const std::string& token = "");

  // True when the server ends the connection within `timeout`; messages
  // that arrive first are skipped.
  bool closed_by_server(std::chrono::milliseconds timeout = std::chrono::seconds(10));

  // True once the server's close frame has been read (not just a dropped connection).
  bool got_close_frame() const { return got_close_frame_; }
  // The code and reason of the server's close frame.
  const boost::beast::websocket::close_reason& close_reason() const { return close_reason_; }

  // WebSocket messages received so far.
  std::size_t messages_received() const { return messages_received_; }

  // Drops the TCP connection without a closing handshake, as a client that
  // crashed or lost its network would.
  void vanish();

 private:
  // Reads one more message into reader_; false on timeout or close.
  bool fill(Clock::time_point deadline) override;
  bool write(const std::string& bytes, bool text);

  boost::asio::io_context io_;
  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_{io_};
  boost::beast::flat_buffer message_;
  bool connected_ = false;
  unsigned handshake_status_ = 0;
  bool read_pending_ = false;  // a message read is under way (it outlives a timed-out fill)
  bool read_done_ = false;
  boost::system::error_code read_error_;
  bool ended_ = false;  // the connection is over: closed by either side, or failed
  bool got_close_frame_ = false;
  boost::beast::websocket::close_reason close_reason_;
  std::size_t messages_received_ = 0;
};

}  // namespace tumble::test
