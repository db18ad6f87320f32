// The measured window of a load run, set once every subscriber is in; read
// by many threads, set by one.
//
//  - MeasuredWindow, on the wall clock: subscribers count what arrives
//    inside it and stop at its end (net_load over TCP).
//  - MeasuredTicks, on the server's clock: subscribers count the frames of
//    the ticks inside it whenever they arrive, so that a reader running
//    behind is neither credited with the frames of the ticks before nor
//    charged with those still on their way at the end (nats_load).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
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

struct MeasuredTicks {
  std::atomic<std::uint64_t> first{std::numeric_limits<std::uint64_t>::max()};  // the first tick counted
  std::atomic<std::uint64_t> end{std::numeric_limits<std::uint64_t>::max()};    // the first tick not counted

  void set(std::uint64_t from, std::uint64_t to) {
    end = to;
    first = from;
  }
  bool contains(std::uint64_t tick) const { return tick >= first.load() && tick < end.load(); }
};

}  // namespace tumble::bench
