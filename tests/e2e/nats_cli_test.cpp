// tumble --nats against real nats-server processes: what it says when NATS
// cannot be reached or refuses it, one line each and a non-zero exit; the
// roles of docker/nats/auth.conf, read from the source tree, with tumbled
// as that file's user; and the subcommands through NATS against a real
// tumbled --nats, with the answers they give over TCP.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nats/nats.h>
#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "nats_server_process.h"
#include "nats_test_client.h"
#include "poll_until.h"
#include "process.h"
#include "scoped_env.h"
#include "test_paths.h"
#include "tumble/v1/world_info.pb.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using nlohmann::json;

// The test's passwords, given to nats-server through the environment that
// docker/nats/auth.conf reads them from.
constexpr const char* kObserverPassword = "obs-pass";
constexpr const char* kControllerPassword = "ctl-pass";
constexpr const char* kTumbledPassword = "tbd-pass";

// docker/nats/auth.conf as committed (the very file the docs and the image
// use), with the test's passwords.
NatsConfig auth_config() {
  return {read_file(nats_auth_conf_path()),
          {std::string("TUMBLE_NATS_OBSERVER_PASSWORD=") + kObserverPassword,
           std::string("TUMBLE_NATS_CONTROLLER_PASSWORD=") + kControllerPassword,
           std::string("TUMBLE_NATS_TUMBLED_PASSWORD=") + kTumbledPassword}};
}

// A message of exactly one line.
void ExpectOneLine(const std::string& text) {
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.find('\n'), text.size() - 1) << text;
}

CommandResult tumble(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {tumble_cli_path()};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command(argv);
}

// nats://USER:PASSWORD@127.0.0.1:PORT
std::string as_user(const NatsServerProcess& nats, const std::string& user, const std::string& password) {
  return "nats://" + user + ":" + password + "@127.0.0.1:" + std::to_string(nats.port());
}

