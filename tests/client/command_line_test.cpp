#include "command_line.h"

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "command_line_helpers.h"
#include "exit_code.h"
#include "requests.h"
#include "support/scoped_env.h"

namespace tumble::cli {
namespace {

using testing::expect_usage_error;
using testing::parse;
using testing::parse_command;

using tumble::test::ScopedEnv;

TEST(CommandLine, GlobalOptionsDefaults) {
  ScopedEnv server("TUMBLE_SERVER", nullptr);
  ScopedEnv token("TUMBLE_TOKEN", nullptr);
  ParsedCommandLine parsed = parse({"bodies"});
  ASSERT_TRUE(parsed.invocation) << parsed.text;
  const GlobalOptions& global = parsed.invocation->global;
  EXPECT_EQ(global.server.host, "127.0.0.1");
  EXPECT_EQ(global.server.port, 7400);
  EXPECT_EQ(global.token, "");
  EXPECT_EQ(global.timeout, std::chrono::seconds(10));
  EXPECT_FALSE(global.json);
  EXPECT_TRUE(std::holds_alternative<BodiesCommand>(parsed.invocation->command));
}

TEST(CommandLine, GlobalOptionsGiven) {
  ParsedCommandLine parsed =
      parse({"--server", "[::1]:7500", "--json", "--token", "s3cret", "--timeout", "2.5", "bodies"});
  ASSERT_TRUE(parsed.invocation) << parsed.text;
  const GlobalOptions& global = parsed.invocation->global;
  EXPECT_EQ(global.server.host, "::1");
  EXPECT_EQ(global.server.port, 7500);
  EXPECT_EQ(global.token, "s3cret");
  EXPECT_EQ(global.timeout, std::chrono::milliseconds(2500));
  EXPECT_TRUE(global.json);
}

TEST(CommandLine, EnvironmentStandsInForServerAndToken) {
  ScopedEnv server("TUMBLE_SERVER", "sim.local:7777");
  ScopedEnv token("TUMBLE_TOKEN", "from-env");
  ParsedCommandLine parsed = parse({"bodies"});
  ASSERT_TRUE(parsed.invocation) << parsed.text;
  EXPECT_EQ(parsed.invocation->global.server.host, "sim.local");
  EXPECT_EQ(parsed.invocation->global.server.port, 7777);
  EXPECT_EQ(parsed.invocation->global.token, "from-env");

  parsed = parse({"--server", "127.0.0.1:1234", "bodies"});
  ASSERT_TRUE(parsed.invocation) << parsed.text;
  EXPECT_EQ(parsed.invocation->global.server.port, 1234);
}

TEST(CommandLine, BadServerOrTimeoutIsUsageError) {
  expect_usage_error({"--server", "localhost", "bodies"});
  expect_usage_error({"--server", "localhost:0", "bodies"});
  expect_usage_error({"--timeout", "0", "bodies"});
  expect_usage_error({"--timeout", "-1", "bodies"});
  expect_usage_error({"--timeout", "soon", "bodies"});
  expect_usage_error({"--timeout", "inf", "bodies"});
}

TEST(CommandLine, GlobalOptionsGoBeforeTheSubcommand) { expect_usage_error({"bodies", "--json"}); }

TEST(CommandLine, ForceWithEverything) {
  auto force = parse_command<ForceCommand>(
      {"force", "crate", "--force", "1", "-2", "3.5", "--at", "0", "0.5", "-0.25", "--local", "--ticks", "12"});
  ASSERT_EQ(force.body.ref_case(), tumble::v1::BodyRef::kName);
  EXPECT_EQ(force.body.name(), "crate");
  EXPECT_EQ(force.force, (Vector3{1, -2, 3.5}));
  ASSERT_TRUE(force.at);
  EXPECT_EQ(*force.at, (Vector3{0, 0.5, -0.25}));
  EXPECT_TRUE(force.local);
  EXPECT_FALSE(force.duration.seconds);
  ASSERT_TRUE(force.duration.ticks);
  EXPECT_EQ(*force.duration.ticks, 12u);
}

TEST(CommandLine, ForceMinimal) {
  auto force = parse_command<ForceCommand>({"force", "17", "--force", "0", "0", "-9.81"});
  ASSERT_EQ(force.body.ref_case(), tumble::v1::BodyRef::kId);
  EXPECT_EQ(force.body.id(), 17u);
  EXPECT_FALSE(force.at);
  EXPECT_FALSE(force.local);
  EXPECT_FALSE(force.duration.seconds);
  EXPECT_FALSE(force.duration.ticks);
}

TEST(CommandLine, NonFiniteNumbersPassThrough) {
  auto force = parse_command<ForceCommand>({"force", "crate", "--force", "nan", "inf", "-inf", "--duration", "nan"});
  EXPECT_TRUE(std::isnan(force.force[0]));
  EXPECT_TRUE(std::isinf(force.force[1]) && force.force[1] > 0);
  EXPECT_TRUE(std::isinf(force.force[2]) && force.force[2] < 0);
  ASSERT_TRUE(force.duration.seconds);
  EXPECT_TRUE(std::isnan(*force.duration.seconds));

  auto subscribe = parse_command<SubscribeCommand>({"subscribe", "--rate", "-5"});
  EXPECT_EQ(subscribe.rate_hz, -5);
}

TEST(CommandLine, ForceUsageErrors) {
  expect_usage_error({"force", "crate", "--force", "1", "abc", "3"});
  expect_usage_error({"force", "crate", "--force", "1", "2"});
  expect_usage_error({"force", "crate"});
  expect_usage_error({"force", "--force", "1", "2", "3"});
  expect_usage_error({"force", "crate", "--force", "1", "2", "3", "--local"});
  expect_usage_error({"force", "crate", "--force", "1", "2", "3", "--duration", "1", "--ticks", "5"});
  expect_usage_error({"force", "crate", "--force", "1", "2", "3", "--ticks", "-1"});
  expect_usage_error({"force", "crate", "--force", "1", "2", "3", "--ticks", "1.5"});
  expect_usage_error({"force", "4294967296", "--force", "1", "2", "3"});
}

TEST(CommandLine, Torque) {
  auto torque = parse_command<TorqueCommand>({"torque", "wheel", "--torque", "0", "0", "2", "--duration", "0.5"});
  EXPECT_EQ(torque.body.name(), "wheel");
  EXPECT_EQ(torque.torque, (Vector3{0, 0, 2}));
  ASSERT_TRUE(torque.duration.seconds);
  EXPECT_EQ(*torque.duration.seconds, 0.5);
  EXPECT_FALSE(torque.duration.ticks);

  expect_usage_error({"torque", "wheel", "--torque", "0", "0", "2", "--at", "1", "1", "1"});
}

TEST(CommandLine, Impulse) {
  auto impulse = parse_command<ImpulseCommand>({"impulse", "3", "--impulse", "0", "5", "0", "--at", "1", "0", "0"});
  EXPECT_EQ(impulse.body.id(), 3u);
  EXPECT_EQ(impulse.impulse, (Vector3{0, 5, 0}));
  ASSERT_TRUE(impulse.at);
  EXPECT_FALSE(impulse.local);

  expect_usage_error({"impulse", "3", "--impulse", "0", "5", "0", "--local"});
  expect_usage_error({"impulse", "3", "--impulse", "0", "5", "0", "--ticks", "2"});
}

TEST(CommandLine, SubscribeDefaults) {
  auto subscribe = parse_command<SubscribeCommand>({"subscribe"});
  EXPECT_TRUE(subscribe.bodies.empty());
  EXPECT_EQ(subscribe.rate_hz, 30);
  EXPECT_FALSE(subscribe.count);
  EXPECT_EQ(subscribe.encoding, tumble::v1::POSE_ENCODING_FULL);
}

TEST(CommandLine, SubscribeFieldsMayAddTheJoints) {
  const struct {
    const char* fields;
    bool poses_only;
    bool joints;
  } cases[] = {{"all", false, false},
               {"pose", true, false},
               {"all,joints", false, true},
               {"pose,joints", true, true},
               {"joints", true, true}};
  for (const auto& c : cases) {
    const auto subscribe = parse_command<SubscribeCommand>({"subscribe", "--fields", c.fields});
    EXPECT_EQ(subscribe.poses_only, c.poses_only) << c.fields;
    EXPECT_EQ(subscribe.joints, c.joints) << c.fields;
    EXPECT_EQ(make_subscribe(subscribe).joints(), c.joints) << c.fields;
  }
  EXPECT_FALSE(parse_command<SubscribeCommand>({"subscribe"}).joints);
  expect_usage_error({"subscribe", "--fields", "joints,all"});
}

TEST(CommandLine, SubscribeEncodings) {
  EXPECT_EQ(parse_command<SubscribeCommand>({"subscribe", "--encoding", "quantized"}).encoding,
            tumble::v1::POSE_ENCODING_QUANTIZED);
  EXPECT_EQ(parse_command<SubscribeCommand>({"subscribe", "--encoding", "delta"}).encoding,
            tumble::v1::POSE_ENCODING_DELTA);
  EXPECT_EQ(parse_command<SubscribeCommand>({"subscribe", "--encoding", "full"}).encoding,
            tumble::v1::POSE_ENCODING_FULL);
  expect_usage_error({"subscribe", "--encoding", "zip"});
}

TEST(CommandLine, WatchEncodings) {
  EXPECT_EQ(parse_command<WatchCommand>({"watch"}).encoding, tumble::v1::POSE_ENCODING_FULL);
  EXPECT_EQ(parse_command<WatchCommand>({"watch", "--encoding", "quantized"}).encoding,
            tumble::v1::POSE_ENCODING_QUANTIZED);
  EXPECT_EQ(parse_command<WatchCommand>({"watch", "--encoding", "delta"}).encoding, tumble::v1::POSE_ENCODING_DELTA);
  EXPECT_EQ(parse_command<WatchCommand>({"watch", "--encoding", "full"}).encoding, tumble::v1::POSE_ENCODING_FULL);
  expect_usage_error({"watch", "--encoding", "zip"});

  WatchCommand watch;
  watch.encoding = tumble::v1::POSE_ENCODING_DELTA;
  EXPECT_EQ(make_watch_subscribe(watch).encoding(), tumble::v1::POSE_ENCODING_DELTA);
  EXPECT_EQ(make_watch_subscribe(WatchCommand{}).encoding(), tumble::v1::POSE_ENCODING_FULL);
}

TEST(CommandLine, SubscribeWithBodiesRateAndCount) {
  auto subscribe =
      parse_command<SubscribeCommand>({"subscribe", "--bodies", "crate,7,ball", "--rate", "60", "--count", "5"});
  ASSERT_EQ(subscribe.bodies.size(), 3u);
  EXPECT_EQ(subscribe.bodies[0].name(), "crate");
  ASSERT_EQ(subscribe.bodies[1].ref_case(), tumble::v1::BodyRef::kId);
  EXPECT_EQ(subscribe.bodies[1].id(), 7u);
  EXPECT_EQ(subscribe.bodies[2].name(), "ball");
  EXPECT_EQ(subscribe.rate_hz, 60);
  ASSERT_TRUE(subscribe.count);
  EXPECT_EQ(*subscribe.count, 5u);
}

TEST(CommandLine, SubscribeUsageErrors) {
  expect_usage_error({"subscribe", "--count", "0"});
  expect_usage_error({"subscribe", "--count", "many"});
  expect_usage_error({"subscribe", "--rate", "fast"});
  expect_usage_error({"subscribe", "--bodies", "crate,99999999999"});
}

TEST(CommandLine, MissingOrUnknownSubcommandIsUsageError) {
  expect_usage_error({});
  expect_usage_error({"launch"});
}

TEST(CommandLine, HelpExitsWithSuccess) {
  ParsedCommandLine parsed = parse({"--help"});
  EXPECT_FALSE(parsed.invocation);
  EXPECT_EQ(parsed.exit_code, kExitSuccess);
  EXPECT_NE(parsed.text.find("subscribe"), std::string::npos) << parsed.text;

  parsed = parse({"force", "--help"});
  EXPECT_FALSE(parsed.invocation);
  EXPECT_EQ(parsed.exit_code, kExitSuccess);
  EXPECT_NE(parsed.text.find("--local"), std::string::npos) << parsed.text;
}

}  // namespace
}  // namespace tumble::cli
