// bench/net/stall_watch: a CPU held by something the watcher cannot
// preempt is reported as a stall of that CPU at that moment, and a latency
// sample is matched to the stalls its span overlaps.
#include "stall_watch.h"

#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>

#include <cerrno>
#include <chrono>
#include <thread>
#include <vector>

namespace tumble::bench {
namespace {

using Clock = std::chrono::steady_clock;

TEST(StallWatch, OverlapsAStallOnlyWhenTheSpansShareAMoment) {
  const std::vector<Stall> stalls = {{1.0, 1.005, 0}, {1.002, 1.030, 1}, {2.0, 2.003, 0}};
  EXPECT_TRUE(overlaps_stall(stalls, 0.995, 1.001));   // runs into the first
  EXPECT_TRUE(overlaps_stall(stalls, 1.020, 1.025));   // inside the second, which began before it
  EXPECT_TRUE(overlaps_stall(stalls, 1.9, 2.1));       // spans the third
  EXPECT_TRUE(overlaps_stall(stalls, 2.003, 2.01));    // begins as the third ends
  EXPECT_FALSE(overlaps_stall(stalls, 0.5, 0.999));    // before them all
  EXPECT_FALSE(overlaps_stall(stalls, 1.031, 1.999));  // between the second and the third
  EXPECT_FALSE(overlaps_stall(stalls, 2.004, 3.0));    // after them all
  EXPECT_FALSE(overlaps_stall({}, 0, 10));
}

// The report's figures, in whole hundredths of a millisecond, agree
// exactly: each length is rounded before the sum.
TEST(StallWatch, FiguresRoundEachStallBeforeTheTotal) {
  // One of 29.526 ms: a total printed with 1 decimal read 29.5, below a
  // longest of 29.53.
  const StallFigures one = stall_figures({{1.0, 1.029526, 0}});
  EXPECT_EQ(one.count, 1u);
  EXPECT_EQ(one.longest_cms, 2953);
  EXPECT_EQ(one.total_cms, 2953);
  // Two of 2.004 ms: summed before rounding the total would be 4.01 ms,
  // more than twice the longest, 2.00.
  const StallFigures two = stall_figures({{1.0, 1.002004, 0}, {2.0, 2.002004, 1}});
  EXPECT_EQ(two.count, 2u);
  EXPECT_EQ(two.longest_cms, 200);
  EXPECT_EQ(two.total_cms, 400);
  const StallFigures none = stall_figures({});
  EXPECT_EQ(none.count, 0u);
  EXPECT_EQ(none.longest_cms, 0);
  EXPECT_EQ(none.total_cms, 0);
}

// A SCHED_FIFO thread at priority 99, above the watcher's 90, spinning on
// CPU 0 for 30 ms is, to the watcher of CPU 0, the CPU taken away.
TEST(StallWatch, ACpuHeldAboveTheWatchersPriorityIsAStallOfThatCpu) {
  if (!stall_watch_refusal().empty()) GTEST_SKIP() << stall_watch_refusal();
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  ASSERT_EQ(sched_getaffinity(0, sizeof allowed, &allowed), 0);
  if (!CPU_ISSET(0, &allowed)) GTEST_SKIP() << "CPU 0 is not in this process's affinity mask";

  const Clock::time_point start = Clock::now();
  const auto at = [&](double seconds) {
    return start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  };
  std::vector<Stall> stalls;
  std::thread watch([&] { stalls = watch_stalls(start, at(0.5)); });

  double held_from = 0, held_to = 0;
  int hold_error = 0;
  std::thread holder([&] {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(0, &one);
    sched_param param{};
    param.sched_priority = 99;
    hold_error = pthread_setaffinity_np(pthread_self(), sizeof one, &one);
    if (hold_error == 0) hold_error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    if (hold_error != 0) return;
    std::this_thread::sleep_until(at(0.2));
    const Clock::time_point from = Clock::now();
    while (Clock::now() - from < std::chrono::milliseconds(30)) {
    }
    held_from = std::chrono::duration<double>(from - start).count();
    held_to = std::chrono::duration<double>(Clock::now() - start).count();
  });
  holder.join();
  watch.join();
  if (hold_error == EPERM) GTEST_SKIP() << "SCHED_FIFO at priority 99 refused (an RLIMIT_RTPRIO below 99)";
  ASSERT_EQ(hold_error, 0);

  ASSERT_GT(held_to, held_from);
  bool seen = false;
  for (const Stall& stall : stalls) {
    EXPECT_LE(stall.start_s, stall.end_s);
    EXPECT_GE(stall.end_s - stall.start_s, kStallMs / 1000);
    if (stall.cpu != 0 || stall.start_s > held_to || stall.end_s < held_from) continue;
    // The watcher's deadline fell within the hold (at most a period after
    // it began) and it ran only once the holder let go.
    EXPECT_LE(stall.start_s, held_from + 0.0011);
    EXPECT_GE(stall.end_s, held_to);
    seen = true;
  }
  EXPECT_TRUE(seen) << "no stall of CPU 0 over the hold at " << held_from << "-" << held_to << " s";
  for (std::size_t i = 1; i < stalls.size(); ++i) EXPECT_LE(stalls[i - 1].start_s, stalls[i].start_s);
}

}  // namespace
}  // namespace tumble::bench