TEST(NatsCli, AnUnreachableNatsUrlFailsInOneLineNamingTheFlag) {
  const std::string url = "nats://127.0.0.1:" + std::to_string(free_loopback_port());
  const CommandResult result = tumble({"--nats", url, "--world", "demo", "--timeout", "2", "bodies"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.out, "");
  ExpectOneLine(result.err);
  EXPECT_EQ(result.err.rfind("tumble: --nats: cannot connect to NATS at " + url, 0), 0u) << result.err;
}

TEST(NatsCli, AWrongPasswordFailsInOneLineWithoutShowingIt) {
  NatsServerProcess nats(auth_config());
  ASSERT_TRUE(nats.start()) << nats.log();
  const CommandResult result =
      tumble({"--nats", as_user(nats, "controller", "wrong-pass"), "--world", "demo", "stats"});
  EXPECT_EQ(result.exit_code, 1);
  ExpectOneLine(result.err);
  EXPECT_NE(result.err.find("--nats: "), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("Authorization Violation"), std::string::npos) << result.err;
  EXPECT_EQ(result.err.find("wrong-pass"), std::string::npos) << result.err;
}

TEST(NatsCli, AnObserversCommandIsNotPermitted) {
  NatsServerProcess nats(auth_config());
  ASSERT_TRUE(nats.start()) << nats.log();
  const CommandResult result = tumble({"--nats", as_user(nats, "observer", kObserverPassword), "--world", "demo",
                                       "force", "crate", "--force", "1", "0", "0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.out, "");
  ExpectOneLine(result.err);
  EXPECT_EQ(result.err.rfind("tumble: not permitted: ", 0), 0u) << result.err;
  EXPECT_NE(result.err.find("tumble.v1.demo.rpc"), std::string::npos) << result.err;
}

TEST(NatsCli, AnObserverListsTheBodiesAndStatsButMayNotPush) {
  NatsServerProcess nats(auth_config());
  ASSERT_TRUE(nats.start()) << nats.log();
  TumbledProcess tumbled(kFloatingScene, {"--nats", as_user(nats, "tumbled", kTumbledPassword), "--world", "demo"});
  ASSERT_TRUE(tumbled.started()) << tumbled.log();
  const std::vector<std::string> observer = {"--nats", as_user(nats, "observer", kObserverPassword), "--world", "demo"};
  const auto as_observer = [&](std::vector<std::string> args) {
    args.insert(args.begin(), observer.begin(), observer.end());
    return tumble(args);
  };
  CommandResult bodies;
  ASSERT_TRUE(poll_until([&] {
    return (bodies = as_observer({"--json", "bodies"})).exit_code == 0;
  })) << bodies.err
      << tumbled.log();
  const json list = json::parse(bodies.out, nullptr, false);
  EXPECT_EQ(body(list, "crate")["mass"], 2.0) << bodies.out;
  EXPECT_EQ(as_observer({"stats"}).exit_code, 0);
  const CommandResult push = as_observer({"impulse", "crate", "--impulse", "1", "0", "0"});
  EXPECT_EQ(push.exit_code, 1);
  EXPECT_EQ(push.err.rfind("tumble: not permitted: ", 0), 0u) << push.err;
}

TEST(NatsCli, AControllersCommandWithNoServerOfTheWorldSaysSo) {
  NatsServerProcess nats(auth_config());
  ASSERT_TRUE(nats.start()) << nats.log();
  const CommandResult result = tumble({"--nats", as_user(nats, "controller", kControllerPassword), "--world", "demo",
                                       "force", "crate", "--force", "1", "0", "0"});
  EXPECT_EQ(result.exit_code, 1);
  ExpectOneLine(result.err);
  EXPECT_EQ(result.err, "tumble: no server serves world 'demo': nothing answers on tumble.v1.demo.rpc\n");
}

TEST(NatsCli, WorldsWithNoWorldRunningListsNone) {
  NatsServerProcess nats(auth_config());
  ASSERT_TRUE(nats.start()) << nats.log();
  const CommandResult table = tumble({"--nats", as_user(nats, "observer", kObserverPassword), "worlds"});
  EXPECT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(table.out, "no worlds answered\n");
  const CommandResult lines = tumble({"--nats", as_user(nats, "observer", kObserverPassword), "--json", "worlds"});
  EXPECT_EQ(lines.exit_code, 0) << lines.err;
  EXPECT_EQ(lines.out, "");
}

TEST(NatsAuthConfig, NatsServerRefusesTheFileWhileAPasswordIsMissing) {
  // Whatever the test's own environment has: nats-server gets none of them.
  const ScopedEnv observer("TUMBLE_NATS_OBSERVER_PASSWORD", nullptr);
  const ScopedEnv controller("TUMBLE_NATS_CONTROLLER_PASSWORD", nullptr);
  const ScopedEnv tumbled("TUMBLE_NATS_TUMBLED_PASSWORD", nullptr);
  const std::string text = read_file(nats_auth_conf_path());
  ASSERT_NE(text.find("authorization"), std::string::npos) << "not read: " << nats_auth_conf_path();
  NatsServerProcess nats(text);
  EXPECT_FALSE(nats.start());
  EXPECT_NE(nats.log().find("TUMBLE_NATS_OBSERVER_PASSWORD"), std::string::npos) << nats.log();
}

// A real tumbled serving world "lab" (kFloatingScene) into a nats-server
// with docker/nats/auth.conf, as that file's tumbled user, with a QUANTIZED
// and a DELTA stream: the observer and the controller can each do what
// their role is for, and nats-server refuses tumbled nothing (the file
// gives it all it publishes and subscribes to, in its queue group).
class NatsCliRoles : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(nats_.start()) << nats_.log();
    tumbled_ = std::make_unique<TumbledProcess>(
        kFloatingScene,
        std::vector<std::string>{"--nats", as_user(nats_, "tumbled", kTumbledPassword), "--world", "lab",
                                 "--nats-stream", "q30=quantized@30", "--nats-stream", "d30=delta@30"});
    ASSERT_TRUE(tumbled_->started()) << tumbled_->log();
    ASSERT_TRUE(poll_until([&] { return as("observer", {"worlds"}).out.find("lab") != std::string::npos; }))
        << tumbled_->log() << nats_.log();
  }

  void TearDown() override {
    // Every refusal nats-server logs names the user it refused.
    EXPECT_EQ(nats_.log().find("User \"tumbled\""), std::string::npos) << nats_.log();
  }

  // tumble --nats nats://USER:PASSWORD@... ARGS...
  CommandResult as(const std::string& user, std::vector<std::string> args) const {
    const std::string password = user == "observer" ? kObserverPassword : kControllerPassword;
    args.insert(args.begin(), {"--nats", as_user(nats_, user, password)});
    return tumble(args);
  }

  // The body of id `id` in a frame; a test failure and null when it is not there.
  static json body_of(const json& frame, int id) {
    for (const json& entry : frame["bodies"]) {
      if (entry["id"] == id) return entry;
    }
    ADD_FAILURE() << "no body " << id << " in " << frame.dump();
    return nullptr;
  }

  NatsServerProcess nats_{auth_config()};
  std::unique_ptr<TumbledProcess> tumbled_;
};

TEST_F(NatsCliRoles, AnObserverFindsTheWorldAndReadsEachStream) {
  const CommandResult worlds = as("observer", {"--json", "worlds"});
  ASSERT_EQ(worlds.exit_code, 0) << worlds.err;
  EXPECT_EQ(json::parse(worlds.out, nullptr, false)["world"], "lab") << worlds.out;
  // The DELTA reader starts from a key frame it asks tumbled for on .key.
  for (const std::string stream : {"q30", "d30"}) {
    const CommandResult frames =
        as("observer", {"--world", "lab", "--json", "subscribe", "--stream", stream, "--count", "3"});
    ASSERT_EQ(frames.exit_code, 0) << stream << ": " << frames.err;
    const std::vector<json> lines = json_lines(frames.out);
    ASSERT_EQ(lines.size(), 3u) << stream << ": " << frames.out;
    for (const json& frame : lines) EXPECT_EQ(frame["bodies"].size(), 2u) << stream << ": " << frame.dump();
  }
}

TEST_F(NatsCliRoles, AnObserversForceIsRefusedAndAControllersMovesTheCrateForTheObserverToSee) {
  const CommandResult refused = as("observer", {"--world", "lab", "force", "crate", "--force", "10", "0", "0"});
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_EQ(refused.err.rfind("tumble: not permitted: ", 0), 0u) << refused.err;

  // 10 N for 24 ticks on 2 kg: 0.5 m/s along x once the ticks are over.
  const CommandResult ack =
      as("controller", {"--world", "lab", "--json", "force", "crate", "--force", "10", "0", "0", "--ticks", "24"});
  ASSERT_EQ(ack.exit_code, 0) << ack.err;
  const std::uint64_t applied = json::parse(ack.out, nullptr, false)["applied_tick"].get<std::uint64_t>();
  const std::uint64_t done = applied + 24;
  json list;
  ASSERT_TRUE(poll_until([&] {
    const CommandResult bodies = as("controller", {"--world", "lab", "--json", "bodies"});
    list = json::parse(bodies.out, nullptr, false);
    return bodies.exit_code == 0 && list.value("tick", std::uint64_t{0}) >= done;
  }));
  EXPECT_NEAR(body(list, "crate")["linear_velocity"][0].get<double>(), 0.5, 1e-9);

  // The observer's frames (the first is the latest frame at the time, so
  // after the force began) show the crate (id 0) drifting along x.
  const CommandResult frames = as("observer", {"--world", "lab", "--json", "subscribe", "--count", "2"});
  ASSERT_EQ(frames.exit_code, 0) << frames.err;
  const std::vector<json> lines = json_lines(frames.out);
  ASSERT_EQ(lines.size(), 2u) << frames.out;
  EXPECT_GT(lines[0]["tick"].get<std::uint64_t>(), applied);
  EXPECT_GT(body_of(lines[1], 0)["position"][0].get<double>(), body_of(lines[0], 0)["position"][0].get<double>())
      << frames.out;
}

// A real tumbled serving world "lab" (kFloatingScene: no gravity, the crate
// of 2 kg at the origin, the ball of 1 kg at z = 50) into a nats-server
// without users, with a stream of each encoding.
class NatsCliWorld : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(nats_.start()) << nats_.log();
    tumbled_ = std::make_unique<TumbledProcess>(
        kFloatingScene,
        std::vector<std::string>{"--nats", nats_.url(), "--world", "lab", "--nats-stream", "f30=full@30:all",
                                 "--nats-stream", "q30=quantized@30", "--nats-stream", "d30=delta@30"});
    ASSERT_TRUE(tumbled_->started()) << tumbled_->log();
    // The link is up once a request through NATS is answered.
    ASSERT_TRUE(poll_until([&] { return over_nats({"stats"}).exit_code == 0; })) << tumbled_->log();
  }

  CommandResult over_nats(std::vector<std::string> args) const {
    args.insert(args.begin(), {"--nats", nats_.url(), "--world", "lab"});
    return tumble(args);
  }

  json json_over_nats(std::vector<std::string> args) const {
    args.insert(args.begin(), "--json");
    const CommandResult result = over_nats(args);
    EXPECT_EQ(result.exit_code, 0) << result.err;
    return json::parse(result.out, nullptr, false);
  }

  NatsServerProcess nats_;
  std::unique_ptr<TumbledProcess> tumbled_;
};

