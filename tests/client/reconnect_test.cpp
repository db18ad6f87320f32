// `tumble subscribe --reconnect`: the backoff between attempts, which
// failures are worth another attempt, and the command itself against a
// scripted server that drops it, refuses it and takes it back.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <future>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "command_line.h"
#include "command_line_helpers.h"
#include "commands.h"
#include "reconnect_policy.h"
#include "scripted_messages.h"
#include "scripted_server.h"

namespace tumble::cli {
namespace {

using namespace std::chrono_literals;
using client::testing::accept_hello;
using client::testing::ScriptedServer;
using client::testing::ServerPeer;
using nlohmann::json;

TEST(ReconnectBackoff, DoublesFromATenthOfASecondToTheCapShortenedByAtMostAQuarter) {
  ReconnectBackoff backoff(5000ms, 7);
  const std::vector<std::chrono::milliseconds> bases = {100ms, 200ms, 400ms, 800ms, 1600ms, 3200ms, 5000ms, 5000ms};
  for (const std::chrono::milliseconds base : bases) {
    EXPECT_EQ(backoff.base_wait(), base);
    const std::chrono::milliseconds wait = backoff.next_wait();
    EXPECT_LE(wait, base);
    EXPECT_GE(wait, base * 3 / 4);
  }
}

TEST(ReconnectBackoff, TheJitterSpreadsTheWaitsAndTheSeedFixesThem) {
  ReconnectBackoff first(100ms, 1);
  ReconnectBackoff again(100ms, 1);
  std::vector<std::chrono::milliseconds> waits;
  for (int i = 0; i < 50; ++i) {
    waits.push_back(first.next_wait());
    EXPECT_EQ(again.next_wait(), waits.back()) << "the same seed gives the same waits";
    EXPECT_GE(waits.back(), 75ms);
    EXPECT_LE(waits.back(), 100ms);
  }
  const auto [shortest, longest] = std::minmax_element(waits.begin(), waits.end());
  EXPECT_LT(*shortest, *longest) << "fifty waits at the cap, all the same: no jitter";
}

TEST(ReconnectBackoff, ResetStartsAgainAndASmallCapBoundsEveryWait) {
  ReconnectBackoff backoff(5000ms, 3);
  for (int i = 0; i < 5; ++i) backoff.next_wait();
  EXPECT_EQ(backoff.base_wait(), 3200ms);
  backoff.reset();
  EXPECT_EQ(backoff.base_wait(), 100ms);

  ReconnectBackoff small(40ms, 3);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(small.base_wait(), 40ms);
    EXPECT_LE(small.next_wait(), 40ms);
  }
}

TEST(WorthReconnecting, LostAndRefusedConnectionsButNotRefusalsOfTheRequest) {
  using client::Failure;
  using client::FailureKind;
  EXPECT_TRUE(worth_reconnecting(Failure{FailureKind::connect, "cannot connect: Connection refused"}));
  EXPECT_TRUE(worth_reconnecting(Failure{FailureKind::closed, "connection closed by the server"}));
  EXPECT_TRUE(worth_reconnecting(Failure{FailureKind::timeout, "timed out"}));
  EXPECT_TRUE(worth_reconnecting(Failure{FailureKind::server, "full", tumble::v1::RESOURCE_EXHAUSTED}));
  EXPECT_TRUE(worth_reconnecting(Failure{FailureKind::server, "slow hello", tumble::v1::HANDSHAKE_REQUIRED}));
  EXPECT_FALSE(worth_reconnecting(Failure{FailureKind::server, "bad token", tumble::v1::UNAUTHENTICATED}));
  EXPECT_FALSE(worth_reconnecting(Failure{FailureKind::server, "no such body", tumble::v1::UNKNOWN_BODY}));
  EXPECT_FALSE(worth_reconnecting(Failure{FailureKind::server, "old client", tumble::v1::UNSUPPORTED_VERSION}));
  EXPECT_FALSE(worth_reconnecting(Failure{FailureKind::protocol, "not a ServerMessage"}));
  EXPECT_FALSE(worth_reconnecting(Failure{FailureKind::invalid_argument, "bad host"}));
}

TEST(ReconnectCommandLine, FlagAndMaxWait) {
  using testing::expect_usage_error;
  using testing::parse_command;
  const auto plain = parse_command<SubscribeCommand>({"subscribe"});
  EXPECT_FALSE(plain.reconnect);
  EXPECT_EQ(plain.reconnect_max_wait, kReconnectDefaultMaxWait);
  const auto both = parse_command<SubscribeCommand>({"subscribe", "--reconnect", "--reconnect-max-wait", "0.25"});
  EXPECT_TRUE(both.reconnect);
  EXPECT_EQ(both.reconnect_max_wait, 250ms);
  expect_usage_error({"subscribe", "--reconnect-max-wait", "1"});  // needs --reconnect
  expect_usage_error({"subscribe", "--reconnect", "--reconnect-max-wait", "0"});
  expect_usage_error({"subscribe", "--reconnect", "--reconnect-max-wait", "soon"});
}

// Plays tumbled for one subscription: Welcome and an empty body list at
// `ticks[0]`, Subscribed as subscription 1, then a frame at each tick.
// Keeps the Subscribe it got in `*subscribe`.
void serve_frames(ServerPeer& peer, const std::vector<std::uint64_t>& ticks, tumble::v1::Subscribe* subscribe) {
  accept_hello(peer, ticks.front());
  auto list = peer.receive();
  ASSERT_TRUE(list.has_value() && list->has_list_bodies());
  peer.send(client::testing::body_list(list->request_id(), ticks.front()));
  auto request = peer.receive();
  ASSERT_TRUE(request.has_value() && request->has_subscribe());
  *subscribe = request->subscribe();
  tumble::v1::ServerMessage subscribed;
  subscribed.mutable_subscribed()->set_request_id(request->request_id());
  subscribed.mutable_subscribed()->set_subscription_id(1);
  peer.send(subscribed);
  for (const std::uint64_t tick : ticks) peer.send(client::testing::pose_frame(1, tick));
}

// `tumble --json subscribe --reconnect --count N` against `server`.
struct SubscribeRun {
  std::optional<client::Failure> failure;
  std::vector<json> frames;  // stdout, line by line
  std::string notes;         // stderr
};

SubscribeRun run_reconnecting(const ScriptedServer& server, std::uint64_t count, bool reconnect = true) {
  GlobalOptions global;
  global.server = server.endpoint();
  global.json = true;
  global.timeout = 5s;
  SubscribeCommand command;
  command.count = count;
  command.reconnect = reconnect;
  std::ostringstream out;
  std::ostringstream notes;
  SubscribeRun run;
  run.failure = run_subscribe(global, command, out, notes);
  std::istringstream lines(out.str());
  for (std::string line; std::getline(lines, line);) run.frames.push_back(json::parse(line, nullptr, false));
  run.notes = notes.str();
  return run;
}

std::vector<std::uint64_t> ticks_of(const std::vector<json>& frames) {
  std::vector<std::uint64_t> ticks;
  for (const json& frame : frames) ticks.push_back(frame.value("tick", std::uint64_t{0}));
  return ticks;
}

TEST(SubscribeReconnect, RidesThroughAClosedConnectionWithTheSameSubscribe) {
  tumble::v1::Subscribe first;
  tumble::v1::Subscribe second;
  ScriptedServer server({[&](ServerPeer& peer) {
                           serve_frames(peer, {100, 108}, &first);
                           peer.close();
                         },
                         [&](ServerPeer& peer) {
                           // A restarted server, further back: the frames go on from there.
                           serve_frames(peer, {50}, &second);
                           peer.wait_for_close();
                         }});
  const SubscribeRun run = run_reconnecting(server, 3);
  EXPECT_FALSE(run.failure) << run.failure->message;
  EXPECT_EQ(ticks_of(run.frames), (std::vector<std::uint64_t>{100, 108, 50})) << "--count spans both connections";
  for (const json& frame : run.frames) ASSERT_FALSE(frame.is_discarded()) << "stdout holds frames only";
  EXPECT_EQ(first.SerializeAsString(), second.SerializeAsString()) << "the same Subscribe again";
  const std::string where = tumble::to_string(server.endpoint());
  EXPECT_NE(run.notes.find("tumble: connection closed by the server; reconnecting in 0."), std::string::npos)
      << run.notes;
  EXPECT_NE(run.notes.find("tumble: reconnected to " + where + " at tick 50\n"), std::string::npos) << run.notes;
}

TEST(SubscribeReconnect, KeepsTryingWhileRefusedWaitingLongerEachTime) {
  tumble::v1::Subscribe subscribe;
  ScriptedServer server({[&](ServerPeer& peer) {
                          serve_frames(peer, {10, 18}, &subscribe);
                          peer.wait_for_close();
                        }},
                        700ms);
  const SubscribeRun run = run_reconnecting(server, 2);
  EXPECT_FALSE(run.failure) << run.failure->message;
  EXPECT_EQ(ticks_of(run.frames), (std::vector<std::uint64_t>{10, 18}));
  // One line per refused attempt, each with its wait: 0.1 s, then twice as
  // long each time, each shortened by at most a quarter.
  const std::regex refused("tumble: cannot connect to " + tumble::to_string(server.endpoint()) +
                           ": [^;\n]+; reconnecting in ([0-9.]+) s\n");
  std::vector<double> waits;
  for (auto it = std::sregex_iterator(run.notes.begin(), run.notes.end(), refused); it != std::sregex_iterator();
       ++it) {
    waits.push_back(std::stod((*it)[1]));
  }
  ASSERT_GE(waits.size(), 2u) << "700 ms of refusals outlast the first two waits (at most 0.1 and 0.2 s)\n"
                              << run.notes;
  double base = 0.1;
  for (const double wait : waits) {
    EXPECT_LE(wait, base + 0.005) << run.notes;
    EXPECT_GE(wait, 0.75 * base - 0.005) << run.notes;
    base *= 2;
  }
  EXPECT_NE(run.notes.find("tumble: reconnected to "), std::string::npos) << run.notes;
}

TEST(SubscribeReconnect, WithoutTheFlagALostConnectionEndsTheCommand) {
  tumble::v1::Subscribe subscribe;
  ScriptedServer server([&](ServerPeer& peer) {
    serve_frames(peer, {5}, &subscribe);
    peer.close();
  });
  const SubscribeRun run = run_reconnecting(server, 3, false);
  ASSERT_TRUE(run.failure);
  EXPECT_EQ(run.failure->kind, client::FailureKind::closed);
  EXPECT_EQ(ticks_of(run.frames), (std::vector<std::uint64_t>{5}));
  EXPECT_EQ(run.notes, "");
}

TEST(SubscribeReconnect, AnErrorAnotherAttemptWouldMeetAgainEndsTheCommand) {
  ScriptedServer server([](ServerPeer& peer) {
    accept_hello(peer);
    auto list = peer.receive();
    ASSERT_TRUE(list.has_value() && list->has_list_bodies());
    peer.send(client::testing::body_list(list->request_id(), 7));
    auto request = peer.receive();
    ASSERT_TRUE(request.has_value() && request->has_subscribe());
    peer.send(client::testing::error(request->request_id(), tumble::v1::UNKNOWN_BODY, "no body named 'ghost'"));
    peer.wait_for_close();
  });
  // On its own thread: a command that wrongly retried would never return,
  // and an interrupt (caught by the command) is then the way to end it.
  auto running = std::async(std::launch::async, [&] { return run_reconnecting(server, 1); });
  if (running.wait_for(30s) != std::future_status::ready) {
    ADD_FAILURE() << "still reconnecting after an UNKNOWN_BODY";
    std::raise(SIGINT);
  }
  const SubscribeRun run = running.get();
  ASSERT_TRUE(run.failure);
  EXPECT_EQ(run.failure->code, tumble::v1::UNKNOWN_BODY);
  EXPECT_TRUE(run.frames.empty());
  EXPECT_EQ(run.notes, "");
}

}  // namespace
}  // namespace tumble::cli
