// The measured window of a load run: set once every subscriber is in; the
// subscribers count what arrives inside it and stop at its end. Read by
// many threads, set by one.
#pragma once

#include <atomic>
#include <chrono>
#include <limits>

namespace tumble::bench {

struct MeasuredWindow {
  using Clock = std::chrono::steady_clock;

  std::atomic<Clock::rep> start{std::numeric_limits<Clock::rep>::max()};
  std::atomic<Clock::rep> end{std::numeric_limits<Clock::rep>::max()};

  void set(Clock::time_point from, Clock::time_point to) {
    start = from.time_since_epoch().count();
    end = to.time_since_epoch().count();
  }
  bool contains(Clock::time_point t) const {
    const Clock::rep at = t.time_since_epoch().count();
    return at >= start.load() && at < end.load();
  }
  bool over(Clock::time_point t) const { return t.time_since_epoch().count() >= end.load(); }
};

}  // namespace tumble::bench
