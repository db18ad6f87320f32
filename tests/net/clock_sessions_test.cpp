// The clock under two sessions on a real socket: every ordered pair of
// clock requests (Pause, Resume, Step, Reset, SetTickRate), the first from
// session A and the second from session B, on a paused world. Every request
// is answered exactly once, a Step cut short says by what and how far it
// got, and a world left paused keeps its tick. A Step whose session is gone
// breaks nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <tuple>
#include <vector>

#include "clock_requests.h"
#include "raw_client.h"
#include "requests.h"
#include "test_scenes.h"
#include "test_server.h"

namespace tumble::test {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// A's Step: the most a Step may ask for, so it is still under way for
// B's request (seconds of stepping, against milliseconds of round trips).
constexpr std::uint32_t kLongStep = 1000000;
// B's Step, which nothing cuts short.
constexpr std::uint32_t kShortStep = 5;

// A connection that keeps every reply it reads, by request id, so that a
// reply that comes twice, or to a request never sent, is seen.
class Session {
 public:
  explicit Session(std::uint16_t port) : client_(port) { EXPECT_TRUE(client_.handshake()); }

  void send(const ClientMessage& message) {
    sent_.push_back(message.request_id());
    EXPECT_TRUE(client_.send(message));
  }

  // Reads until request `id` has a reply, keeping every reply on the way;
  // its first reply, or an empty message when none came.
  ServerMessage await(std::uint64_t id) {
    if (replies_[id].empty()) {
      (void)client_.read_until([&](const ServerMessage& m) {
        const std::uint64_t to = request_id_of(m);
        if (to != 0) replies_[to].push_back(m);
        return to == id;
      });
    }
    EXPECT_FALSE(replies_[id].empty()) << "no reply to request " << id;
    return replies_[id].empty() ? ServerMessage{} : replies_[id].front();
  }

  ServerMessage call(const ClientMessage& message) {
    send(message);
    return await(message.request_id());
  }

  // Every request sent has exactly one reply, and no other reply came.
  // Call after a last request whose reply comes after all the others.
  void expect_each_answered_once(const std::string& who) {
    for (std::uint64_t id : sent_) EXPECT_EQ(replies_[id].size(), 1u) << who << "'s request " << id;
    for (const auto& [id, replies] : replies_) {
      EXPECT_NE(std::find(sent_.begin(), sent_.end(), id), sent_.end()) << who << " got a reply to " << id;
    }
  }

 private:
  static std::uint64_t request_id_of(const ServerMessage& m) {
    if (m.has_ack()) return m.ack().request_id();
    if (m.has_error()) return m.error().request_id();
    if (m.has_stats()) return m.stats().request_id();
    if (m.has_body_list()) return m.body_list().request_id();
    if (m.has_subscribed()) return m.subscribed().request_id();
    return 0;
  }

