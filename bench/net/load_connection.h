// How net_load's parts reach the server: one place for the address, the
// token and what a failure to set up does.
#pragma once

#include <string>

#include "tumble_client/connection.h"
#include "tumble_client/failure.h"

namespace tumble::bench {

// The server under load.
struct LoadTarget {
  std::string server = "127.0.0.1:7400";  // HOST:PORT
  std::string token;                      // controller token, when the server asks for one
};

// Prints "net_load: WHAT: why" on stderr and exits 1: for failures while
// setting the load up, which leave nothing to measure.
[[noreturn]] void exit_with(const std::string& what, const client::Failure& failure);

// A connection named `name`, or exit_with().
client::Connection connect_or_exit(const LoadTarget& target, const std::string& name);

}  // namespace tumble::bench
