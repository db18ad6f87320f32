// When and how soon `tumble subscribe --reconnect` tries again after its
// connection failed: which failures are worth another attempt, and an
// exponential backoff with jitter between attempts.
#pragma once

#include <chrono>
#include <cstdint>
#include <random>

#include "tumble_client/failure.h"

namespace tumble::cli {

// The wait before the first new attempt after a failure.
inline constexpr std::chrono::milliseconds kReconnectFirstWait{100};

// The longest wait between two attempts unless --reconnect-max-wait says otherwise.
inline constexpr std::chrono::milliseconds kReconnectDefaultMaxWait{5000};

// True when `failure` may pass if the connection is made again: the server
// could not be reached, the connection closed or broke, a deadline passed,
// or the server turned the client away for now (RESOURCE_EXHAUSTED when
// full, RATE_LIMITED, HANDSHAKE_REQUIRED, INTERNAL). False for what another
// attempt would meet again: a refused token or protocol version, a body the
// server does not know, input it rejects, a stream this client cannot read.
bool worth_reconnecting(const client::Failure& failure);

// The waits between attempts: the first is kReconnectFirstWait, each later
// one twice the one before, up to `max_wait`; each is then shortened by up
// to a quarter at random, so that clients cut off together do not all come
// back at the same moment. Not thread-safe.
class ReconnectBackoff {
 public:
  // `max_wait`: the cap, at least 1 ms (a smaller one counts as 1 ms); a cap
  // below kReconnectFirstWait makes every wait at most the cap. `seed`
  // chooses the jitter, for tests that want the same waits every run.
  explicit ReconnectBackoff(std::chrono::milliseconds max_wait = kReconnectDefaultMaxWait,
                            std::uint64_t seed = std::random_device{}());

  // The wait before the next attempt without its jitter.
  std::chrono::milliseconds base_wait() const { return base_; }

  // The wait before the next attempt, in [3/4, 1] of base_wait(); the base
  // then doubles, up to the cap.
  std::chrono::milliseconds next_wait();

  // Back to the first wait: call once a connection has served again.
  void reset();

 private:
  std::chrono::milliseconds max_wait_;
  std::chrono::milliseconds base_;
  std::mt19937_64 random_;
};

}  // namespace tumble::cli
