// The HTTP endpoint of tumbled (--http): serves the viewer's page and its
// script from the files embedded at build time, and takes WebSocket
// clients at /ws (net/http_connection.h). It runs on the same io_context,
// on the same I/O thread, as the TCP listener; a WebSocket client, once its
// handshake is done, is handed to the Server like a TCP one.
//
// At most HttpLimits::max_connections HTTP connections are open at once
// (WebSocket clients no longer count once handed over, but against the
// server's own limit); one more is closed at once, counted in
// connections_refused and in a log line a second (net/refusal_tally.h).
// No TLS: it belongs on loopback or behind a proxy that terminates TLS.
//
// Thread: constructed, started and stopped on the I/O thread (or before it
// runs); all its work happens there.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "net/asio.h"
#include "net/http_connection.h"
#include "net/net_counters.h"
#include "net/refusal_tally.h"
#include "sim/status.h"

namespace tumble::net {

class HttpListener {
 public:
  // `counters` must outlive the listener.
  HttpListener(boost::asio::io_context& io, std::string host, std::uint16_t port, HttpLimits limits,
               NetCounters& counters, HttpConnection::UpgradeFn on_websocket);
  ~HttpListener();

  // Binds and listens; fails with a sentence when the address is unusable.
  // Without allowed hosts in the limits, the defaults for the bound address apply.
  sim::Status start();

  // Stops accepting and closes every HTTP connection (and handshake under way).
  void stop();

  // The port actually bound, once started.
  std::uint16_t port() const { return port_; }

  std::size_t connection_count() const { return connections_.size(); }

 private:
  void accept_next();
  void admit(boost::asio::ip::tcp::socket socket);

  std::string host_;
  std::uint16_t requested_port_;
  HttpLimits limits_;
  HttpConnection::UpgradeFn on_websocket_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer accept_retry_;
  RefusalTally refusals_;
  std::shared_ptr<const AllowedHosts> allowed_hosts_;  // once started
  std::map<std::uint64_t, std::shared_ptr<HttpConnection>> connections_;
  std::uint64_t next_connection_id_ = 1;
  std::uint16_t port_ = 0;
};

}  // namespace tumble::net
