#include "net/http_listener.h"

#include <utility>

#include "net/listen.h"
#include "net/log.h"

namespace tumble::net {

namespace asio = boost::asio;
using asio::ip::tcp;

HttpListener::HttpListener(asio::io_context& io, std::string host, std::uint16_t port, HttpLimits limits,
                           NetCounters& counters, HttpConnection::UpgradeFn on_websocket)
    : host_(std::move(host)),
      requested_port_(port),
      limits_(std::move(limits)),
      on_websocket_(std::move(on_websocket)),
      acceptor_(io),
      accept_retry_(io),
      refusals_(io, "HTTP connections", limits_.max_connections, counters) {}

HttpListener::~HttpListener() { stop(); }

sim::Status HttpListener::start() {
  if (auto status = listen_on(acceptor_, host_, requested_port_); !status.ok()) {
    return sim::Status::error("the HTTP endpoint: " + status.message());
  }
  port_ = acceptor_.local_endpoint().port();
  allowed_hosts_ = std::make_shared<const AllowedHosts>(
      limits_.allowed_hosts.empty() ? AllowedHosts::defaults(host_) : AllowedHosts(limits_.allowed_hosts));
  std::string names;
  for (const std::string& entry : allowed_hosts_->entries()) names += (names.empty() ? "" : ", ") + entry;
  if (allowed_hosts_->any_ip_address()) names += ", any IP address";
  net_log().info("serving HTTP and WebSocket clients on {}:{} as {}", host_, port_, names);
  accept_next();
  return {};
}

void HttpListener::stop() {
  boost::system::error_code ignored;
  acceptor_.close(ignored);
  accept_retry_.cancel();
  refusals_.cancel();
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
  if (connections_.size() >= limits_.max_connections) {
    refusals_.note(false);
    boost::system::error_code ignored;
    socket.close(ignored);
    return;
  }
  const std::uint64_t id = next_connection_id_++;
  auto connection =
      std::make_shared<HttpConnection>(std::move(socket), id, limits_.header_timeout, allowed_hosts_, on_websocket_,
                                       [this](std::uint64_t closed) { connections_.erase(closed); });
  connections_.emplace(id, connection);
  connection->start();
}

}  // namespace tumble::net