  RawClient client_;
  std::vector<std::uint64_t> sent_;
  std::map<std::uint64_t, std::vector<ServerMessage>> replies_;
};

// Asks `session` for stats until the paused world's tick has moved past
// `from` (a Step is under way); each answer comes from a later pass of the
// sim loop. The tick reached.
std::uint64_t await_stepping(Session& session, std::uint64_t from, std::uint64_t& next_id) {
  for (int i = 0; i < 5000; ++i) {
    const ServerMessage stats = session.call(get_stats(next_id++));
    if (!stats.has_stats()) break;
    EXPECT_TRUE(stats.stats().paused());
    if (stats.stats().tick() > from) return stats.stats().tick();
  }
  ADD_FAILURE() << "the Step never moved the tick from " << from;
  return from;
}

void expect_ack(const ServerMessage& reply, std::uint64_t tick, const std::string& what) {
  ASSERT_TRUE(reply.has_ack()) << what << ": " << reply.DebugString();
  EXPECT_EQ(reply.ack().applied_tick(), tick) << what;
  EXPECT_FALSE(reply.ack().has_step_ticks_left()) << what;
  EXPECT_EQ(reply.ack().step_ended_by(), tumble::v1::STEP_END_UNSPECIFIED) << what;
}

// The Ack of a Step of `asked` ticks from tick `from`, ended by `end`: the
// ticks left are those it did not step. Returns the tick it reached.
std::uint64_t expect_step_ack(const ServerMessage& reply, std::uint64_t from, std::uint32_t asked,
                              tumble::v1::StepEnd end, const std::string& what) {
  EXPECT_TRUE(reply.has_ack()) << what << ": " << reply.DebugString();
  const auto& ack = reply.ack();
  EXPECT_EQ(ack.step_ended_by(), end) << what;
  EXPECT_TRUE(ack.has_step_ticks_left()) << what;
  EXPECT_GE(ack.applied_tick(), from) << what;
  EXPECT_EQ(ack.applied_tick() - from + ack.step_ticks_left(), asked) << what << ": stepped plus left";
  if (end != tumble::v1::STEP_END_COMPLETED) {
    EXPECT_GT(ack.step_ticks_left(), 0u) << what;
  }
  return ack.applied_tick();
}

void expect_refused(const ServerMessage& reply, const std::string& what) {
  ASSERT_TRUE(reply.has_error()) << what << ": " << reply.DebugString();
  EXPECT_EQ(reply.error().code(), tumble::v1::FAILED_PRECONDITION) << what;
}

using Pair = std::tuple<ClockRequest, ClockRequest>;

class ClockSessionsTest : public ::testing::TestWithParam<Pair> {};

TEST_P(ClockSessionsTest, EachIsAnsweredOnceAndAPausedTickStays) {
  const auto [first, second] = GetParam();
  TestServer server(kCrateAndBallScene);
  Session a(server.port());
  Session b(server.port());
  std::uint64_t b_id = 100;  // B's next request id

  const ServerMessage paused = a.call(clock_request(ClockRequest::pause, 1, 0));
  ASSERT_TRUE(paused.has_ack());
  const std::uint64_t t0 = paused.ack().applied_tick();

  // A's request. A Step is answered later; B waits until it is under way.
  bool running = false;
  bool stepping = false;
  switch (first) {
    case ClockRequest::step:
      a.send(clock_request(first, 2, kLongStep));
      await_stepping(b, t0, b_id);
      stepping = true;
      break;
    case ClockRequest::resume:
      expect_ack(a.call(clock_request(first, 2, 0)), t0 + 1, "A's Resume");
      running = true;
      break;
    case ClockRequest::set_tick_rate:
      expect_ack(a.call(clock_request(first, 2, 0)), t0 + 1, "A's SetTickRate");
      break;
    case ClockRequest::pause:
    case ClockRequest::reset:
      expect_ack(a.call(clock_request(first, 2, 0)), t0, std::string("A's ") + name_of(first));
      break;
  }

  // B's request, then what it did to A's Step and to the clock.
  const std::string what = std::string("B's ") + name_of(second);
  const ServerMessage reply = b.call(clock_request(second, b_id++, kShortStep));
  std::optional<std::uint64_t> paused_at;  // the tick a world left paused must keep
  if (stepping) {
    switch (second) {
      case ClockRequest::pause:
      case ClockRequest::reset: {
        const auto end = second == ClockRequest::pause ? tumble::v1::STEP_END_PAUSE : tumble::v1::STEP_END_RESET;
        const std::uint64_t reached = expect_step_ack(a.await(2), t0, kLongStep, end, "A's Step");
        expect_ack(reply, reached, what);
        paused_at = reached;
        break;
      }
      case ClockRequest::resume: {
        const std::uint64_t reached =
            expect_step_ack(a.await(2), t0, kLongStep, tumble::v1::STEP_END_RESUME, "A's Step");
        expect_ack(reply, reached + 1, what);
        break;
      }
      case ClockRequest::step:
      case ClockRequest::set_tick_rate: {
        // A's Step goes on: still under way for the Pause that ends it.
        if (second == ClockRequest::step) {
          expect_refused(reply, what);
        } else {
          ASSERT_TRUE(reply.has_ack()) << reply.DebugString();
        }
        const ServerMessage pause = b.call(clock_request(ClockRequest::pause, b_id++, 0));
        const std::uint64_t reached =
            expect_step_ack(a.await(2), t0, kLongStep, tumble::v1::STEP_END_PAUSE, "A's Step, after " + what);
        expect_ack(pause, reached, "B's Pause");
        if (second == ClockRequest::set_tick_rate) {
          EXPECT_LE(reply.ack().applied_tick(), reached + 1);
        }
        paused_at = reached;
        break;
      }
    }
  } else if (running) {
    switch (second) {
      case ClockRequest::pause:
        ASSERT_TRUE(reply.has_ack()) << reply.DebugString();
        EXPECT_GT(reply.ack().applied_tick(), t0) << what;
        paused_at = reply.ack().applied_tick();
        break;
      case ClockRequest::step:
        expect_refused(reply, what);
        break;
      case ClockRequest::resume:
      case ClockRequest::reset:
      case ClockRequest::set_tick_rate:
        ASSERT_TRUE(reply.has_ack()) << reply.DebugString();
        EXPECT_GT(reply.ack().applied_tick(), t0 + 1) << what;
        break;
    }
  } else {
    switch (second) {
      case ClockRequest::pause:
      case ClockRequest::reset:
        expect_ack(reply, t0, what);
        paused_at = t0;
        break;
      case ClockRequest::resume:
        expect_ack(reply, t0 + 1, what);
        break;
      case ClockRequest::step:
        expect_step_ack(reply, t0, kShortStep, tumble::v1::STEP_END_COMPLETED, what);
        EXPECT_EQ(reply.ack().applied_tick(), t0 + kShortStep) << what;
        paused_at = t0 + kShortStep;
        break;
      case ClockRequest::set_tick_rate:
        expect_ack(reply, t0 + 1, what);
        paused_at = t0;
        break;
    }
  }

  // Last requests, answered after everything else each session asked.
  const ServerMessage a_stats = a.call(get_stats(9));
  const ServerMessage b_stats = b.call(get_stats(b_id++));
  a.expect_each_answered_once("A");
  b.expect_each_answered_once("B");
  ASSERT_TRUE(a_stats.has_stats() && b_stats.has_stats());
  EXPECT_EQ(b_stats.stats().paused(), paused_at.has_value());
  if (paused_at) {
    EXPECT_EQ(a_stats.stats().tick(), *paused_at);
    EXPECT_EQ(b_stats.stats().tick(), *paused_at) << "paused, with no Step under way";
  }
}

std::string pair_name(const ::testing::TestParamInfo<Pair>& info) {
  return std::string(name_of(std::get<0>(info.param))) + "Then" + name_of(std::get<1>(info.param));
}

const auto kEveryRequest = ::testing::Values(ClockRequest::pause, ClockRequest::resume, ClockRequest::step,
                                             ClockRequest::reset, ClockRequest::set_tick_rate);

INSTANTIATE_TEST_SUITE_P(EveryOrderedPair, ClockSessionsTest, ::testing::Combine(kEveryRequest, kEveryRequest),
                         pair_name);

// A pauses, steps a million ticks and goes away. B's Resume and Pause are
// answered, the world stays paused, and B's own Step runs.
TEST(ClockSessions, AStepWhoseSessionIsGoneBreaksNothing) {
  TestServer server(kCrateAndBallScene);
  Session b(server.port());
  std::uint64_t b_id = 100;
  std::uint64_t t0 = 0;
  {
    Session a(server.port());
    const ServerMessage paused = a.call(clock_request(ClockRequest::pause, 1, 0));
    ASSERT_TRUE(paused.has_ack());
    t0 = paused.ack().applied_tick();
    a.send(clock_request(ClockRequest::step, 2, kLongStep));
    await_stepping(b, t0, b_id);
  }
  const ServerMessage resumed = b.call(clock_request(ClockRequest::resume, b_id++, 0));
  ASSERT_TRUE(resumed.has_ack()) << resumed.DebugString();
  EXPECT_GT(resumed.ack().applied_tick(), t0 + 1);
  const ServerMessage paused = b.call(clock_request(ClockRequest::pause, b_id++, 0));
  ASSERT_TRUE(paused.has_ack()) << paused.DebugString();
  const std::uint64_t at = paused.ack().applied_tick();
  EXPECT_EQ(b.call(get_stats(b_id++)).stats().tick(), at);
  const ServerMessage stepped = b.call(clock_request(ClockRequest::step, b_id++, kShortStep));
  expect_step_ack(stepped, at, kShortStep, tumble::v1::STEP_END_COMPLETED, "B's Step");
  EXPECT_EQ(stepped.ack().applied_tick(), at + kShortStep);
  EXPECT_EQ(b.call(get_stats(b_id++)).stats().tick(), at + kShortStep);
  b.expect_each_answered_once("B");
}

}  // namespace
}  // namespace tumble::test
