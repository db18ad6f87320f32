#include "reconnect_policy.h"

#include <algorithm>

namespace tumble::cli {

bool worth_reconnecting(const client::Failure& failure) {
  switch (failure.kind) {
    case client::FailureKind::connect:
    case client::FailureKind::closed:
    case client::FailureKind::timeout:
      return true;
    case client::FailureKind::server:
      switch (failure.code) {
        case tumble::v1::RESOURCE_EXHAUSTED:  // at --max-connections, or out of room
        case tumble::v1::RATE_LIMITED:
        case tumble::v1::HANDSHAKE_REQUIRED:  // Hello came too late, e.g. on a stalled machine
        case tumble::v1::INTERNAL:
          return true;
        default:
          return false;
      }
    case client::FailureKind::invalid_argument:
    case client::FailureKind::protocol:
      return false;
  }
  return false;
}

ReconnectBackoff::ReconnectBackoff(std::chrono::milliseconds max_wait, std::uint64_t seed)
    : max_wait_(std::max(max_wait, std::chrono::milliseconds(1))),
      base_(std::min(kReconnectFirstWait, max_wait_)),
      random_(seed) {}

std::chrono::milliseconds ReconnectBackoff::next_wait() {
  const std::chrono::milliseconds::rep base = base_.count();
  // Uniform over [base - base/4, base]: at most a quarter shorter, never longer.
  std::uniform_int_distribution<std::chrono::milliseconds::rep> jittered(base - base / 4, base);
  const std::chrono::milliseconds wait(jittered(random_));
  base_ = std::min(base_ * 2, max_wait_);
  return wait;
}

void ReconnectBackoff::reset() { base_ = std::min(kReconnectFirstWait, max_wait_); }

}  // namespace tumble::cli
