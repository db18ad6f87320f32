// An HTTP/1.1 client for the HTTP endpoint's tests: sends exact bytes on one
// TCP connection and reads whole responses with Boost.Beast's parser, each
// wait bounded. Knows nothing of the server's HTTP code.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>

#include "net/asio.h"

namespace tumble::test {

using HttpResponse = boost::beast::http::response<boost::beast::http::string_body>;

class HttpClient {
 public:
  // Connects to 127.0.0.1:port; check connected().
  explicit HttpClient(std::uint16_t port);
  ~HttpClient();
  HttpClient(const HttpClient&) = delete;
  HttpClient& operator=(const HttpClient&) = delete;

  bool connected() const { return connected_; }

  // Writes all of `bytes`; false if the connection is gone.
  bool send_bytes(const std::string& bytes);

  // Sends "METHOD TARGET HTTP/1.1" with a Host header and `extra_headers`
  // (each line ending in "\r\n").
  bool send_request(const std::string& method, const std::string& target, const std::string& extra_headers = "");

  // The next whole response, or nullopt on timeout, close or bytes that are
  // not HTTP. `to_head`: it answers a HEAD request, so no body follows.
  std::optional<HttpResponse> read_response(bool to_head = false,
                                            std::chrono::milliseconds timeout = std::chrono::seconds(10));

  // True when the server closes the connection within `timeout`; whatever
  // arrives first is discarded.
  bool closed_by_server(std::chrono::milliseconds timeout = std::chrono::seconds(10));

  // Every byte the server sends until it closes the connection (those a
  // read_response() left over first), or nullopt when it does not close
  // within `timeout`: for what follows a WebSocket upgrade, byte for byte.
  std::optional<std::string> bytes_until_closed(std::chrono::milliseconds timeout = std::chrono::seconds(10));

 private:
  boost::asio::io_context io_;
  boost::beast::tcp_stream stream_{io_};
  boost::beast::flat_buffer buffer_;
  std::uint16_t port_;
  bool connected_ = false;
};

// One request on a fresh connection: its response, or nullopt.
std::optional<HttpResponse> http_request(std::uint16_t port, const std::string& method, const std::string& target,
                                         const std::string& extra_headers = "");

}  // namespace tumble::test
