// The names the HTTP endpoint answers to: the Host header of every request,
// the WebSocket upgrade's included, must be one of them. A page of any site
// can make a browser connect to 127.0.0.1 by giving its own name an address
// of 127.0.0.1 (DNS rebinding); its requests then carry that site's name as
// their Host, and are refused here (421).
//
// An entry is "name:port" (that port only), "name" (any port, or none), or
// "*" (any Host: the check is off). Names compare without regard to case;
// an IPv6 address is written in brackets, "[::1]:8080". The defaults also
// serve any Host that is an IP address: a rebinding page sends its own
// name, never an address.
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
  // Exactly `entries`.
  explicit AllowedHosts(std::vector<std::string> entries);

  // The defaults for an endpoint bound to `listen_host`: localhost and that
  // name (when it is a name), at any port, and every IP address at any
  // port. The port is left open because a container's published port or a
  // proxy changes it and the name is what tells a rebinding page.
  static AllowedHosts defaults(const std::string& listen_host);

  // True when a request with this Host header value is served.
  bool allows(std::string_view host) const;

  const std::vector<std::string>& entries() const { return entries_; }
  // True when every Host that is an IP address is served (the defaults).
  bool any_ip_address() const { return any_ip_address_; }

 private:
  std::vector<std::string> entries_;
  bool any_ip_address_ = false;
};

}  // namespace tumble::net
