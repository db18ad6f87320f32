// The TCP stream under the server's side of a WebSocket, checking each frame
// header the client sends for what Boost.Beast leaves unchecked: a 64-bit
// payload length whose most significant bit is set, which RFC 6455 section
// 5.2 forbids (Beast would go on to read a payload of 2^63 bytes). The bytes
// are watched as they are read, never changed: the frames before such a
// header are delivered, and the read after them fails with
// TransportError::illegal_frame_length, and with it the WebSocket stream
// above (net/websocket_transport.h).
//
// Thread: the I/O thread only.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>

#include <boost/beast/core/role.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/websocket/teardown.hpp>

#include "net/asio.h"
#include "net/transport.h"

namespace tumble::net {

// Follows the frames of a client's WebSocket byte stream (RFC 6455 5.2):
// reads each header and skips the payload it announces.
class FrameHeaderScanner {
 public:
  // Takes the next `size` bytes of the stream. Returns how many of them
  // come before a header with an illegal length (`size` when there is
  // none); once one is seen, illegal() is true and the stream cannot be
  // followed past it.
  std::size_t scan(const unsigned char* data, std::size_t size);

  bool illegal() const { return illegal_; }

 private:
  std::array<unsigned char, 14> header_{};  // the header being read: at most 2 + 8 + 4 (mask) bytes
  std::size_t header_bytes_ = 0;            // bytes of it read so far
  std::size_t header_size_ = 2;             // its size, known once its first 2 bytes are
  std::uint64_t payload_left_ = 0;          // bytes of the current frame's payload still to skip
  bool illegal_ = false;
};

class CheckedTcpStream : public boost::beast::tcp_stream {
 public:
  explicit CheckedTcpStream(boost::beast::tcp_stream&& stream) : boost::beast::tcp_stream(std::move(stream)) {}

  // tcp_stream's read, with the bytes that came scanned before the handler
  // runs: those before an illegal header are delivered, and the read that
  // would deliver it fails.
  template <class MutableBuffers, class ReadHandler>
  void async_read_some(const MutableBuffers& buffers, ReadHandler&& handler) {
    if (scanner_.illegal()) {
      boost::asio::post(get_executor(), [handler = std::forward<ReadHandler>(handler)]() mutable {
        std::move(handler)(make_error_code(TransportError::illegal_frame_length), std::size_t{0});
      });
      return;
    }
    boost::beast::tcp_stream::async_read_some(buffers, [this, buffers, handler = std::forward<ReadHandler>(handler)](
                                                           boost::system::error_code error, std::size_t bytes) mutable {
      if (!error) {
        bytes = scan(buffers, bytes);
        if (bytes == 0 && scanner_.illegal()) error = make_error_code(TransportError::illegal_frame_length);
      }
      std::move(handler)(error, bytes);
    });
  }

 private:
  // How many of the `bytes` read into `buffers` come before an illegal header.
  template <class MutableBuffers>
  std::size_t scan(const MutableBuffers& buffers, std::size_t bytes) {
    std::size_t legal = 0;
    for (auto it = boost::asio::buffer_sequence_begin(buffers);
         bytes > 0 && it != boost::asio::buffer_sequence_end(buffers); ++it) {
      const boost::asio::mutable_buffer piece = *it;
      const std::size_t size = std::min(bytes, piece.size());
      legal += scanner_.scan(static_cast<const unsigned char*>(piece.data()), size);
      if (scanner_.illegal()) break;
      bytes -= size;
    }
    return legal;
  }

  FrameHeaderScanner scanner_;
};

// The WebSocket stream tears a CheckedTcpStream down as it does its socket.
template <class TeardownHandler>
void async_teardown(boost::beast::role_type role, CheckedTcpStream& stream, TeardownHandler&& handler) {
  boost::beast::websocket::async_teardown(role, stream.socket(), std::forward<TeardownHandler>(handler));
}

}  // namespace tumble::net