TEST_F(NatsCliWorld, WorldsFindsTheRunningWorldWithItsStreams) {
  const CommandResult result = tumble({"--nats", nats_.url(), "--json", "worlds"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::vector<std::string> lines = lines_of(result.out);
  ASSERT_EQ(lines.size(), 1u) << result.out;
  const json world = json::parse(lines[0], nullptr, false);
  ASSERT_FALSE(world.is_discarded()) << lines[0];
  EXPECT_EQ(world["world"], "lab");
  EXPECT_EQ(world["bodies"], 2);
  EXPECT_EQ(world["rpc_subject"], "tumble.v1.lab.rpc");
  ASSERT_EQ(world["streams"].size(), 3u);
  EXPECT_EQ(world["streams"][2]["name"], "d30");
  EXPECT_EQ(world["streams"][2]["encoding"], "delta");
  EXPECT_EQ(world["streams"][2]["subject"], "tumble.v1.lab.poses.d30");

  const CommandResult table = tumble({"--nats", nats_.url(), "worlds"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("lab"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("d30=delta@30"), std::string::npos) << table.out;
}

TEST_F(NatsCliWorld, BodiesThroughNatsAreTheBodiesOverTcp) {
  const json over_nats_list = json_over_nats({"bodies"});
  const CommandResult tcp = tumbled_->cli({"--json", "bodies"});
  ASSERT_EQ(tcp.exit_code, 0) << tcp.err;
  const json over_tcp_list = json::parse(tcp.out, nullptr, false);
  ASSERT_EQ(over_nats_list["bodies"].size(), 2u) << over_nats_list.dump();
  // Nothing moves in this world: the two lists differ in their tick only.
  EXPECT_EQ(over_nats_list["bodies"], over_tcp_list["bodies"]);
}

TEST_F(NatsCliWorld, AForceThroughNatsIsAppliedAtTheTickItsAckNames) {
  // 10 N for 24 ticks on 2 kg: v = F n dt / M = 0.5 m/s, exactly, once the ticks are over.
  const json ack = json_over_nats({"force", "crate", "--force", "10", "0", "0", "--ticks", "24"});
  ASSERT_TRUE(ack.contains("applied_tick")) << ack.dump();
  const std::uint64_t done = ack["applied_tick"].get<std::uint64_t>() + 24;
  json list;
  ASSERT_TRUE(poll_until([&] {
    list = json_over_nats({"bodies"});
    return list.value("tick", std::uint64_t{0}) >= done;
  }));
  EXPECT_NEAR(body(list, "crate")["linear_velocity"][0].get<double>(), 0.5, 1e-9);
  EXPECT_EQ(body(list, "ball")["linear_velocity"], json::array({0.0, 0.0, 0.0})) << "only the crate moved";
}

TEST_F(NatsCliWorld, SubscribeReadsEachEncodingToThePosesOfTheWorld) {
  // The crate drifts along x at 1 m/s, so every delta frame carries a change
  // and a reader that missed or misapplied one shows the crate out of place.
  ASSERT_EQ(over_nats({"set", "crate", "--velocity", "1", "0", "0"}).exit_code, 0);
  for (const std::string stream : {"f30", "q30", "d30"}) {
    const CommandResult result = over_nats({"--json", "subscribe", "--stream", stream, "--count", "4"});
    ASSERT_EQ(result.exit_code, 0) << stream << ": " << result.err;
    const std::vector<std::string> lines = lines_of(result.out);
    ASSERT_EQ(lines.size(), 4u) << stream << ": " << result.out;
    std::vector<json> frames;
    for (const std::string& line : lines) {
      frames.push_back(json::parse(line, nullptr, false));
      ASSERT_FALSE(frames.back().is_discarded()) << line;
      ASSERT_EQ(frames.back()["bodies"].size(), 2u) << stream << ": " << line;
    }
    for (std::size_t i = 1; i < frames.size(); ++i) {
      const json& first = frames.front();
      const json& frame = frames[i];
      EXPECT_GT(frame["tick"].get<std::uint64_t>(), first["tick"].get<std::uint64_t>()) << stream;
      // x(t) - x(t0) = v (t - t0), within the quantization grid of two readings.
      const double moved =
          body(frame, "crate")["position"][0].get<double>() - body(first, "crate")["position"][0].get<double>();
      const double elapsed = frame["time"].get<double>() - first["time"].get<double>();
      EXPECT_NEAR(moved, elapsed, 2e-3) << stream << ": " << lines[i];
      EXPECT_NEAR(body(frame, "ball")["position"][2].get<double>(), 50.0, 1e-3) << stream << ": " << lines[i];
    }
  }
}

// Answers tumble.v1.worlds as a standby of world "lab" would (tumbled
// --standby): no streams, and an id that sorts before any other.
void answer_as_standby(natsConnection* connection, natsSubscription*, natsMsg* message, void*) {
  tumble::v1::WorldInfo info;
  info.set_world("lab");
  info.set_server_id("0000000000000000");
  info.set_standby(true);
  const std::string bytes = info.SerializeAsString();
  if (natsMsg_GetReply(message) != nullptr) {
    natsConnection_Publish(connection, natsMsg_GetReply(message), bytes.data(), static_cast<int>(bytes.size()));
  }
  natsMsg_Destroy(message);
}

TEST_F(NatsCliWorld, SubscribeReadsTheLeadersStreamsWhenAStandbyAnswersToo) {
  NatsTestClient standby(nats_.url());
  ASSERT_TRUE(standby.connected());
  natsSubscription* subscription = nullptr;
  ASSERT_EQ(
      natsConnection_Subscribe(&subscription, standby.connection(), "tumble.v1.worlds", &answer_as_standby, nullptr),
      NATS_OK);
  ASSERT_EQ(standby.flush(), NATS_OK);
  const CommandResult result = over_nats({"--json", "subscribe", "--stream", "f30", "--count", "2"});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(lines_of(result.out).size(), 2u) << result.out;
  const CommandResult table = tumble({"--nats", nats_.url(), "worlds"});
  EXPECT_NE(table.out.find("STANDBYS"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("0000000000000000"), std::string::npos) << table.out;
  natsSubscription_Destroy(subscription);
}

TEST_F(NatsCliWorld, StatsThroughNatsShowTheLink) {
  const json stats = json_over_nats({"stats"});
  ASSERT_TRUE(stats.contains("nats")) << stats.dump();
  EXPECT_EQ(stats["nats"]["world"], "lab");
  EXPECT_EQ(stats["nats"]["connected"], true);
  EXPECT_GT(stats["nats"]["messages_out"].get<std::uint64_t>(), 0u);
  // Over TCP the same link is reported.
  const CommandResult tcp = tumbled_->cli({"--json", "stats"});
  ASSERT_EQ(tcp.exit_code, 0) << tcp.err;
  EXPECT_EQ(json::parse(tcp.out, nullptr, false)["nats"]["connected"], true) << tcp.out;
}

}  // namespace
}  // namespace tumble::test
