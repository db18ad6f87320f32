#include "tumble/endpoint.h"

#include <algorithm>

namespace tumble {
namespace {

bool all_digits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

ParsedEndpoint parse_endpoint(std::string_view text, PortZero port_zero) {
  const std::string not_host_port = "'" + std::string(text) + "' is not HOST:PORT: ";
  const auto invalid = [&not_host_port](const char* reason) {
    return ParsedEndpoint{std::nullopt, not_host_port + reason};
  };
  const std::size_t colon = text.rfind(':');
  if (colon == std::string_view::npos) return invalid("the port is missing");

  std::string_view host = text.substr(0, colon);
  const std::string_view port_text = text.substr(colon + 1);
  if (!host.empty() && host.front() == '[') {
    if (host.size() < 2 || host.back() != ']') return invalid("unbalanced '['");
    host = host.substr(1, host.size() - 2);
  } else if (host.find_first_of(":[]") != std::string_view::npos) {
    return invalid("write an IPv6 address in brackets, as in [::1]:7400");
  }
  if (host.empty()) return invalid("the host is missing");

  const unsigned lowest = port_zero == PortZero::allowed ? 0 : 1;
  const char* range = port_zero == PortZero::allowed ? "the port must be a number from 0 to 65535"
                                                     : "the port must be a number from 1 to 65535";
  // At most five digits, so the value cannot overflow before the range check.
  if (!all_digits(port_text) || port_text.size() > 5) return invalid(range);
  unsigned value = 0;
  for (char c : port_text) value = value * 10 + static_cast<unsigned>(c - '0');
  if (value < lowest || value > 65535) return invalid(range);
  return ParsedEndpoint{Endpoint{std::string(host), static_cast<std::uint16_t>(value)}, {}};
}

std::string to_string(const Endpoint& endpoint) {
  const bool bracket = endpoint.host.find(':') != std::string::npos;
  return (bracket ? "[" + endpoint.host + "]" : endpoint.host) + ":" + std::to_string(endpoint.port);
}

}  // namespace tumble
