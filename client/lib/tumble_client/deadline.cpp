#include "tumble_client/deadline.h"

namespace tumble::client {

Deadline Deadline::after(Timeout timeout) {
  using Clock = std::chrono::steady_clock;
  if (timeout < Timeout::zero()) timeout = Timeout::zero();
  const Clock::time_point now = Clock::now();
  if (timeout >= Clock::time_point::max() - now) return Deadline{std::nullopt, timeout};
  return Deadline{now + timeout, timeout};
}

}  // namespace tumble::client
