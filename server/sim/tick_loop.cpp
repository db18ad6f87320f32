#include "sim/tick_loop.h"

#include <pthread.h>

#include <algorithm>
#include <utility>

#include "sim/log.h"
#include "sim/tick_timing.h"

namespace tumble::sim {
namespace {

using Clock = std::chrono::steady_clock;

Clock::duration period_of(double tick_rate_hz) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / tick_rate_hz));
}

}  // namespace

void TickLoop::start(std::function<void()> begin, std::function<void(double late_ms)> pass,
                     std::function<double()> tick_rate_hz) {
  if (thread_.joinable()) return;
  begin_ = std::move(begin);
  pass_ = std::move(pass);
  tick_rate_hz_ = std::move(tick_rate_hz);
  {
    std::lock_guard lock(run_mutex_);
    stopping_ = false;
  }
  thread_ = std::thread([this] { run(); });
}

void TickLoop::stop() {
  {
    std::lock_guard lock(run_mutex_);
    stopping_ = true;
  }
  run_wakeup_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void TickLoop::wake() {
  {
    std::lock_guard lock(run_mutex_);
    woken_ = true;
  }
  run_wakeup_.notify_all();
}

void TickLoop::run() {
  // Named for top -H, perf and /proc/PID/task/*/comm (at most 15 characters).
  pthread_setname_np(pthread_self(), "tumbled-sim");
  begin_();
  double rate = tick_rate_hz_();
  Clock::duration period = period_of(rate);
  Clock::time_point start = Clock::now();
  std::uint64_t ticks_since_start = 0;
  sim_log().info("stepping at {} Hz", rate);

  std::unique_lock lock(run_mutex_);
  Clock::time_point due = start;  // when this pass should begin
  while (!stopping_) {
    const bool woken = std::exchange(woken_, false);
    lock.unlock();
    // Late after a deadline: woken late, or behind (the last pass overran).
    // A pass run by wake() has no deadline, and is not late.
    pass_(woken ? 0.0 : std::max(0.0, milliseconds(Clock::now() - due)));
    ++ticks_since_start;
    if (woken) {
      // Deadlines afresh from the end of this pass: the next is a period away.
      start = Clock::now();
      ticks_since_start = 1;
    }
    if (const double now_rate = tick_rate_hz_(); now_rate != rate) {
      // A new rate: count deadlines afresh at the new period from the end of this pass.
      rate = now_rate;
      period = period_of(rate);
      start = Clock::now();
      ticks_since_start = 1;
      sim_log().info("stepping at {} Hz", rate);
    }
    // Absolute deadlines: pass n is due at start + n * period, no accumulation of sleep error.
    const Clock::time_point deadline = start + ticks_since_start * period;
    const Clock::time_point now = Clock::now();
    due = deadline;
    lock.lock();
    if (now < deadline) {
      run_wakeup_.wait_until(lock, deadline, [this] { return stopping_ || woken_; });
    } else if (now - deadline > max_catch_up_ticks_ * period) {
      // Too far behind to catch up: skip the missed deadlines and start counting again from now.
      const auto missed = static_cast<std::uint64_t>((now - deadline) / period);
      overruns_.fetch_add(missed, std::memory_order_relaxed);
      sim_log().warn("fell {} ticks behind the clock; skipped them", missed);
      start = now;
      ticks_since_start = 0;
      due = now;
    }
  }
}

}  // namespace tumble::sim
