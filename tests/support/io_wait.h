// Waiting on a test client's private io_context with a deadline, so that a
// server that does not answer fails the test instead of hanging it.
#pragma once

#include <chrono>

#include "net/asio.h"

namespace tumble::test {

// Runs `io`'s handlers until `done` is true or `deadline` passes; true when
// done. Operations still under way stay under way for the next call.
inline bool run_until(boost::asio::io_context& io, const bool& done, std::chrono::steady_clock::time_point deadline) {
  io.restart();
  while (!done) {
    if (io.run_one_until(deadline) == 0) break;  // the deadline passed, or nothing is under way
  }
  return done;
}

}  // namespace tumble::test
