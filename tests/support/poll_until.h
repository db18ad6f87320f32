// Waiting for a condition another thread or process makes true, with a
// deadline: the condition is checked every few milliseconds, so a test
// waits for the event itself, never for a guess at how long it takes.
#pragma once

#include <chrono>
#include <thread>

namespace tumble::test {

// Checks `condition` until it holds or `timeout` passes; true when it held.
// It is checked once more at the deadline, so a slow machine that makes it
// true late is not reported as a failure.
template <typename Condition>
bool poll_until(Condition&& condition, std::chrono::milliseconds timeout = std::chrono::seconds(30)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return condition();
}

}  // namespace tumble::test
