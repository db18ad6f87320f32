// Opening a listening socket, shared by the TCP listener (net/server.h) and
// the HTTP one (net/http_listener.h).
#pragma once

#include <cstdint>
#include <string>

#include "net/asio.h"
#include "sim/status.h"

namespace tumble::net {

// Opens, binds (reusing the address) and listens on host:port; the errors
// name the address. `host` is an IPv4 or IPv6 address, not a name.
sim::Status listen_on(boost::asio::ip::tcp::acceptor& acceptor, const std::string& host, std::uint16_t port);

}  // namespace tumble::net
