// The byte stream under a Session: a plain TCP socket (net/tcp_transport.h)
// or a WebSocket over TCP (net/websocket_transport.h). A Session speaks the
// same protocol over either; the transport only moves bytes, so every rule
// of the protocol (handshake, tokens, limits, latest-wins frames) is the
// Session's and holds the same for both.
//
// Contract: at most one read and one write (or shutdown) under way at a
// time; the buffers passed in stay valid until their handler runs; handlers
// run on the I/O thread, never from inside the call that started them.
// After close() every pending operation completes with an error.
//
// Thread: the I/O thread only.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <system_error>
#include <vector>

#include "net/asio.h"

namespace tumble::net {

// Why a Session ends its stream, for a transport that can tell the peer (a
// WebSocket close code).
enum class ShutdownCause {
  refused,    // the client broke a rule or a limit, or was refused: 1008 (policy violation)
  too_large,  // the client announced a frame over the size limit: 1009 (message too big)
};

class Transport {
 public:
  using ReadHandler = std::function<void(const boost::system::error_code& error, std::size_t bytes)>;
  using DoneHandler = std::function<void(const boost::system::error_code& error)>;

  virtual ~Transport() = default;

  // Reads some bytes of the stream into `buffer`, or completes with an
  // error: asio::error::eof when the peer ended the stream (a FIN, a
  // WebSocket close frame), a socket error, or a TransportError.
  virtual void async_read_some(boost::asio::mutable_buffer buffer, ReadHandler handler) = 0;

  // Writes all of `buffers`, in order. A WebSocket sends them as one binary
  // message.
  virtual void async_write(const std::vector<boost::asio::const_buffer>& buffers, DoneHandler handler) = 0;

  // The bytes an async_write of `payload` bytes puts on the connection:
  // the payload, and for a WebSocket its frame's header.
  virtual std::size_t wire_size(std::size_t payload) const = 0;

  // Ends the outgoing direction after what was written: a TCP FIN, or a
  // WebSocket close frame that carries `cause` as its code and `reason`.
  // Reading goes on until the peer closes its side too. Nothing may be
  // written after it.
  virtual void async_shutdown(ShutdownCause cause, const std::string& reason, DoneHandler handler) = 0;

  // Closes the connection at once.
  virtual void close() = 0;

  // "ADDRESS:PORT" of the peer, "unknown" when the socket could not tell.
  virtual const std::string& peer() const = 0;

  // What the stream is, for the log: "TCP" or "WebSocket".
  virtual const char* kind() const = 0;
};

// Errors of a transport's own, beside the socket's: the peer broke the
// transport's rules, not the socket. A Session answers one with an Error
// and closes, as it does a malformed frame.
enum class TransportError {
  text_message = 1,          // a WebSocket text message: the protocol is carried in binary messages only
  illegal_frame_length = 2,  // a WebSocket frame's 64-bit length with its top bit set (RFC 6455 5.2)
};

const boost::system::error_category& transport_category();
boost::system::error_code make_error_code(TransportError error);

}  // namespace tumble::net

template <>
struct boost::system::is_error_code_enum<tumble::net::TransportError> : std::true_type {};
