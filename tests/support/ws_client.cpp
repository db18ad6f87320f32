#include "ws_client.h"

#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/http/field.hpp>
#include <boost/beast/websocket/error.hpp>

#include "io_wait.h"

namespace tumble::test {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;

WsClient::WsClient(std::uint16_t port, const std::string& origin) {
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  bool done = false;
  boost::system::error_code result;
  beast::get_lowest_layer(ws_).async_connect(asio::ip::tcp::endpoint(asio::ip::address_v4::loopback(), port),
                                             [&](const boost::system::error_code& error) {
                                               result = error;
                                               done = true;
                                             });
  if (!run_until(io_, done, deadline) || result) return;
  if (!origin.empty()) {
    ws_.set_option(websocket::stream_base::decorator(
        [origin](websocket::request_type& request) { request.set(beast::http::field::origin, origin); }));
  }
  websocket::response_type response;
  done = false;
  ws_.async_handshake(response, "127.0.0.1:" + std::to_string(port), "/ws",
                      [&](const boost::system::error_code& error) {
                        result = error;
                        done = true;
                      });
  if (!run_until(io_, done, deadline)) return;
  handshake_status_ = response.result_int();
  connected_ = !result;
  ws_.binary(true);
}

WsClient::~WsClient() {
  boost::system::error_code ignored;
  beast::get_lowest_layer(ws_).socket().close(ignored);
  io_.restart();
  io_.poll();  // lets aborted operations finish while their state still exists
}

bool WsClient::write(const std::string& bytes, bool text) {
  if (!connected_ || ended_) return false;
  ws_.text(text);
  bool done = false;
  boost::system::error_code result;
  ws_.async_write(asio::buffer(bytes), [&](const boost::system::error_code& error, std::size_t) {
    result = error;
    done = true;
  });
  const bool finished = run_until(io_, done, Clock::now() + std::chrono::seconds(10));
  ws_.binary(true);
  return finished && !result;
}

bool WsClient::send_bytes(const std::string& bytes) { return write(bytes, false); }

bool WsClient::send_text(const std::string& text) { return write(text, true); }

std::optional<tumble::v1::ServerMessage> WsClient::handshake(const std::string& name, const std::string& token) {
  tumble::v1::ClientMessage hello;
  hello.set_request_id(1);
  hello.mutable_hello()->set_protocol_version(tumble::v1::PROTOCOL_VERSION_CURRENT);
  hello.mutable_hello()->set_client_name(name);
  hello.mutable_hello()->set_token(token);
  if (!send(hello)) return std::nullopt;
  return read();
}

bool WsClient::fill(Clock::time_point deadline) {
  if (!connected_ || ended_) return false;
  if (!read_pending_) {
    read_pending_ = true;
    read_done_ = false;
    ws_.async_read(message_, [this](const boost::system::error_code& error, std::size_t) {
      read_error_ = error;
      read_done_ = true;
      read_pending_ = false;
    });
  }
  if (!run_until(io_, read_done_, deadline)) return false;
  read_done_ = false;
  if (read_error_) {
    ended_ = true;
    if (read_error_ == websocket::error::closed) {
      got_close_frame_ = true;
      close_reason_ = ws_.reason();
    }
    return false;
  }
  ++messages_received_;
  const std::string payload = beast::buffers_to_string(message_.data());
  message_.consume(message_.size());
  reader_.append(payload.data(), payload.size());
  return true;
}

bool WsClient::closed_by_server(std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (!ended_) {
    if (!fill(deadline) && !ended_) return false;  // the deadline passed
  }
  return true;
}

void WsClient::vanish() {
  boost::system::error_code ignored;
  beast::get_lowest_layer(ws_).socket().close(ignored);
  ended_ = true;
}

}  // namespace tumble::test
