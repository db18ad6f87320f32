// A steady stream of world-changing requests, for soak runs: forces,
// impulses and state sets in turn, on the load's bodies in a fixed
// pseudo-random order, at a fixed rate from one connection. Each is small
// (a 0.2 N force for 10 ticks, a 0.05 N s impulse, or a set that stops the
// body and spins it at 1 rad/s about the vertical), so the world keeps its shape over
// a long run.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

#include "load_connection.h"

namespace tumble::bench {

struct CommandTally {
  std::uint64_t sent = 0;
  std::uint64_t errors = 0;  // any reply but an Ack, and any request left unanswered
};

// Sends `per_second` requests a second, on an absolute schedule, until `end`.
CommandTally run_commands(const LoadTarget& target, const std::vector<std::uint32_t>& bodies, double per_second,
                          std::chrono::steady_clock::time_point end);

}  // namespace tumble::bench
