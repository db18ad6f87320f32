// The sim thread and its clock. Pass n of the loop is due at the absolute
// deadline t0 + n * period on the steady clock, so the rate does not drift.
// A pass that ends late is followed at once by the next; a loop that falls
// more than max_catch_up_ticks periods behind skips the missed deadlines,
// counts them as overruns and counts deadlines afresh from now. The period
// is 1 / tick_rate_hz(), read after every pass: when it changes, deadlines
// are counted afresh at the new period from the end of that pass. wake()
// runs a pass at once, without waiting for its deadline; deadlines are then
// counted afresh from the end of that pass too, so a woken pass is never
// followed by one less than a period later. The thread waits on nothing but
// its clock, wake() and stop().
//
// Thread: start() and stop() from one owning thread; overruns() from any.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>

namespace tumble::sim {

class TickLoop {
 public:
  explicit TickLoop(std::uint32_t max_catch_up_ticks) : max_catch_up_ticks_(max_catch_up_ticks) {}
  ~TickLoop() { stop(); }

  TickLoop(const TickLoop&) = delete;
  TickLoop& operator=(const TickLoop&) = delete;

  // Starts the thread, unless it runs: `begin` once on it, then `pass` at
  // each deadline, with how late it begins after that deadline (ms, >= 0).
  // `tick_rate_hz` (Hz, > 0) is called on the thread before the first pass
  // and after every pass. The callables outlive stop().
  void start(std::function<void()> begin, std::function<void(double late_ms)> pass,
             std::function<double()> tick_rate_hz);
  // Stops and joins the thread after the pass under way. Idempotent.
  void stop();
  // Runs the next pass now: at once when the loop waits for a deadline,
  // right after the pass under way otherwise. Any thread; many wakes before
  // the pass make one.
  void wake();

  // Deadlines skipped because the loop fell too far behind its clock.
  std::uint64_t overruns() const { return overruns_.load(std::memory_order_relaxed); }

 private:
  void run();

  const std::uint32_t max_catch_up_ticks_;
  std::function<void()> begin_;
  std::function<void(double late_ms)> pass_;
  std::function<double()> tick_rate_hz_;
  std::atomic<std::uint64_t> overruns_{0};

  std::mutex run_mutex_;
  std::condition_variable run_wakeup_;
  bool stopping_ = false;  // guarded by run_mutex_
  bool woken_ = false;     // guarded by run_mutex_
  std::thread thread_;
};

}  // namespace tumble::sim
