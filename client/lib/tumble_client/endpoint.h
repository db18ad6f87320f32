// Endpoint: where a tumbled server listens.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "tumble_client/result.h"

namespace tumble::client {

// The address tumbled listens on unless told otherwise.
inline constexpr std::string_view kDefaultServer = "127.0.0.1:7400";

// A host (name, IPv4 or IPv6 address, without brackets) and a TCP port.
struct Endpoint {
  std::string host;
  std::uint16_t port = 0;
};

// Parses "HOST:PORT", with an IPv6 address in brackets ("[::1]:7400"). The
// port must be a decimal number from 1 to 65535. Fails with kind
// invalid_argument and a sentence naming what is wrong.
Result<Endpoint> parse_endpoint(std::string_view text);

// "host:port", or "[host]:port" when the host holds a colon (IPv6).
std::string to_string(const Endpoint& endpoint);

}  // namespace tumble::client
