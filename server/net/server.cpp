#include "net/server.h"

#include "net/log.h"

namespace tumble::net {

namespace asio = boost::asio;
using asio::ip::tcp;

Server::Server(asio::io_context& io, sim::Simulation& sim, ServerConfig config)
    : io_(io),
      sim_(sim),
      config_(std::move(config)),
      acceptor_(io),
      accept_retry_(io),
      publisher_(io, sim),
      context_{io, sim, publisher_, config_.limits, config_.server_version} {
  sim_.set_snapshot_listener(
      [this](std::shared_ptr<const sim::Snapshot> snapshot) { publisher_.offer(std::move(snapshot)); });
}

Server::~Server() { stop(); }

sim::Status Server::start() {
  boost::system::error_code error;
  const asio::ip::address address = asio::ip::make_address(config_.host, error);
  if (error) return sim::Status::error("'" + config_.host + "' is not an IP address");
  const tcp::endpoint endpoint(address, config_.port);
  const std::string where = config_.host + ":" + std::to_string(config_.port);
  if (acceptor_.open(endpoint.protocol(), error); error) {
    return sim::Status::error("cannot open a socket for " + where + ": " + error.message());
  }
  acceptor_.set_option(tcp::acceptor::reuse_address(true), error);
  if (acceptor_.bind(endpoint, error); error) return sim::Status::error("cannot bind " + where + ": " + error.message());
  if (acceptor_.listen(asio::socket_base::max_listen_connections, error); error) {
    return sim::Status::error("cannot listen on " + where + ": " + error.message());
  }
  port_ = acceptor_.local_endpoint().port();
  net_log().info("listening on {}:{}", config_.host, port_);
  accept_next();
  return {};
}

void Server::stop() {
  boost::system::error_code ignored;
  acceptor_.close(ignored);
  accept_retry_.cancel();
  // close() erases from sessions_ through the closed callback: iterate a copy.
  const auto sessions = sessions_;
  for (const auto& [id, session] : sessions) session->close("server shutting down");
  sessions_.clear();
}

void Server::accept_next() {
  acceptor_.async_accept([this](const boost::system::error_code& error, tcp::socket socket) {
    if (error == asio::error::operation_aborted) return;
    if (error) {
      // Out of descriptors and the like: keep serving the others and try
      // again shortly, rather than spinning on the same failure.
      net_log().warn("accept failed: {}", error.message());
      accept_retry_.expires_after(std::chrono::milliseconds(100));
      accept_retry_.async_wait([this](const boost::system::error_code& wait_error) {
        if (!wait_error) accept_next();
      });
      return;
    }
    {
      const std::uint64_t id = next_session_id_++;
      auto session = std::make_shared<Session>(std::move(socket), id, context_,
                                               [this](std::uint64_t closed) { sessions_.erase(closed); });
      sessions_.emplace(id, session);
      session->start();
    }
    accept_next();
  });
}

}  // namespace tumble::net
