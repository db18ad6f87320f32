// One HTTP/1.1 connection to the HTTP endpoint (net/http_listener.h).
//
// Serves the embedded files (net/static_assets.h) to GET and HEAD, each
// response with its Content-Type, Content-Length, `Cache-Control: no-cache`
// and `X-Content-Type-Options: nosniff`; keeps the connection alive between
// requests as HTTP/1.1 (and a 1.0 client that asks) expects. A WebSocket
// upgrade of /ws becomes a WebSocketTransport, handed to the server as a new
// client (net/websocket_transport.h); this object is then done.
//
// Refused, each with a short plain-text sentence: an HTTP/1.1 request
// without Host (400, RFC 9112 3.2), a Host that is not one of the allowed
// names (421, net/allowed_hosts.h), an unknown path (404), a method other
// than GET and HEAD (405), /ws without an upgrade (426), a WebSocket
// handshake from a page of another origin (403), headers over
// kMaxHeaderBytes (431), a request with a body (413), bytes that are not
// HTTP (400), a request whose header has begun but not ended within the
// header timeout (408). After a 4xx that leaves unread input, the connection
// is closed once the response is written. A kept-alive connection idle for
// the header timeout is closed without an answer.
//
// Thread: the I/O thread only. Owned by shared_ptrs held by its pending
// operations and by the listener's registry.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/span_body.hpp>
#include <boost/beast/http/status.hpp>

#include "net/allowed_hosts.h"
#include "net/asio.h"
#include "net/transport.h"

namespace tumble::net {

class WebSocketTransport;

// How the HTTP endpoint treats its clients.
struct HttpLimits {
  // HTTP connections at once; a WebSocket client counts as a session once its handshake is done.
  std::size_t max_connections = 64;
  // How long a request's header may take to arrive whole, and an idle kept-alive connection may wait.
  std::chrono::steady_clock::duration header_timeout = std::chrono::seconds(10);
  // The Host names served (net/allowed_hosts.h); empty: AllowedHosts::defaults for the bound address.
  std::vector<std::string> allowed_hosts;
};

// Largest request header accepted, request line included.
inline constexpr std::size_t kMaxHeaderBytes = 8 * 1024;
// How long a response may take to be written.
inline constexpr std::chrono::seconds kWriteTimeout{60};

class HttpConnection : public std::enable_shared_from_this<HttpConnection> {
 public:
  // Takes a WebSocket client that completed its opening handshake.
  using UpgradeFn = std::function<void(std::unique_ptr<Transport>)>;
  using ClosedFn = std::function<void(std::uint64_t connection_id)>;

  // `allowed_hosts` is shared by the listener's connections.
  HttpConnection(boost::asio::ip::tcp::socket socket, std::uint64_t id,
                 std::chrono::steady_clock::duration header_timeout, std::shared_ptr<const AllowedHosts> allowed_hosts,
                 UpgradeFn on_websocket, ClosedFn on_closed);
  ~HttpConnection();

  // Starts reading requests. Call once, after the object is owned by a shared_ptr.
  void start();

  // Closes the connection now (the server is stopping).
  void close();

 private:
  using Request = boost::beast::http::request<boost::beast::http::empty_body>;
  using Response = boost::beast::http::response<boost::beast::http::span_body<const char>>;

  void read_request();
  void on_header(const boost::system::error_code& error);
  // The header timeout passed while a request's header was being read.
  void on_header_timeout(const boost::system::error_code& error);
  // False (and the request refused) when its Host is missing or not allowed.
  bool check_host(const Request& request, bool keep_alive);
  void handle(const Request& request);
  void upgrade(const Request& request);
  void on_upgraded(const boost::system::error_code& error);
  // Makes response_ with the headers every response has and `body`, which
  // must outlive the write (an embedded file, or error_text_). With
  // `head_only` the headers tell the body's length and the body is left out.
  Response& make_response(boost::beast::http::status status, std::string_view content_type, std::string_view body,
                          bool head_only);
  // Writes response_; then reads the next request, or closes.
  void write_response(bool keep_alive);
  // A refusal: `text` and a line break as text/plain.
  void refuse(boost::beast::http::status status, std::string text, bool keep_alive);
  void on_written(const boost::system::error_code& error, bool keep_alive);
  // Half-closes, reads and discards until the peer closes (or a short
  // grace period ends), then closes: closing with unread input would reset
  // the connection and could destroy the response before the client reads it.
  void linger();
  void drain();
  void finish(const std::string& reason);

  boost::beast::tcp_stream stream_;
  const std::uint64_t id_;
  const std::chrono::steady_clock::duration header_timeout_;
  std::shared_ptr<const AllowedHosts> allowed_hosts_;
  boost::asio::steady_timer header_timer_;  // the header timeout of the request being read
  bool header_timed_out_ = false;           // it passed, and the read was cancelled
  UpgradeFn on_websocket_;
  ClosedFn on_closed_;
  std::string peer_;
  boost::beast::flat_buffer buffer_;
  std::optional<boost::beast::http::request_parser<boost::beast::http::empty_body>> parser_;
  std::optional<Response> response_;               // the response being written
  std::string error_text_;                         // the body of a refusal being written
  std::string request_line_;                       // "GET /", for the log
  std::unique_ptr<WebSocketTransport> upgrading_;  // during the WebSocket handshake
  std::array<char, 4096> drain_buffer_{};
  bool closed_ = false;
};

}  // namespace tumble::net
