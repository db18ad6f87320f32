// A token bucket: lets through `rate` events per second on average and up
// to `burst` at once. Each event takes one token; tokens come back at `rate`
// per second up to `burst`. The bucket starts full.
//
// Time is passed in by the caller (a steady clock's time points), so the
// logic is deterministic under test.
//
// Thread: not shared; each session owns one, on the I/O thread.
#pragma once

#include <chrono>

namespace tumble::net {

class TokenBucket {
 public:
  using Clock = std::chrono::steady_clock;

  // `rate` in tokens per second and `burst` in tokens, both > 0.
  TokenBucket(double rate, double burst, Clock::time_point now);

  // Takes one token if there is one at `now`; false (and nothing taken)
  // otherwise. `now` must not go backwards.
  bool try_take(Clock::time_point now);

 private:
  double rate_;             // tokens per second
  double burst_;            // the most tokens the bucket holds
  double tokens_;           // tokens left at last_
  Clock::time_point last_;  // when tokens_ was last brought up to date
};

}  // namespace tumble::net
