#include "tumble_client/endpoint.h"

#include <algorithm>

namespace tumble::client {
namespace {

Failure invalid(std::string message) { return Failure{FailureKind::invalid_argument, std::move(message)}; }

bool all_digits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

Result<Endpoint> parse_endpoint(std::string_view text) {
  const std::string quoted = "'" + std::string(text) + "'";
  const std::size_t colon = text.rfind(':');
  if (colon == std::string_view::npos) return invalid(quoted + " is not HOST:PORT: the port is missing");

  std::string_view host = text.substr(0, colon);
  const std::string_view port_text = text.substr(colon + 1);
  if (!host.empty() && host.front() == '[') {
    if (host.size() < 2 || host.back() != ']') return invalid(quoted + " is not HOST:PORT: unbalanced '['");
    host = host.substr(1, host.size() - 2);
  } else if (host.find_first_of(":[]") != std::string_view::npos) {
    return invalid(quoted + " is not HOST:PORT: write an IPv6 address in brackets, as in [::1]:7400");
  }
  if (host.empty()) return invalid(quoted + " is not HOST:PORT: the host is missing");

  // At most five digits, so the value cannot overflow before the range check.
  if (!all_digits(port_text) || port_text.size() > 5) {
    return invalid(quoted + " is not HOST:PORT: the port must be a number from 1 to 65535");
  }
  unsigned value = 0;
  for (char c : port_text) value = value * 10 + static_cast<unsigned>(c - '0');
  if (value == 0 || value > 65535) {
    return invalid(quoted + " is not HOST:PORT: the port must be a number from 1 to 65535");
  }
  return Endpoint{std::string(host), static_cast<std::uint16_t>(value)};
}

std::string to_string(const Endpoint& endpoint) {
  const bool bracket = endpoint.host.find(':') != std::string::npos;
  return (bracket ? "[" + endpoint.host + "]" : endpoint.host) + ":" + std::to_string(endpoint.port);
}

}  // namespace tumble::client
