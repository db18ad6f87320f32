// tumble --nats against real nats-server processes: what it says when NATS
// cannot be reached or refuses it, one line each and a non-zero exit; and
// the subcommands through NATS against a real tumbled --nats, with the
// answers they give over TCP.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "nats_server_process.h"
#include "poll_until.h"
#include "process.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using nlohmann::json;

// Users as docker/nats/auth.conf has them, with fixed test passwords.
constexpr const char* kAuthConfig = R"(
authorization {
  users = [
    { user: observer, password: obs-pass,
      permissions: { publish: ["tumble.v1.worlds", "tumble.v1.*.key.>", "tumble.v1.*.query"],
                     subscribe: ["tumble.v1.*.poses.>", "tumble.v1.*.events", "_INBOX.>"] } }
    { user: controller, password: ctl-pass,
      permissions: { publish: ["tumble.v1.worlds", "tumble.v1.*.key.>", "tumble.v1.*.query", "tumble.v1.*.rpc"],
                     subscribe: ["tumble.v1.*.poses.>", "tumble.v1.*.events", "_INBOX.>"] } }
    { user: tumbled, password: srv-pass }
  ]
}
)";

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
  NatsServerProcess nats(kAuthConfig);
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
  NatsServerProcess nats(kAuthConfig);
  ASSERT_TRUE(nats.start()) << nats.log();
  const CommandResult result = tumble(
      {"--nats", as_user(nats, "observer", "obs-pass"), "--world", "demo", "force", "crate", "--force", "1", "0", "0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.out, "");
  ExpectOneLine(result.err);
  EXPECT_EQ(result.err.rfind("tumble: not permitted: ", 0), 0u) << result.err;
  EXPECT_NE(result.err.find("tumble.v1.demo.rpc"), std::string::npos) << result.err;
}

TEST(NatsCli, AnObserverListsTheBodiesAndStatsButMayNotPush) {
  NatsServerProcess nats(kAuthConfig);
  ASSERT_TRUE(nats.start()) << nats.log();
  TumbledProcess tumbled(kFloatingScene, {"--nats", as_user(nats, "tumbled", "srv-pass"), "--world", "demo"});
  ASSERT_TRUE(tumbled.started()) << tumbled.log();
  const std::vector<std::string> observer = {"--nats", as_user(nats, "observer", "obs-pass"), "--world", "demo"};
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
  NatsServerProcess nats(kAuthConfig);
  ASSERT_TRUE(nats.start()) << nats.log();
  const CommandResult result = tumble({"--nats", as_user(nats, "controller", "ctl-pass"), "--world", "demo", "force",
                                       "crate", "--force", "1", "0", "0"});
  EXPECT_EQ(result.exit_code, 1);
  ExpectOneLine(result.err);
  EXPECT_EQ(result.err, "tumble: no server serves world 'demo': nothing answers on tumble.v1.demo.rpc\n");
}

TEST(NatsCli, WorldsWithNoWorldRunningListsNone) {
  NatsServerProcess nats(kAuthConfig);
  ASSERT_TRUE(nats.start()) << nats.log();
  const CommandResult table = tumble({"--nats", as_user(nats, "observer", "obs-pass"), "worlds"});
  EXPECT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(table.out, "no worlds answered\n");
  const CommandResult lines = tumble({"--nats", as_user(nats, "observer", "obs-pass"), "--json", "worlds"});
  EXPECT_EQ(lines.exit_code, 0) << lines.err;
  EXPECT_EQ(lines.out, "");
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
