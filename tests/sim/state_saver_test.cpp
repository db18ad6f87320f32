// StateSaver's report, which Stats.checkpoints carries: what was written,
// what failed, and how long the last write took.
#include "sim/state_saver.h"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>

#include "poll_until.h"

namespace tumble::sim {
namespace {

std::shared_ptr<const tumble::v1::WorldState> state_at(std::uint64_t tick, int bodies) {
  auto state = std::make_shared<tumble::v1::WorldState>();
  state->set_tick(tick);
  for (int i = 0; i < bodies; ++i) state->add_bodies()->set_id(static_cast<std::uint32_t>(i + 1));
  return state;
}

TEST(StateSaver, ReportsTheLastCheckpointWrittenAndCountsTheFailures) {
  // Even ticks are written, taking at least 5 ms; odd ones fail.
  StateSaver saver("bucket b, key k", [](const tumble::v1::WorldState& state) {
    if (state.tick() % 2 == 1) return Status::error("refused");
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(5);
    while (std::chrono::steady_clock::now() < until) {
    }
    return Status{};
  });
  EXPECT_EQ(saver.destination(), "bucket b, key k");
  EXPECT_EQ(saver.report().written, 0u);

  const auto written = state_at(10, 3);
  saver.offer(written, std::chrono::milliseconds(7));
  ASSERT_TRUE(test::poll_until([&] { return saver.written() == 1; }));
  saver.offer(state_at(11, 7), std::chrono::milliseconds(2));
  saver.stop();  // writes what is waiting first

  const StateSaver::Report report = saver.report();
  EXPECT_EQ(report.written, 1u);
  EXPECT_EQ(report.failed, 1u);
  EXPECT_EQ(report.last_tick, 10u) << "a failed write is not the last checkpoint";
  EXPECT_EQ(report.last_bytes, written->ByteSizeLong());
  EXPECT_GE(report.last_write_ms, 5.0);
  EXPECT_EQ(report.write_ms_max, report.last_write_ms);
  // The capture times are those of the states offered, failed or not.
  EXPECT_EQ(report.last_capture_ms, 2.0);
  EXPECT_EQ(report.capture_ms_max, 7.0);
}

}  // namespace
}  // namespace tumble::sim
