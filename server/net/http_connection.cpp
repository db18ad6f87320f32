#include "net/http_connection.h"

#include <utility>

#include <boost/beast/http/error.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/write.hpp>
#include <boost/beast/websocket/rfc6455.hpp>

#include <spdlog/fmt/fmt.h>

#include "net/ascii_case.h"
#include "net/log.h"
#include "net/static_assets.h"
#include "net/tcp_transport.h"
#include "net/websocket_transport.h"
#include "sim/log_text.h"

namespace tumble::net {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;

namespace {

// The path WebSocket clients connect to.
constexpr std::string_view kWebSocketPath = "/ws";

// How long linger() waits for the client to close its side.
constexpr auto kLingerTimeout = std::chrono::seconds(2);

// True unless the request comes from a web page of another origin than
// this server's. Browsers send Origin with every WebSocket handshake and
// let any page open one to any address, so without this check any site a
// user visits could drive the world through the user's browser
// (cross-site WebSocket hijacking). Clients that are not browsers send no
// Origin and are let through; the token decides for them as for TCP.
bool same_origin(const http::request_header<>& request) {
  const std::string_view origin = request[http::field::origin];
  if (origin.empty()) return true;
  const std::string_view host = request[http::field::host];
  for (const std::string_view scheme : {std::string_view("http://"), std::string_view("https://")}) {
    if (origin.size() > scheme.size() && equal_ignoring_ascii_case(origin.substr(0, scheme.size()), scheme)) {
      return !host.empty() && equal_ignoring_ascii_case(origin.substr(scheme.size()), host);
    }
  }
  return false;  // "null" (a file:// page) and other schemes
}

std::string_view path_of(std::string_view target) { return target.substr(0, target.find('?')); }

// A header's value as a response and the log may quote it: printable ASCII
// only, at most 64 characters.
std::string quotable(std::string_view value) {
  constexpr std::size_t kMaxQuoted = 64;
  std::string quoted;
  for (const char c : value.substr(0, kMaxQuoted)) quoted += c >= 0x20 && c < 0x7F ? c : '?';
  if (value.size() > kMaxQuoted) quoted += "...";
  return quoted;
}

// An error of the HTTP parser: the bytes were not an HTTP request.
bool is_parse_error(const boost::system::error_code& error) {
  return error.category() == http::make_error_code(http::error::bad_method).category();
}

}  // namespace

HttpConnection::HttpConnection(asio::ip::tcp::socket socket, std::uint64_t id,
                               std::chrono::steady_clock::duration header_timeout,
                               std::shared_ptr<const AllowedHosts> allowed_hosts, UpgradeFn on_websocket,
                               ClosedFn on_closed)
    : stream_(std::move(socket)),
      id_(id),
      header_timeout_(header_timeout),
      allowed_hosts_(std::move(allowed_hosts)),
      header_timer_(stream_.get_executor()),
      on_websocket_(std::move(on_websocket)),
      on_closed_(std::move(on_closed)),
      peer_(peer_of(stream_.socket())) {
  boost::system::error_code ignored;
  stream_.socket().set_option(asio::ip::tcp::no_delay(true), ignored);
}

HttpConnection::~HttpConnection() = default;

void HttpConnection::start() {
  net_log().debug("http {}: connected from {}", id_, peer_);
  read_request();
}

void HttpConnection::read_request() {
  if (closed_) return;
  parser_.emplace();
  parser_->header_limit(static_cast<std::uint32_t>(kMaxHeaderBytes));
  // The deadline is a timer of its own, not the stream's: the stream's
  // closes the socket, and a request that began late is answered with 408.
  stream_.expires_never();
  header_timed_out_ = false;
  header_timer_.expires_after(header_timeout_);
  header_timer_.async_wait(
      [self = shared_from_this()](const boost::system::error_code& error) { self->on_header_timeout(error); });
  // The header only: a body is refused rather than read.
  http::async_read_header(
      stream_, buffer_, *parser_,
      [self = shared_from_this()](const boost::system::error_code& error, std::size_t) { self->on_header(error); });
}

void HttpConnection::on_header_timeout(const boost::system::error_code& error) {
  if (error || closed_) return;  // cancelled: the header came, or the connection is gone
  header_timed_out_ = true;
  stream_.cancel();  // the read ends with operation_aborted, in on_header
}

void HttpConnection::on_header(const boost::system::error_code& error) {
  if (closed_) return;
  header_timer_.cancel();
  if (header_timed_out_) {
    const std::string limit = fmt::format("{:g} s", std::chrono::duration<double>(header_timeout_).count());
    if (buffer_.size() == 0 && !parser_->got_some()) {
      finish("idle for " + limit);  // no request begun: nothing to answer
    } else {
      refuse(http::status::request_timeout, "the request's header did not arrive whole within " + limit, false);
    }
    return;
  }
  if (error == http::error::end_of_stream) {
    finish("client closed the connection");
    return;
  }
  if (error == http::error::header_limit) {
    refuse(http::status::request_header_fields_too_large,
           "the request's header is over the limit of " + std::to_string(kMaxHeaderBytes) + " bytes", false);
    return;
  }
  if (error == http::error::partial_message || (error && !is_parse_error(error))) {
    // The client left in the middle of a request, or the socket failed: nobody to answer.
    finish("read failed: " + error.message());
    return;
  }
  if (error) {
    refuse(http::status::bad_request, "not an HTTP/1.1 request (" + error.message() + ")", false);
    return;
  }
  handle(parser_->get());
}

bool HttpConnection::check_host(const Request& request, bool keep_alive) {
  const auto host = request.find(http::field::host);
  if (host == request.end()) {
    if (request.version() < 11) return true;  // HTTP/1.0 may leave it out; no browser does
    refuse(http::status::bad_request, "an HTTP/1.1 request must have a Host header (RFC 9112 section 3.2)", keep_alive);
    return false;
  }
  if (allowed_hosts_->allows(host->value())) return true;
  refuse(http::status::misdirected_request,
         "this server does not answer to the host name '" + quotable(host->value()) +
             "' (see tumbled's --http-allowed-hosts)",
         false);
  return false;
}

void HttpConnection::handle(const Request& request) {
  request_line_ = std::string(request.method_string()) + " " + std::string(request.target());
  // A body is never read: its bytes would be taken for the next request.
  const bool no_body = parser_->is_done();
  const bool keep_alive = request.keep_alive() && no_body;
  const bool head = request.method() == http::verb::head;
  if (!check_host(request, keep_alive)) return;
  if (request.method() != http::verb::get && !head) {
    refuse(http::status::method_not_allowed, "only GET and HEAD are served here", keep_alive);
    return;
  }
  if (!no_body) {
    refuse(http::status::payload_too_large, "requests with a body are not accepted", false);
    return;
  }
  const std::string_view path = path_of(request.target());
  if (path == kWebSocketPath) {
    if (!beast::websocket::is_upgrade(request)) {
      refuse(http::status::upgrade_required, "this is the WebSocket endpoint: connect with a WebSocket client",
             keep_alive);
      return;
    }
    if (!same_origin(request)) {
      refuse(
          http::status::forbidden,
          "a WebSocket from a page of another origin (" + sim::log_text(request[http::field::origin]) + ") is refused",
          false);
      return;
    }
    upgrade(request);
    return;
  }
  const StaticAsset* asset = find_static_asset(request.target());
  if (!asset) {
    refuse(http::status::not_found, "no such file: " + sim::log_text(path), keep_alive);
    return;
  }
  make_response(http::status::ok, asset->content_type, asset->bytes, head);
  write_response(keep_alive);
}

void HttpConnection::upgrade(const Request& request) {
  if (buffer_.size() != 0) {
    // RFC 6455 4.1: a client waits for the handshake's answer before it sends frames.
    refuse(http::status::bad_request, "data sent before the WebSocket handshake was answered", false);
    return;
  }
  stream_.expires_never();
  upgrading_ = std::make_unique<WebSocketTransport>(std::move(stream_));
  // The request stays in parser_, untouched until the handshake is done.
  upgrading_->async_accept(
      request, [self = shared_from_this()](const boost::system::error_code& error) { self->on_upgraded(error); });
}

void HttpConnection::on_upgraded(const boost::system::error_code& error) {
  if (closed_) return;
  if (error) {
    finish("WebSocket handshake failed: " + error.message());
    return;
  }
  net_log().debug("http {}: {} upgraded to a WebSocket", id_, peer_);
  closed_ = true;
  on_websocket_(std::move(upgrading_));
  if (on_closed_) on_closed_(id_);
}

HttpConnection::Response& HttpConnection::make_response(http::status status, std::string_view content_type,
                                                        std::string_view body, bool head_only) {
  const bool parsed = parser_ && parser_->is_header_done();
  response_.emplace(status, parsed ? parser_->get().version() : 11);
  response_->set(http::field::content_type, content_type);
  response_->set(http::field::cache_control, "no-cache");
  response_->set("X-Content-Type-Options", "nosniff");
  if (!head_only) response_->body() = Response::body_type::value_type(body.data(), body.size());
  // Set by hand, not by prepare_payload(): a HEAD response tells the length of the body it leaves out.
  response_->content_length(body.size());
  return *response_;
}

void HttpConnection::write_response(bool keep_alive) {
  response_->keep_alive(keep_alive);
  net_log().debug("http {}: {} {} -> {}", id_, peer_, sim::log_text(request_line_), response_->result_int());
  stream_.expires_after(kWriteTimeout);
  http::async_write(stream_, *response_,
                    [self = shared_from_this(), keep_alive](const boost::system::error_code& error, std::size_t) {
                      self->on_written(error, keep_alive);
                    });
}

void HttpConnection::refuse(http::status status, std::string text, bool keep_alive) {
  net_log().info("http {}: {} {}: {} {}", id_, peer_,
                 request_line_.empty() ? "(no request line)" : sim::log_text(request_line_),
                 static_cast<unsigned>(status), sim::log_text(text, sim::kLogMessageBytes));
  error_text_ = std::move(text);
  error_text_ += "\n";
  const bool head = parser_ && parser_->is_header_done() && parser_->get().method() == http::verb::head;
  Response& response = make_response(status, "text/plain; charset=utf-8", error_text_, head);
  if (status == http::status::method_not_allowed) response.set(http::field::allow, "GET, HEAD");
  if (status == http::status::upgrade_required) {
    // RFC 7230 6.7: a 426 names the protocol to upgrade to, with "upgrade" in Connection.
    response.set(http::field::upgrade, "websocket");
    response.set(http::field::connection, "upgrade");
  }
  write_response(keep_alive);
}

void HttpConnection::on_written(const boost::system::error_code& error, bool keep_alive) {
  if (closed_) return;
  if (error) {
    finish("write failed: " + error.message());
    return;
  }
  request_line_.clear();
  if (keep_alive) {
    read_request();
  } else {
    linger();
  }
}

void HttpConnection::linger() {
  boost::system::error_code ignored;
  stream_.socket().shutdown(asio::ip::tcp::socket::shutdown_send, ignored);
  stream_.expires_after(kLingerTimeout);  // one deadline for the whole drain
  drain();
}

void HttpConnection::drain() {
  stream_.async_read_some(asio::buffer(drain_buffer_),
                          [self = shared_from_this()](const boost::system::error_code& error, std::size_t) {
                            if (self->closed_) return;
                            if (error) {
                              self->finish("response written; connection closed");
                            } else {
                              self->drain();
                            }
                          });
}

void HttpConnection::finish(const std::string& reason) {
  if (closed_) return;
  net_log().debug("http {}: {} closed: {}", id_, peer_, sim::log_text(reason, sim::kLogMessageBytes));
  close();
}

void HttpConnection::close() {
  if (closed_) return;
  closed_ = true;
  header_timer_.cancel();
  if (upgrading_) {
    upgrading_->close();
  } else {
    boost::system::error_code ignored;
    stream_.socket().shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
    stream_.close();
  }
  if (on_closed_) on_closed_(id_);
}

}  // namespace tumble::net
