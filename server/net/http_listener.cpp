#include "net/http_listener.h"

#include <utility>

#include "net/listen.h"
#include "net/log.h"

namespace tumble::net {

namespace asio = boost::asio;
using asio::ip::tcp;

HttpListener::HttpListener(asio::io_context& io, std::string host, std::uint16_t port, std::size_t max_connections,
                           HttpConnection::UpgradeFn on_websocket)
    : host_(std::move(host)),
      requested_port_(port),
      max_connections_(max_connections),
      on_websocket_(std::move(on_websocket)),
      acceptor_(io),
      accept_retry_(io) {}

HttpListener::~HttpListener() { stop(); }

sim::Status HttpListener::start() {
  if (auto status = listen_on(acceptor_, host_, requested_port_); !status.ok()) {
    return sim::Status::error("the HTTP endpoint: " + status.message());
  }
  port_ = acceptor_.local_endpoint().port();
  net_log().info("serving HTTP and WebSocket clients on {}:{}", host_, port_);
  accept_next();
  return {};
}

void HttpListener::stop() {
  boost::system::error_code ignored;
  acceptor_.close(ignored);
  accept_retry_.cancel();
  // close() erases from connections_ through the closed callback: iterate a copy.
  const auto connections = connections_;
  for (const auto& [id, connection] : connections) connection->close();
  connections_.clear();
}

void HttpListener::accept_next() {
  acceptor_.async_accept([this](const boost::system::error_code& error, tcp::socket socket) {
    if (error == asio::error::operation_aborted) return;
    if (error) {
      // Out of descriptors and the like: retry shortly rather than spin.
      net_log().warn("HTTP accept failed: {}", error.message());
      accept_retry_.expires_after(std::chrono::milliseconds(100));
      accept_retry_.async_wait([this](const boost::system::error_code& wait_error) {
        if (!wait_error) accept_next();
      });
      return;
    }
    admit(std::move(socket));
    accept_next();
  });
}

void HttpListener::admit(tcp::socket socket) {
  if (connections_.size() >= max_connections_) {
    if (!warned_full_) {
      net_log().warn("over {} HTTP connections at once; closing new ones until some end", max_connections_);
      warned_full_ = true;
    }
    boost::system::error_code ignored;
    socket.close(ignored);
    return;
  }
  warned_full_ = false;
  const std::uint64_t id = next_connection_id_++;
  auto connection = std::make_shared<HttpConnection>(std::move(socket), id, on_websocket_,
                                                     [this](std::uint64_t closed) { connections_.erase(closed); });
  connections_.emplace(id, connection);
  connection->start();
}

}  // namespace tumble::net
