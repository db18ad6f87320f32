// A Session's stream over a WebSocket (RFC 6455, Boost.Beast): the protocol's
// byte stream carried in binary messages. The payloads of the messages a
// client sends, concatenated, are read exactly as the bytes of a TCP
// connection, wherever the message boundaries fall (a client may send one
// frame per message, or split a frame over several); each write of the
// Session goes out as one binary message, which may hold several frames. A
// text message is refused (TransportError::text_message). When the Session
// closes after an Error, the close frame carries the Error's sentence with
// code 1008 (policy violation), or 1009 (message too big) for a frame over
// the size limit. A message may be of any size: its payload is streamed, and
// the Session bounds each frame in it.
//
// A frame header with an illegal 64-bit length (net/checked_tcp_stream.h)
// is reported as TransportError::illegal_frame_length. Beast's stream has
// failed by then, so what the Session still writes (its Error) goes onto the
// socket in frames made here, and the close frame carries code 1002
// (protocol error) with the reason, followed by a TCP FIN.
//
// Thread: the I/O thread only.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/websocket/stream.hpp>

#include "net/asio.h"
#include "net/checked_tcp_stream.h"
#include "net/transport.h"

namespace tumble::net {

class WebSocketTransport final : public Transport {
 public:
  using Stream = boost::beast::websocket::stream<CheckedTcpStream>;
  using UpgradeRequest = boost::beast::http::request<boost::beast::http::empty_body>;

  // Takes a connection whose HTTP request asked for a WebSocket upgrade;
  // call async_accept() with that request before anything else.
  explicit WebSocketTransport(boost::beast::tcp_stream stream);

  // Answers the upgrade request (101 Switching Protocols, or a 400 for a
  // malformed upgrade, then an error). The opening and the closing
  // handshakes each have 10 s.
  void async_accept(const UpgradeRequest& request, DoneHandler handler);

  void async_read_some(boost::asio::mutable_buffer buffer, ReadHandler handler) override;
  void async_write(const std::vector<boost::asio::const_buffer>& buffers, DoneHandler handler) override;
  // Sends a close frame with the code of `cause` (or 1002 after an illegal
  // frame) and `reason` (cut to the 123 bytes a close frame holds); the read
  // under way ends when the peer's close frame comes. Completes at once when
  // the WebSocket is already closing.
  void async_shutdown(ShutdownCause cause, const std::string& reason, DoneHandler handler) override;
  void close() override;
  const std::string& peer() const override { return peer_; }
  const char* kind() const override { return "WebSocket"; }
  // One unfragmented, unmasked frame a write (RFC 6455 section 5.2): 2 bytes
  // of header, 2 more for a payload of 126 to 65535 bytes, 8 more beyond.
  std::size_t wire_size(std::size_t payload) const override {
    return payload + 2 + (payload > 65535 ? 8 : payload >= 126 ? 2 : 0);
  }

 private:
  // After an illegal frame: writes `payload` in one unmasked frame of
  // `opcode` straight onto the socket (Beast's stream has failed).
  void async_write_raw(unsigned char opcode, const std::vector<boost::asio::const_buffer>& payload,
                       DoneHandler handler);

  Stream ws_;
  std::string peer_;
  bool refused_text_ = false;                           // a text message was reported; later reads just drain
  bool broken_ = false;                                 // the client sent an illegal frame: Beast's stream has failed
  std::array<unsigned char, 10> raw_header_{};          // the header of the frame async_write_raw is writing
  std::vector<boost::asio::const_buffer> raw_buffers_;  // that frame's header and payload
  std::string raw_close_payload_;                       // a close frame's code and reason, while written
};

// `reason` cut to at most `max_bytes`, never inside a UTF-8 sequence.
std::string truncate_utf8(const std::string& reason, std::size_t max_bytes);

}  // namespace tumble::net
