#include "load_connection.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "tumble/endpoint.h"

namespace tumble::bench {

void exit_with(const std::string& what, const client::Failure& failure) {
  std::fprintf(stderr, "net_load: %s: %s\n", what.c_str(), failure.message.c_str());
  std::exit(1);
}

client::Connection connect_or_exit(const LoadTarget& target, const std::string& name) {
  const ParsedEndpoint server = parse_endpoint(target.server);
  if (!server.endpoint) exit_with("server", client::Failure{client::FailureKind::invalid_argument, server.error});
  auto connection = client::Connection::connect(*server.endpoint, name, target.token, std::chrono::seconds(10));
  if (!connection) exit_with("connect", connection.failure());
  return std::move(*connection);
}

}  // namespace tumble::bench
