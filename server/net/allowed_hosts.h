// The names the HTTP endpoint answers to: the Host header of every request,
// the WebSocket upgrade's included, must be one of them. A page of any site
// can make a browser connect to 127.0.0.1 by giving its own name an address
// of 127.0.0.1 (DNS rebinding); its requests then carry that site's name as
// their Host, and are refused here (421).
//
// An entry is "name:port" (that port only), "name" (any port, or none), or
// "*" (any Host: the check is off). Names compare without regard to case;
// an IPv6 address is written in brackets, "[::1]:8080".
//
// Thread: immutable once made; shared by the HTTP connections.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tumble::net {

class AllowedHosts {
 public:
  explicit AllowedHosts(std::vector<std::string> entries);

  // The defaults for an endpoint bound to `listen_host`:`port`: that address,
  // localhost, 127.0.0.1 and [::1], each with the port (and without it when
  // the port is 80, HTTP's own).
  static AllowedHosts defaults(const std::string& listen_host, std::uint16_t port);

  // True when a request with this Host header value is served.
  bool allows(std::string_view host) const;

  const std::vector<std::string>& entries() const { return entries_; }

 private:
  std::vector<std::string> entries_;
};

}  // namespace tumble::net
