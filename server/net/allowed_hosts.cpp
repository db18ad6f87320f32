#include "net/allowed_hosts.h"

#include <algorithm>
#include <utility>

namespace tumble::net {

namespace {

char lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

bool equal_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return lower(x) == lower(y); });
}

// "name" of "name:port", "[::1]" of "[::1]:port"; the whole of a value without a port.
std::string_view name_of(std::string_view host) {
  if (!host.empty() && host.front() == '[') return host.substr(0, host.find(']') + 1);
  return host.substr(0, host.find(':'));
}

bool has_port(std::string_view entry) { return name_of(entry).size() < entry.size(); }

// "[::1]" for an IPv6 address, the name or IPv4 address as it is.
std::string bracketed(const std::string& host) {
  return host.find(':') != std::string::npos && host.front() != '[' ? "[" + host + "]" : host;
}

}  // namespace

AllowedHosts::AllowedHosts(std::vector<std::string> entries) : entries_(std::move(entries)) {}

AllowedHosts AllowedHosts::defaults(const std::string& listen_host, std::uint16_t port) {
  std::vector<std::string> entries;
  for (const std::string& name :
       {bracketed(listen_host), std::string("localhost"), std::string("127.0.0.1"), std::string("[::1]")}) {
    for (std::string entry : {name + ":" + std::to_string(port), port == 80 ? name : std::string()}) {
      if (!entry.empty() && std::find(entries.begin(), entries.end(), entry) == entries.end()) {
        entries.push_back(std::move(entry));
      }
    }
  }
  return AllowedHosts(std::move(entries));
}

bool AllowedHosts::allows(std::string_view host) const {
  return std::any_of(entries_.begin(), entries_.end(), [&](const std::string& entry) {
    if (entry == "*") return true;
    return has_port(entry) ? equal_ignoring_case(entry, host) : equal_ignoring_case(entry, name_of(host));
  });
}

}  // namespace tumble::net
