// TickTiming: step-time quantiles over a bounded window and the real-time
// factor over about the last second.
#include "sim/tick_timing.h"

#include <gtest/gtest.h>

#include <thread>

namespace tumble::sim {
namespace {

using Clock = TickTiming::Clock;
using std::chrono::milliseconds;

TEST(TickTiming, NothingRecordedReadsZero) {
  const TickTiming timing;
  EXPECT_EQ(timing.step_ms_quantile(0.5), 0.0);
  EXPECT_EQ(timing.real_time_factor(), 0.0);
}

TEST(TickTiming, QuantilesAreNearestRank) {
  TickTiming timing;
  for (int ms = 100; ms >= 1; --ms) timing.record_step(ms, ms / 4.0);  // 1..100 ms, in any order
  EXPECT_EQ(timing.step_ms_quantile(0.5), 50.0);
  EXPECT_EQ(timing.step_ms_quantile(0.99), 99.0);
  EXPECT_EQ(timing.step_ms_quantile(1.0), 100.0);
  EXPECT_EQ(timing.step_cpu_ms_quantile(0.5), 12.5);
  EXPECT_EQ(timing.step_cpu_ms_quantile(1.0), 25.0);
  EXPECT_EQ(timing.start_late_ms_quantile(0.99), 0.0) << "nothing recorded";
  for (int i = 0; i < 99; ++i) timing.record_start_late(0.25);
  timing.record_start_late(8);
  EXPECT_EQ(timing.start_late_ms_quantile(0.5), 0.25);
  EXPECT_EQ(timing.start_late_ms_quantile(0.99), 0.25);
  EXPECT_EQ(timing.start_late_ms_quantile(1.0), 8.0);
}

TEST(TickTiming, ThreadCpuTimeCountsOnlyThisThreadsWork) {
  const double before = TickTiming::thread_cpu_ms();
  // Another thread works 50 ms of its CPU time while this one waits for
  // it: next to nothing here (a process-wide clock would read 50).
  std::thread other([] {
    const double from = TickTiming::thread_cpu_ms();
    volatile double sink = 0;
    while (TickTiming::thread_cpu_ms() - from < 50) sink = sink + 1;
  });
  other.join();
  EXPECT_LT(TickTiming::thread_cpu_ms() - before, 25.0);
  // This thread's own work counts: 100 ms of spinning on the wall clock
  // gives it at least a millisecond of CPU however busy the machine.
  const Clock::time_point until = Clock::now() + milliseconds(100);
  volatile double sink = 0;
  while (Clock::now() < until) sink = sink + 1;
  EXPECT_GT(TickTiming::thread_cpu_ms() - before, 1.0);
}

TEST(TickTiming, OnlyTheLastWindowOfStepsCounts) {
  TickTiming timing;
  for (std::size_t i = 0; i < TickTiming::kStepWindow; ++i) timing.record_step(1000, 1);
  for (std::size_t i = 0; i < TickTiming::kStepWindow; ++i) timing.record_step(2, 1);
  EXPECT_EQ(timing.step_ms_quantile(0.99), 2.0);
}

TEST(TickTiming, RealTimeFactorOverTheLastSecond) {
  TickTiming timing;
  const Clock::time_point t0 = Clock::now();
  // Two seconds at half speed, then one at double speed: only the last second counts.
  for (int i = 0; i <= 200; ++i) timing.record_clock(t0 + milliseconds(10 * i), 0.005 * i);
  for (int i = 1; i <= 100; ++i) timing.record_clock(t0 + milliseconds(2000 + 10 * i), 1.0 + 0.02 * i);
  EXPECT_NEAR(timing.real_time_factor(), 2.0, 1e-9);
}

TEST(TickTiming, PausedSimTimeGivesZero) {
  TickTiming timing;
  const Clock::time_point t0 = Clock::now();
  for (int i = 0; i < 10; ++i) timing.record_clock(t0 + milliseconds(10 * i), 3.0);
  EXPECT_EQ(timing.real_time_factor(), 0.0);
}

}  // namespace
}  // namespace tumble::sim
