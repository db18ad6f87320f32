#include "net/server.h"

#include <vector>

#include "net/listen.h"
#include "net/log.h"
#include "net/tcp_transport.h"

namespace tumble::net {

namespace asio = boost::asio;
using asio::ip::tcp;

namespace {

// How often session deadlines are checked: the resolution of the handshake
// timeout and of the undelivered-message limit.
constexpr auto kDeadlineSweepInterval = std::chrono::milliseconds(100);

}  // namespace

Server::Server(asio::io_context& io, sim::Simulation& sim, ServerConfig config)
    : io_(io),
      sim_(sim),
      config_(std::move(config)),
      acceptor_(io),
      accept_retry_(io),
      sweep_timer_(io),
      publisher_(io, sim, config_.fanout_slice),
      refusals_(io, "connections", config_.max_connections, counters_),
      context_{io, sim, publisher_, config_.limits, config_.server_version, config_.access, counters_} {
  sim_.add_snapshot_listener(
      [this](std::shared_ptr<const sim::Snapshot> snapshot) { publisher_.offer(std::move(snapshot)); });
  sim_.add_event_listener(
      [this](std::shared_ptr<const sim::WorldEvents> events) { publisher_.offer_events(std::move(events)); });
}

Server::~Server() { stop(); }

sim::Status Server::start() {
  if (auto status = listen_on(acceptor_, config_.host, config_.port); !status.ok()) return status;
  port_ = acceptor_.local_endpoint().port();
  net_log().info("listening on {}:{}", config_.host, port_);
  if (config_.serve_http) {
    http_ =
        std::make_unique<HttpListener>(io_, config_.http_host, config_.http_port, config_.http_limits, counters_,
                                       [this](std::unique_ptr<Transport> transport) { admit(std::move(transport)); });
    if (auto status = http_->start(); !status.ok()) {
      http_.reset();
      boost::system::error_code ignored;
      acceptor_.close(ignored);
      return status;
    }
  }
  accept_next();
  sweep_deadlines();
  return {};
}

void Server::stop() {
  boost::system::error_code ignored;
  acceptor_.close(ignored);
  if (http_) http_->stop();
  accept_retry_.cancel();
  sweep_timer_.cancel();
  refusals_.cancel();
  // close() erases from sessions_ through the closed callback: iterate a copy.
  for (auto* registry : {&sessions_, &refused_}) {
    const auto sessions = *registry;
    for (const auto& [id, session] : sessions) session->close("server shutting down");
    registry->clear();
  }
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
    admit(std::make_unique<TcpTransport>(std::move(socket)));
    accept_next();
  });
}

void Server::admit(std::unique_ptr<Transport> transport) {
  if (!acceptor_.is_open()) {
    // A WebSocket handshake that finished as the server stopped.
    transport->close();
    return;
  }
  const std::uint64_t id = next_session_id_++;
  const bool full = sessions_.size() >= config_.max_connections;
  if (full && refused_.size() >= config_.max_pending_refusals) {
    // A flood of connections: refusing each politely would cost as much as
    // serving it, so these are closed without a word, and counted.
    refusals_.note(false);
    transport->close();
    return;
  }
  auto session = std::make_shared<Session>(std::move(transport), id, context_, [this](std::uint64_t closed) {
    sessions_.erase(closed);
    refused_.erase(closed);
  });
  if (full) {
    refusals_.note(true);
    refused_.emplace(id, session);
    session->refuse(
        tumble::v1::RESOURCE_EXHAUSTED,
        "the server is at its limit of " + std::to_string(config_.max_connections) + " connections; try again later");
    return;
  }
  sessions_.emplace(id, session);
  session->start();
}

void Server::sweep_deadlines() {
  if (!acceptor_.is_open()) return;  // stopped: a sweep that was already due ends the cycle
  const auto now = std::chrono::steady_clock::now();
  // enforce_deadlines() may close a session, which erases it: iterate copies.
  std::vector<std::shared_ptr<Session>> sessions;
  sessions.reserve(sessions_.size() + refused_.size());
  for (const auto* registry : {&sessions_, &refused_}) {
    for (const auto& [id, session] : *registry) sessions.push_back(session);
  }
  for (const auto& session : sessions) session->enforce_deadlines(now);
  sweep_timer_.expires_after(kDeadlineSweepInterval);
  sweep_timer_.async_wait([this](const boost::system::error_code& error) {
    if (!error) sweep_deadlines();
  });
}

}  // namespace tumble::net
