#include "http_client.h"

#include <array>

#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/read.hpp>

#include "io_wait.h"

namespace tumble::test {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using Clock = std::chrono::steady_clock;

namespace {

// Room for any embedded file.
constexpr std::uint64_t kMaxBodyBytes = std::uint64_t{64} << 20;

}  // namespace

HttpClient::HttpClient(std::uint16_t port) : port_(port) {
  bool done = false;
  boost::system::error_code result;
  stream_.async_connect(asio::ip::tcp::endpoint(asio::ip::address_v4::loopback(), port),
                        [&](const boost::system::error_code& error) {
                          result = error;
                          done = true;
                        });
  connected_ = run_until(io_, done, Clock::now() + std::chrono::seconds(10)) && !result;
}

HttpClient::~HttpClient() {
  stream_.close();
  io_.restart();
  io_.poll();  // lets aborted operations finish while their state still exists
}

bool HttpClient::send_bytes(const std::string& bytes) {
  bool done = false;
  boost::system::error_code result;
  asio::async_write(stream_, asio::buffer(bytes), [&](const boost::system::error_code& error, std::size_t) {
    result = error;
    done = true;
  });
  return run_until(io_, done, Clock::now() + std::chrono::seconds(10)) && !result;
}

bool HttpClient::send_request(const std::string& method, const std::string& target, const std::string& extra_headers) {
  return send_bytes(method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port_) + "\r\n" +
                    extra_headers + "\r\n");
}

std::optional<HttpResponse> HttpClient::read_response(bool to_head, std::chrono::milliseconds timeout) {
  http::response_parser<http::string_body> parser;
  parser.body_limit(kMaxBodyBytes);
  parser.skip(to_head);
  bool done = false;
  boost::system::error_code result;
  http::async_read(stream_, buffer_, parser, [&](const boost::system::error_code& error, std::size_t) {
    result = error;
    done = true;
  });
  if (!run_until(io_, done, Clock::now() + timeout)) {
    stream_.cancel();  // the parser is about to go: stop the read that writes into it
    run_until(io_, done, Clock::now() + std::chrono::seconds(10));
    return std::nullopt;
  }
  if (result) return std::nullopt;
  return parser.release();
}

bool HttpClient::closed_by_server(std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  std::array<char, 4096> discard{};
  for (;;) {
    bool done = false;
    boost::system::error_code result;
    stream_.async_read_some(asio::buffer(discard), [&](const boost::system::error_code& error, std::size_t) {
      result = error;
      done = true;
    });
    if (!run_until(io_, done, deadline)) {
      stream_.cancel();
      run_until(io_, done, Clock::now() + std::chrono::seconds(10));
      return false;
    }
    if (result) return result != asio::error::operation_aborted;
  }
}

std::optional<std::string> HttpClient::bytes_until_closed(std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  std::string bytes = beast::buffers_to_string(buffer_.data());
  buffer_.consume(buffer_.size());
  std::array<char, 4096> chunk{};
  for (;;) {
    bool done = false;
    boost::system::error_code result;
    std::size_t got = 0;
    stream_.async_read_some(asio::buffer(chunk), [&](const boost::system::error_code& error, std::size_t n) {
      result = error;
      got = n;
      done = true;
    });
    if (!run_until(io_, done, deadline)) {
      stream_.cancel();
      run_until(io_, done, Clock::now() + std::chrono::seconds(10));
      return std::nullopt;
    }
    bytes.append(chunk.data(), got);
    if (result) {
      if (result == asio::error::operation_aborted) return std::nullopt;
      return bytes;
    }
  }
}

std::optional<HttpResponse> http_request(std::uint16_t port, const std::string& method, const std::string& target,
                                         const std::string& extra_headers) {
  HttpClient client(port);
  if (!client.connected() || !client.send_request(method, target, extra_headers)) return std::nullopt;
  return client.read_response(method == "HEAD");
}

}  // namespace tumble::test
