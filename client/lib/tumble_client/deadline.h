// Deadline: when a blocking call of a transport must give up.
#pragma once

#include <chrono>
#include <optional>

#include "tumble_client/transport.h"

namespace tumble::client {

// The moment a call gives up, and the timeout it came from (for messages).
struct Deadline {
  std::optional<std::chrono::steady_clock::time_point> at;  // none: never
  Timeout timeout{};

  // `timeout` from now. A negative timeout counts as zero; one that would
  // pass the clock's end never passes.
  static Deadline after(Timeout timeout);
};

}  // namespace tumble::client
