// TickLoop on a real thread and the steady clock: what it does when a pass
// overruns its period. The passes below busy-wait a known span of wall time,
// so how far behind the loop is has a lower bound that needs no luck.
#include "sim/tick_loop.h"

#include <gtest/gtest.h>
#include <pthread.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace tumble::sim {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

constexpr double kRateHz = 1000;  // a 1 ms period

// Holds the loop's thread for `span` of wall time.
void busy_for(Clock::duration span) {
  const Clock::time_point end = Clock::now() + span;
  while (Clock::now() < end) {
  }
}

// The passes a loop has run and how late each began, handed to the test thread.
class PassLog {
 public:
  void add(double late_ms) {
    {
      std::lock_guard lock(mutex_);
      late_ms_.push_back(late_ms);
    }
    changed_.notify_all();
  }
  // The late starts of the first `count` passes, once they have run.
  std::vector<double> wait_for(std::size_t count) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return late_ms_.size() >= count; });
    return {late_ms_.begin(), late_ms_.begin() + static_cast<std::ptrdiff_t>(count)};
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<double> late_ms_;
};

// Starts `loop` at kRateHz with a first pass that works for 20 ms (20
// periods), waits for its second pass, stops it, and returns how late the
// two passes began.
std::vector<double> run_two_passes_the_first_20_ms_long(TickLoop& loop) {
  PassLog log;
  int pass = 0;
  loop.start([] {},
             [&](double late_ms) {
               if (pass++ == 0) busy_for(milliseconds(20));
               log.add(late_ms);
             },
             [] { return kRateHz; });
  std::vector<double> late = log.wait_for(2);
  loop.stop();
  return late;
}

TEST(TickLoop, RunsBeginOnItsNamedThreadBeforeThePasses) {
  TickLoop loop(8);
  PassLog log;
  std::string name;
  bool begun = false;
  bool begun_before_first_pass = false;
  int pass = 0;
  loop.start(
      [&] {
        char buffer[16] = {};
        pthread_getname_np(pthread_self(), buffer, sizeof buffer);
        name = buffer;
        begun = true;
      },
      [&](double late_ms) {
        if (pass++ == 0) begun_before_first_pass = begun;
        log.add(late_ms);
      },
      [] { return kRateHz; });
  log.wait_for(1);
  loop.stop();  // joined: what the thread wrote is visible here
  EXPECT_EQ(name, "tumbled-sim");
  EXPECT_TRUE(begun_before_first_pass);
}

TEST(TickLoop, CatchesUpAPassThatOverranWithinTheBound) {
  // 20 periods late, 1000 allowed: the next passes run at once, late, and
  // nothing is skipped.
  TickLoop loop(1000);
  const std::vector<double> late = run_two_passes_the_first_20_ms_long(loop);
  // Pass 2 was due 1 ms after the start and began after the 20 ms of pass 1.
  EXPECT_GE(late[1], 19.0);
  EXPECT_EQ(loop.overruns(), 0u);
}

TEST(TickLoop, SkipsAndCountsTheDeadlinesOfAPassFarBehind) {
  // 20 periods late, 2 allowed: the missed deadlines are skipped and counted.
  TickLoop loop(2);
  run_two_passes_the_first_20_ms_long(loop);
  // The first pass ended at least 20 ms after the start, the deadline 1 ms
  // after it: at least 19 whole periods behind.
  EXPECT_GE(loop.overruns(), 19u);
}

// A loop at 1 Hz woken after its first pass runs its second at once, not a
// second later, and its third a period after the second: deadlines count
// afresh from a woken pass (else the third would wait for the deadline two
// periods after the first, and a stream of wakes would push the deadlines
// ever further ahead of the clock).
TEST(TickLoop, WakeRunsAPassAtOnceAndTheNextAPeriodAfterIt) {
  TickLoop loop(8);
  PassLog log;
  std::mutex mutex;
  std::vector<Clock::time_point> starts;
  loop.start([] {},
             [&](double late_ms) {
               {
                 std::lock_guard lock(mutex);
                 starts.push_back(Clock::now());
               }
               log.add(late_ms);
             },
             [] { return 1.0; });
  log.wait_for(1);
  const Clock::time_point woken = Clock::now();
  loop.wake();
  const std::vector<double> late = log.wait_for(3);
  loop.stop();
  std::lock_guard lock(mutex);
  EXPECT_LT(starts[1] - woken, milliseconds(500)) << "a woken pass does not wait for its deadline, 1 s away";
  EXPECT_EQ(late[1], 0.0) << "a woken pass is not late";
  EXPECT_GT(starts[2] - starts[1], milliseconds(900));
  EXPECT_LT(starts[2] - starts[1], milliseconds(1500)) << "the next deadline is a period after the woken pass";
}

}  // namespace
}  // namespace tumble::sim
