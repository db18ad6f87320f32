#include "net/allowed_hosts.h"

#include <algorithm>
#include <string>
#include <utility>

#include "net/ascii_case.h"

namespace tumble::net {

namespace {

// "name" of "name:port", "[::1]" of "[::1]:port"; the whole of a value without a port.
std::string_view name_of(std::string_view host) {
  if (!host.empty() && host.front() == '[') return host.substr(0, host.find(']') + 1);
  return host.substr(0, host.find(':'));
}

bool has_port(std::string_view entry) { return name_of(entry).size() < entry.size(); }

// True for a dotted-quad IPv4 address ("10.0.0.5") or a bracketed IPv6
// one ("[::1]"), as a Host header names them.
bool is_ip_address(std::string_view name) {
  if (name.size() > 2 && name.front() == '[' && name.back() == ']') {
    const std::string_view inner = name.substr(1, name.size() - 2);
    return inner.find(':') != std::string_view::npos && std::all_of(inner.begin(), inner.end(), [](char c) {
             return (c >= '0' && c <= '9') || (ascii_lower(c) >= 'a' && ascii_lower(c) <= 'f') || c == ':' || c == '.';
           });
  }
  int parts = 0;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = name.find('.', start);
    const std::string_view part = name.substr(start, dot == std::string_view::npos ? name.npos : dot - start);
    if (part.empty() || part.size() > 3 ||
        !std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return false;
    }
    if (std::stoi(std::string(part)) > 255) return false;
    ++parts;
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return parts == 4;
}

}  // namespace

AllowedHosts::AllowedHosts(std::vector<std::string> entries) : entries_(std::move(entries)) {}

AllowedHosts AllowedHosts::defaults(const std::string& listen_host) {
  std::vector<std::string> entries{"localhost"};
  if (!listen_host.empty() && !is_ip_address(listen_host) && !equal_ignoring_ascii_case(listen_host, "localhost") &&
      listen_host.find(':') == std::string::npos) {
    entries.push_back(listen_host);
  }
  AllowedHosts hosts(std::move(entries));
  hosts.any_ip_address_ = true;
  return hosts;
}

bool AllowedHosts::allows(std::string_view host) const {
  if (any_ip_address_ && is_ip_address(name_of(host))) return true;
  return std::any_of(entries_.begin(), entries_.end(), [&](const std::string& entry) {
    if (entry == "*") return true;
    return has_port(entry) ? equal_ignoring_ascii_case(entry, host) : equal_ignoring_ascii_case(entry, name_of(host));
  });
}

}  // namespace tumble::net
