// The clock under two clients: every ordered pair of clock requests (Pause,
// Resume, Step, Reset, SetTickRate), the first from client A and the second
// from client B, from a paused and from a running world, stepped pass by
// pass with run_tick(). Each request is answered exactly once, at the tick
// the contract gives (protocol.proto, Step), and a paused world's tick
// moves only through a Step.
#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "clock_requests.h"
#include "sim/request_check.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "test_scenes.h"

namespace tumble::sim {
namespace {

using tumble::test::clock_request;
using tumble::test::ClockRequest;
using tumble::test::name_of;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;
using tumble::v1::StepEnd;

// A free box in zero gravity: every tick is a step of the same small world.
enum class ClockStart { paused, running };

// run_tick() steps one tick of a Step a pass, so a Step of 4 ticks is
// still under way on the pass after the one that takes it up.
constexpr std::uint32_t kStepTicks = 4;
constexpr std::uint64_t kStartTick = 3;
// Passes after B's request: more than a Step needs to finish.
constexpr int kSettlePasses = 8;

// One Simulation and the replies its clients got, every one kept (so a
// second reply to a request is seen), checking after each pass that a
// world paused for the whole pass moved only through a Step.
class TwoClients {
 public:
  TwoClients() {
    tumble::v1::Scene scene;
    EXPECT_TRUE(parse_scene_json(test::kCrateScene, &scene).ok());
    const Status status = Simulation::create(scene, SimConfig{}, &sim_);
    EXPECT_TRUE(status.ok()) << status.message();
  }

  Simulation& sim() { return *sim_; }

  // Submits as the network layer does: checked first, refused at once.
  void submit(const ClientMessage& message) {
    ASSERT_FALSE(check_request(message).has_value()) << message.DebugString();
    if (message.has_step()) open_steps_.push_back(message.request_id());
    sim_->submit(Command{
        message, [this, id = message.request_id()](ServerMessage reply) { replies_[id].push_back(std::move(reply)); }});
  }

  // One pass of the loop. A world that is paused once the pass has
  // applied its commands steps only for a Step that was open in it.
  void pass() {
    const std::uint64_t before = sim_->tick();
    const bool step_open = any_step_open();
    sim_->run_tick();
    if (sim_->paused() && sim_->tick() != before) {
      EXPECT_TRUE(step_open) << "paused, the tick moved from " << before << " to " << sim_->tick() << " with no Step";
      EXPECT_EQ(sim_->tick(), before + 1) << "run_tick() steps one tick of a Step a pass";
    }
  }

  void passes(int n) {
    for (int i = 0; i < n; ++i) pass();
  }

  // Every reply to request `id`; exactly one is expected.
  const std::vector<ServerMessage>& replies_to(std::uint64_t id) { return replies_[id]; }

 private:
  bool any_step_open() {
    for (std::uint64_t id : open_steps_) {
      if (replies_[id].empty()) return true;
    }
    return false;
  }

