// Endpoint: a host and a TCP port, as a user writes them on a command line
// (tumbled --listen, --http; tumble --server). Standard library only, so the
// server and the client share one reading of "HOST:PORT".
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace tumble {

// A host (name, IPv4 or IPv6 address, without brackets) and a TCP port.
struct Endpoint {
  std::string host;
  std::uint16_t port = 0;
};

// Where tumbled listens unless told otherwise, and where tumble looks for it.
inline Endpoint default_endpoint() { return Endpoint{"127.0.0.1", 7400}; }

// Whether port 0 is accepted: a listener given 0 asks the kernel for a free
// port; a client has nothing to connect to there.
enum class PortZero { refused, allowed };

// What parse_endpoint made of its text: an endpoint, or why not.
struct ParsedEndpoint {
  std::optional<Endpoint> endpoint;
  std::string error;  // without an endpoint: "'TEXT' is not HOST:PORT: " and the reason
};

// Parses "HOST:PORT", with an IPv6 address in brackets ("[::1]:7400"). The
// port is decimal digits only, from 1 (0 too, when allowed) to 65535.
ParsedEndpoint parse_endpoint(std::string_view text, PortZero port_zero = PortZero::refused);

// "host:port", or "[host]:port" when the host holds a colon (IPv6).
std::string to_string(const Endpoint& endpoint);

}  // namespace tumble
