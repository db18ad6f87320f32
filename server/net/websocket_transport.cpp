#include "net/websocket_transport.h"

#include <chrono>
#include <utility>

#include "net/tcp_transport.h"

namespace tumble::net {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;

namespace {

// How long the opening and the closing handshakes may take.
constexpr auto kHandshakeTimeout = std::chrono::seconds(10);

// A close frame's reason: 125 bytes of payload less the 2 of the code.
constexpr std::size_t kMaxCloseReasonBytes = 123;

}  // namespace

std::string truncate_utf8(const std::string& reason, std::size_t max_bytes) {
  if (reason.size() <= max_bytes) return reason;
  std::size_t end = max_bytes;
  // Back off over continuation bytes (10xxxxxx) to the start of the sequence that was cut.
  while (end > 0 && (static_cast<unsigned char>(reason[end]) & 0xC0) == 0x80) --end;
  return reason.substr(0, end);
}

WebSocketTransport::WebSocketTransport(beast::tcp_stream stream)
    : ws_(CheckedTcpStream(std::move(stream))), peer_(peer_of(beast::get_lowest_layer(ws_).socket())) {
  boost::system::error_code ignored;
  beast::get_lowest_layer(ws_).socket().set_option(asio::ip::tcp::no_delay(true), ignored);
  // The HTTP side's read deadline is over: from here the WebSocket keeps
  // its own handshake deadlines, and the Session the rest.
  beast::get_lowest_layer(ws_).expires_never();
  websocket::stream_base::timeout timeouts;
  timeouts.handshake_timeout = kHandshakeTimeout;
  timeouts.idle_timeout = websocket::stream_base::none();
  timeouts.keep_alive_pings = false;
  ws_.set_option(timeouts);
  ws_.binary(true);
  // A write is one message in one WebSocket frame, its buffers written as they are.
  ws_.auto_fragment(false);
  // No limit on a message's size: read_some streams it, and the Session's
  // frame reader bounds what is held (--max-frame-bytes).
  ws_.read_message_max(0);
}

void WebSocketTransport::async_accept(const UpgradeRequest& request, DoneHandler handler) {
  ws_.async_accept(request, std::move(handler));
}

void WebSocketTransport::async_read_some(asio::mutable_buffer buffer, ReadHandler handler) {
  if (broken_) {
    // Only a Session that is closing reads now, to discard what comes.
    beast::get_lowest_layer(ws_).socket().async_read_some(buffer, std::move(handler));
    return;
  }
  // `this` outlives the read: the Session that owns the transport is kept
  // alive by `handler`.
  ws_.async_read_some(buffer,
                      [this, handler = std::move(handler)](const boost::system::error_code& error, std::size_t bytes) {
                        if (error == TransportError::illegal_frame_length) {
                          broken_ = true;
                          handler(error, 0);
                          return;
                        }
                        if (error == websocket::error::closed) {
                          // The peer's close frame: the end of the stream, as a TCP FIN is.
                          handler(asio::error::eof, bytes);
                          return;
                        }
                        if (!error && !refused_text_ && ws_.got_text()) {
                          refused_text_ = true;
                          handler(TransportError::text_message, 0);
                          return;
                        }
                        handler(error, bytes);
                      });
}

void WebSocketTransport::async_write(const std::vector<asio::const_buffer>& buffers, DoneHandler handler) {
  if (broken_) {
    async_write_raw(0x2, buffers, std::move(handler));  // a binary frame
    return;
  }
  ws_.async_write(
      buffers, [handler = std::move(handler)](const boost::system::error_code& error, std::size_t) { handler(error); });
}

void WebSocketTransport::async_shutdown(ShutdownCause cause, const std::string& reason, DoneHandler handler) {
  if (broken_) {
    // A close frame of code 1002, then a FIN: Beast can no longer do either.
    const std::string text = truncate_utf8(reason, kMaxCloseReasonBytes);
    const auto code = static_cast<std::uint16_t>(websocket::close_code::protocol_error);
    raw_close_payload_ = std::string{static_cast<char>(code >> 8), static_cast<char>(code & 0xFF)} + text;
    async_write_raw(0x8, {asio::buffer(raw_close_payload_)},
                    [this, handler = std::move(handler)](const boost::system::error_code& error) {
                      boost::system::error_code ignored;
                      beast::get_lowest_layer(ws_).socket().shutdown(asio::ip::tcp::socket::shutdown_send, ignored);
                      handler(error);
                    });
    return;
  }
  if (!ws_.is_open()) {
    // The peer's close frame came first (and was answered), or the stream failed.
    asio::post(ws_.get_executor(), [handler = std::move(handler)] { handler({}); });
    return;
  }
  const auto code =
      cause == ShutdownCause::too_large ? websocket::close_code::too_big : websocket::close_code::policy_error;
  const websocket::close_reason close(code, truncate_utf8(reason, kMaxCloseReasonBytes));
  ws_.async_close(close, std::move(handler));
}

void WebSocketTransport::async_write_raw(unsigned char opcode, const std::vector<asio::const_buffer>& payload,
                                         DoneHandler handler) {
  const std::size_t size = asio::buffer_size(payload);
  // RFC 6455 5.2: FIN and the opcode; then the length in 7 bits, or 126 and
  // 16 bits, or 127 and 64 bits; a server's frames are not masked.
  std::size_t header = 0;
  raw_header_[header++] = static_cast<unsigned char>(0x80 | opcode);
  if (size < 126) {
    raw_header_[header++] = static_cast<unsigned char>(size);
  } else if (size <= 0xFFFF) {
    raw_header_[header++] = 126;
    for (int shift = 8; shift >= 0; shift -= 8) raw_header_[header++] = static_cast<unsigned char>(size >> shift);
  } else {
    raw_header_[header++] = 127;
    for (int shift = 56; shift >= 0; shift -= 8) {
      raw_header_[header++] = static_cast<unsigned char>(static_cast<std::uint64_t>(size) >> shift);
    }
  }
  raw_buffers_.clear();
  raw_buffers_.emplace_back(raw_header_.data(), header);
  raw_buffers_.insert(raw_buffers_.end(), payload.begin(), payload.end());
  asio::async_write(
      beast::get_lowest_layer(ws_).socket(), raw_buffers_,
      [handler = std::move(handler)](const boost::system::error_code& error, std::size_t) { handler(error); });
}

void WebSocketTransport::close() {
  boost::system::error_code ignored;
  beast::get_lowest_layer(ws_).socket().shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
  beast::get_lowest_layer(ws_).close();
}

}  // namespace tumble::net