  std::unique_ptr<Simulation> sim_;
  std::map<std::uint64_t, std::vector<ServerMessage>> replies_;
  std::vector<std::uint64_t> open_steps_;
};

// What a request is answered with.
struct Expected {
  bool refused = false;  // FAILED_PRECONDITION
  std::uint64_t tick = 0;
  StepEnd end = tumble::v1::STEP_END_UNSPECIFIED;  // a Step's Ack
  std::uint32_t left = 0;                          // a Step's ticks left
};

Expected ack(std::uint64_t tick) { return {false, tick}; }
Expected refused() { return {true}; }
Expected step_ack(std::uint64_t tick, StepEnd end, std::uint32_t left) { return {false, tick, end, left}; }

constexpr StepEnd kCompleted = tumble::v1::STEP_END_COMPLETED;
constexpr StepEnd kByPause = tumble::v1::STEP_END_PAUSE;
constexpr StepEnd kByResume = tumble::v1::STEP_END_RESUME;
constexpr StepEnd kByReset = tumble::v1::STEP_END_RESET;

void expect_reply(const std::vector<ServerMessage>& replies, const Expected& expected, const std::string& what) {
  ASSERT_EQ(replies.size(), 1u) << what << ": answered " << replies.size() << " times, not once";
  const ServerMessage& reply = replies.front();
  if (expected.refused) {
    ASSERT_TRUE(reply.has_error()) << what << ": " << reply.DebugString();
    EXPECT_EQ(reply.error().code(), tumble::v1::FAILED_PRECONDITION) << what;
    return;
  }
  ASSERT_TRUE(reply.has_ack()) << what << ": " << reply.DebugString();
  EXPECT_EQ(reply.ack().applied_tick(), expected.tick) << what;
  EXPECT_EQ(reply.ack().step_ended_by(), expected.end) << what;
  if (expected.end == tumble::v1::STEP_END_UNSPECIFIED) {
    EXPECT_FALSE(reply.ack().has_step_ticks_left()) << what << ": not a Step";
  } else {
    ASSERT_TRUE(reply.ack().has_step_ticks_left()) << what;
    EXPECT_EQ(reply.ack().step_ticks_left(), expected.left) << what;
  }
}

// One ordered pair: from `start` at tick 3, A's request, a pass, B's
// request, a pass, then kSettlePasses passes. A's Step is of kStepTicks,
// as is B's.
struct PairCase {
  ClockStart start;
  ClockRequest first;
  ClockRequest second;
  Expected first_reply;
  Expected second_reply;
  bool paused_after;
  std::uint64_t tick_after;
};

// gtest names the case by pair_name(); this is what it prints of one.
void PrintTo(const PairCase& c, std::ostream* os) {
  *os << (c.start == ClockStart::paused ? "paused, " : "running, ") << name_of(c.first) << " then "
      << name_of(c.second);
}

using R = ClockRequest;
constexpr ClockStart kPaused = ClockStart::paused;
constexpr ClockStart kRunning = ClockStart::running;

// Paused at tick 3, or running through tick 3 (a running pass steps once).
const PairCase kPairs[] = {
    // Paused: a Pause, Reset or SetTickRate leaves the world paused at 3.
    {kPaused, R::pause, R::pause, ack(3), ack(3), true, 3},
    {kPaused, R::pause, R::resume, ack(3), ack(4), false, 12},
    {kPaused, R::pause, R::step, ack(3), step_ack(7, kCompleted, 0), true, 7},
    {kPaused, R::pause, R::reset, ack(3), ack(3), true, 3},
    {kPaused, R::pause, R::set_tick_rate, ack(3), ack(4), true, 3},
    {kPaused, R::reset, R::pause, ack(3), ack(3), true, 3},
    {kPaused, R::reset, R::resume, ack(3), ack(4), false, 12},
    {kPaused, R::reset, R::step, ack(3), step_ack(7, kCompleted, 0), true, 7},
    {kPaused, R::reset, R::reset, ack(3), ack(3), true, 3},
    {kPaused, R::reset, R::set_tick_rate, ack(3), ack(4), true, 3},
    {kPaused, R::set_tick_rate, R::pause, ack(4), ack(3), true, 3},
    {kPaused, R::set_tick_rate, R::resume, ack(4), ack(4), false, 12},
    {kPaused, R::set_tick_rate, R::step, ack(4), step_ack(7, kCompleted, 0), true, 7},
    {kPaused, R::set_tick_rate, R::reset, ack(4), ack(3), true, 3},
    {kPaused, R::set_tick_rate, R::set_tick_rate, ack(4), ack(4), true, 3},
    // Paused, A resumes: running through tick 4 when B's request comes.
    {kPaused, R::resume, R::pause, ack(4), ack(4), true, 4},
    {kPaused, R::resume, R::resume, ack(4), ack(5), false, 13},
    {kPaused, R::resume, R::step, ack(4), refused(), false, 13},
    {kPaused, R::resume, R::reset, ack(4), ack(5), false, 13},
    {kPaused, R::resume, R::set_tick_rate, ack(4), ack(5), false, 13},
    // Paused, A steps: one tick of four done (tick 4) when B's request comes.
    {kPaused, R::step, R::pause, step_ack(4, kByPause, 3), ack(4), true, 4},
    {kPaused, R::step, R::resume, step_ack(4, kByResume, 3), ack(5), false, 13},
    {kPaused, R::step, R::step, step_ack(7, kCompleted, 0), refused(), true, 7},
    {kPaused, R::step, R::reset, step_ack(4, kByReset, 3), ack(4), true, 4},
    {kPaused, R::step, R::set_tick_rate, step_ack(7, kCompleted, 0), ack(5), true, 7},
    // Running: A pauses at 3, and B's request finds a paused world.
    {kRunning, R::pause, R::pause, ack(3), ack(3), true, 3},
    {kRunning, R::pause, R::resume, ack(3), ack(4), false, 12},
    {kRunning, R::pause, R::step, ack(3), step_ack(7, kCompleted, 0), true, 7},
    {kRunning, R::pause, R::reset, ack(3), ack(3), true, 3},
    {kRunning, R::pause, R::set_tick_rate, ack(3), ack(4), true, 3},
    // Running: anything else leaves it running through tick 4.
    {kRunning, R::resume, R::pause, ack(4), ack(4), true, 4},
    {kRunning, R::resume, R::resume, ack(4), ack(5), false, 13},
    {kRunning, R::resume, R::step, ack(4), refused(), false, 13},
    {kRunning, R::resume, R::reset, ack(4), ack(5), false, 13},
    {kRunning, R::resume, R::set_tick_rate, ack(4), ack(5), false, 13},
    {kRunning, R::step, R::pause, refused(), ack(4), true, 4},
    {kRunning, R::step, R::resume, refused(), ack(5), false, 13},
    {kRunning, R::step, R::step, refused(), refused(), false, 13},
    {kRunning, R::step, R::reset, refused(), ack(5), false, 13},
    {kRunning, R::step, R::set_tick_rate, refused(), ack(5), false, 13},
    {kRunning, R::reset, R::pause, ack(4), ack(4), true, 4},
    {kRunning, R::reset, R::resume, ack(4), ack(5), false, 13},
    {kRunning, R::reset, R::step, ack(4), refused(), false, 13},
    {kRunning, R::reset, R::reset, ack(4), ack(5), false, 13},
    {kRunning, R::reset, R::set_tick_rate, ack(4), ack(5), false, 13},
    {kRunning, R::set_tick_rate, R::pause, ack(4), ack(4), true, 4},
    {kRunning, R::set_tick_rate, R::resume, ack(4), ack(5), false, 13},
    {kRunning, R::set_tick_rate, R::step, ack(4), refused(), false, 13},
    {kRunning, R::set_tick_rate, R::reset, ack(4), ack(5), false, 13},
    {kRunning, R::set_tick_rate, R::set_tick_rate, ack(4), ack(5), false, 13},
};

class ClockPairTest : public ::testing::TestWithParam<PairCase> {};

TEST_P(ClockPairTest, EachIsAnsweredOnceAtItsTickAndAPausedTickStays) {
  const PairCase& c = GetParam();
  TwoClients clients;
  clients.passes(static_cast<int>(kStartTick));
  if (c.start == ClockStart::paused) {
    clients.submit(clock_request(R::pause, 1, kStepTicks));
    clients.pass();
    ASSERT_EQ(clients.replies_to(1).size(), 1u);
  }
  ASSERT_EQ(clients.sim().tick(), kStartTick);
  ASSERT_EQ(clients.sim().paused(), c.start == ClockStart::paused);

  clients.submit(clock_request(c.first, 10, kStepTicks));  // client A
  clients.pass();
  clients.submit(clock_request(c.second, 20, kStepTicks));  // client B
  clients.pass();
  clients.passes(kSettlePasses);

  expect_reply(clients.replies_to(10), c.first_reply, std::string("A's ") + name_of(c.first));
  expect_reply(clients.replies_to(20), c.second_reply, std::string("B's ") + name_of(c.second));
  EXPECT_EQ(clients.sim().paused(), c.paused_after);
  EXPECT_EQ(clients.sim().tick(), c.tick_after);
  if (c.paused_after) {
    clients.passes(kSettlePasses);
    EXPECT_EQ(clients.sim().tick(), c.tick_after) << "paused, with no Step under way";
  }
}

std::string pair_name(const ::testing::TestParamInfo<PairCase>& info) {
  const PairCase& c = info.param;
  return std::string(c.start == ClockStart::paused ? "Paused" : "Running") + name_of(c.first) + "Then" +
         name_of(c.second);
}

INSTANTIATE_TEST_SUITE_P(EveryOrderedPair, ClockPairTest, ::testing::ValuesIn(kPairs), pair_name);

TEST(ClockPairs, TheTableHoldsEveryOrderedPairFromBothStarts) {
  std::map<std::string, int> seen;
  for (const PairCase& c : kPairs) {
    ++seen[std::to_string(static_cast<int>(c.start)) + name_of(c.first) + name_of(c.second)];
  }
  EXPECT_EQ(seen.size(), 2u * 5u * 5u);
  for (const auto& [pair, count] : seen) EXPECT_EQ(count, 1) << pair;
}

// The report this contract answers: A pauses and steps 300000 ticks, B
// resumes while the Step is under way. A is answered at once with the tick
// it reached, a later Pause stops the world for good, and a Step is
// accepted again.
TEST(ClockPairs, AResumeAnswersALongStepAndALaterPauseHolds) {
  TwoClients clients;
  clients.submit(clock_request(R::pause, 1, kStepTicks));
  clients.pass();
  clients.submit(clock_request(R::step, 2, 300000));
  clients.passes(5);
  ASSERT_TRUE(clients.replies_to(2).empty()) << "under way";
  clients.submit(clock_request(R::resume, 3, kStepTicks));
  clients.pass();
  expect_reply(clients.replies_to(2), step_ack(5, kByResume, 300000 - 5), "the long Step");
  expect_reply(clients.replies_to(3), ack(6), "the Resume");

  clients.passes(4);
  clients.submit(clock_request(R::pause, 4, kStepTicks));
  clients.pass();
  expect_reply(clients.replies_to(4), ack(10), "the Pause");
  clients.passes(50);
  EXPECT_EQ(clients.sim().tick(), 10u) << "paused means paused";

  clients.submit(clock_request(R::step, 5, 3));
  clients.passes(3);
  expect_reply(clients.replies_to(5), step_ack(13, kCompleted, 0), "a new Step");
}

// A Step whose client is gone (its reply goes nowhere) is ended like any
// other, and the next client's Step runs.
TEST(ClockPairs, AStepWithNoOneToAnswerEndsQuietly) {
  TwoClients clients;
  clients.submit(clock_request(R::pause, 1, kStepTicks));
  clients.pass();
  ClientMessage orphan = clock_request(R::step, 2, 1000);
  clients.sim().submit(Command{orphan, nullptr});
  for (int i = 0; i < 3; ++i) clients.sim().run_tick();  // not pass(): this Step is open without a reply to await
  EXPECT_EQ(clients.sim().tick(), 3u);
  clients.submit(clock_request(R::pause, 3, kStepTicks));
  clients.pass();
  expect_reply(clients.replies_to(3), ack(3), "the Pause");
  clients.submit(clock_request(R::step, 4, 2));
  clients.passes(2);
  expect_reply(clients.replies_to(4), step_ack(5, kCompleted, 0), "the next Step");
}

}  // namespace
}  // namespace tumble::sim
