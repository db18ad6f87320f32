// The network front of tumbled: accepts TCP connections, and WebSocket
// clients through the HTTP endpoint when it is on (net/http_listener.h),
// and keeps every client's session, whatever its transport. Beyond
// max_connections a new client of either kind is refused with
// RESOURCE_EXHAUSTED and closed; the sessions it has are not affected. While
// max_pending_refusals refusals are still being written, one more client
// over the limit is closed without a word. Every refusal counts in Stats's
// connections_refused and in a log line a second (net/refusal_tally.h). A
// periodic sweep enforces every session's deadlines (handshake timeout,
// partial frames, undelivered messages).
//
// Thread: constructed, started and stopped on the thread that runs the
// io_context (or before it runs); all its work happens there.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "net/asio.h"
#include "net/http_listener.h"
#include "net/publisher.h"
#include "net/refusal_tally.h"
#include "net/session.h"
#include "net/transport.h"
#include "sim/simulation.h"
#include "sim/status.h"

namespace tumble::net {

struct ServerConfig {
  std::string host = "127.0.0.1";
  std::uint16_t port = 7400;  // 0 picks a free port; see Server::port()
  SessionLimits limits;
  std::size_t max_connections = 1024;  // sessions at once, handshaking ones included
  // Refusals over max_connections being written at once; beyond, a refusal is a close.
  std::size_t max_pending_refusals = 256;
  AccessTokens access;  // none set: every client is a controller
  std::string server_version;
  // The HTTP endpoint (the viewer's page, WebSocket clients at /ws); off unless serve_http.
  bool serve_http = false;
  std::string http_host = "127.0.0.1";
  std::uint16_t http_port = 8080;  // 0 picks a free port; see Server::http_port()
  HttpLimits http_limits;          // its own connection limit, header deadline and Host names
  // I/O time a frame's fan-out to its sessions takes before the I/O thread
  // reads requests again (Publisher); 0: one session at a time.
  std::chrono::microseconds fanout_slice{250};
};

class Server {
 public:
  // `sim` must outlive the server. The server adds itself to the sim's
  // snapshot and event listeners.
  Server(boost::asio::io_context& io, sim::Simulation& sim, ServerConfig config);
  ~Server();

  // Binds and listens (TCP, then HTTP when on); fails with a sentence when
  // an address is unusable.
  sim::Status start();

  // Stops accepting and closes every session and HTTP connection.
  void stop();

  // The TCP port actually bound, once started.
  std::uint16_t port() const { return port_; }

  // The HTTP port actually bound, once started with serve_http; else 0.
  std::uint16_t http_port() const { return http_ ? http_->port() : 0; }

  std::size_t session_count() const { return sessions_.size(); }

 private:
  void accept_next();
  // Makes a session of a new client, or refuses it when the server is full.
  void admit(std::unique_ptr<Transport> transport);
  // Calls enforce_deadlines() on every session, then again after a while.
  void sweep_deadlines();

  boost::asio::io_context& io_;
  sim::Simulation& sim_;
  ServerConfig config_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer accept_retry_;
  boost::asio::steady_timer sweep_timer_;
  Publisher publisher_;
  NetCounters counters_;   // GetStats's network figures, kept by the sessions and the listeners
  RefusalTally refusals_;  // connections refused over max_connections
  SessionContext context_;
  std::map<std::uint64_t, std::shared_ptr<Session>> sessions_;
  // Connections being refused (their Error still being written); not counted against max_connections.
  std::map<std::uint64_t, std::shared_ptr<Session>> refused_;
  std::uint64_t next_session_id_ = 1;
  std::uint16_t port_ = 0;
  std::unique_ptr<HttpListener> http_;  // with serve_http, once started
};

}  // namespace tumble::net
