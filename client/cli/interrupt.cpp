#include "interrupt.h"

#include <algorithm>
#include <csignal>
#include <thread>

namespace tumble::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;

void on_interrupt(int) { g_interrupted = 1; }

}  // namespace

void catch_interrupts() {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
}

bool interrupted() { return g_interrupted != 0; }

bool sleep_unless_interrupted(std::chrono::milliseconds duration) {
  constexpr std::chrono::milliseconds kSlice{100};
  const auto end = std::chrono::steady_clock::now() + duration;
  for (;;) {
    if (interrupted()) return false;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    if (left <= std::chrono::milliseconds::zero()) return true;
    std::this_thread::sleep_for(std::min(left, kSlice));
  }
}

}  // namespace tumble::cli
