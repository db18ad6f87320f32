// The command line's NATS options: where they come from, what goes with
// what, and the one-line usage errors that name the flag.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "command_line.h"
#include "command_line_helpers.h"
#include "exit_code.h"
#include "support/scoped_env.h"

namespace tumble::cli {
namespace {

using testing::expect_usage_error;
using testing::parse;
using testing::parse_command;
using tumble::test::ScopedEnv;

// A usage error whose one line starts with `flag`.
void expect_usage_error_naming(const std::string& flag, std::vector<std::string> args) {
  const ParsedCommandLine parsed = parse(args);
  expect_usage_error(std::move(args));
  EXPECT_EQ(parsed.text.rfind(flag, 0), 0u) << parsed.text;
}

struct NoNatsEnvironment {
  ScopedEnv nats{"TUMBLE_NATS", nullptr};
  ScopedEnv world{"TUMBLE_WORLD", nullptr};
};

TEST(NatsCommandLine, WithoutNatsTheWorldIsTcp) {
  NoNatsEnvironment clean;
  const ParsedCommandLine parsed = parse({"bodies"});
  ASSERT_TRUE(parsed.invocation) << parsed.text;
  EXPECT_TRUE(parsed.invocation->global.nats.empty());
  EXPECT_EQ(parsed.invocation->global.world, "");
}

TEST(NatsCommandLine, UrlsWorldAndCredentials) {
  NoNatsEnvironment clean;
  const ParsedCommandLine parsed =
      parse({"--nats", "nats://a:4222,nats://b:4222", "--world", "demo-2_x", "--nats-creds", "/dev/null", "bodies"});
  ASSERT_TRUE(parsed.invocation) << parsed.text;
  const GlobalOptions& global = parsed.invocation->global;
  EXPECT_EQ(global.nats, (std::vector<std::string>{"nats://a:4222", "nats://b:4222"}));
  EXPECT_EQ(global.world, "demo-2_x");
  EXPECT_EQ(global.nats_credentials, "/dev/null");
}

TEST(NatsCommandLine, EnvironmentStandsInForNatsAndWorld) {
  ScopedEnv nats("TUMBLE_NATS", "nats://a:4222,nats://b:4222");
  ScopedEnv world("TUMBLE_WORLD", "demo");
  ParsedCommandLine parsed = parse({"stats"});
  ASSERT_TRUE(parsed.invocation) << parsed.text;
  EXPECT_EQ(parsed.invocation->global.nats, (std::vector<std::string>{"nats://a:4222", "nats://b:4222"}));
  EXPECT_EQ(parsed.invocation->global.world, "demo");

  parsed = parse({"--world", "other", "stats"});
  ASSERT_TRUE(parsed.invocation) << parsed.text;
  EXPECT_EQ(parsed.invocation->global.world, "other");
}

TEST(NatsCommandLine, AWorldNameThatIsNotOneSubjectTokenIsRefused) {
  NoNatsEnvironment clean;
  for (const std::string& bad : std::vector<std::string>{"de.mo", "*", ">", "a b", "", "wörld", std::string(65, 'w')}) {
    expect_usage_error_naming("--world", {"--nats", "nats://a:4222", "--world", bad, "bodies"});
  }
  EXPECT_TRUE(parse({"--nats", "nats://a:4222", "--world", std::string(64, 'w'), "bodies"}).invocation);
}

TEST(NatsCommandLine, NatsNeedsAWorldExceptToListThem) {
  NoNatsEnvironment clean;
  expect_usage_error_naming("--world", {"--nats", "nats://a:4222", "bodies"});
  parse_command<WorldsCommand>({"--nats", "nats://a:4222", "worlds"});
}

TEST(NatsCommandLine, NatsOnlyOptionsWithoutNatsAreRefused) {
  NoNatsEnvironment clean;
  expect_usage_error_naming("worlds", {"worlds"});
  expect_usage_error_naming("--nats-creds", {"--nats-creds", "/dev/null", "bodies"});
  expect_usage_error_naming("--stream", {"subscribe", "--stream", "q60"});
  expect_usage_error_naming("--stream", {"watch", "--stream", "q60"});
}

TEST(NatsCommandLine, AMissingCredentialsFileOrAnEmptyUrlIsRefused) {
  NoNatsEnvironment clean;
  expect_usage_error_naming("--nats-creds", {"--nats", "nats://a:4222", "--world", "demo", "--nats-creds",
                                             "/nonexistent/user.creds", "bodies"});
  expect_usage_error_naming("--nats", {"--nats", "", "--world", "demo", "bodies"});
}

TEST(NatsCommandLine, SubscribeAndWatchReadAStream) {
  NoNatsEnvironment clean;
  const auto subscribe = parse_command<SubscribeCommand>(
      {"--nats", "nats://a:4222", "--world", "demo", "subscribe", "--stream", "d30", "--count", "3", "--events"});
  EXPECT_EQ(subscribe.stream, "d30");
  EXPECT_EQ(subscribe.count, 3u);
  EXPECT_TRUE(subscribe.events);
  const auto watch = parse_command<WatchCommand>({"--nats", "nats://a:4222", "--world", "demo", "watch"});
  EXPECT_EQ(watch.stream, "");  // the world's first
  expect_usage_error_naming("--stream", {"--nats", "nats://a:4222", "--world", "demo", "watch", "--stream", "q.60"});
}

TEST(NatsCommandLine, WhatTheStreamDecidesIsRefusedOverNats) {
  NoNatsEnvironment clean;
  const std::vector<std::string> nats = {"--nats", "nats://a:4222", "--world", "demo"};
  const auto with = [&](std::vector<std::string> rest) {
    std::vector<std::string> args = nats;
    args.insert(args.end(), rest.begin(), rest.end());
    return args;
  };
  expect_usage_error_naming("--rate", with({"subscribe", "--rate", "10"}));
  expect_usage_error_naming("--encoding", with({"subscribe", "--encoding", "delta"}));
  expect_usage_error_naming("--fields", with({"subscribe", "--fields", "pose"}));
  expect_usage_error_naming("--bodies", with({"subscribe", "--bodies", "crate"}));
  expect_usage_error_naming("--rate", with({"watch", "--rate", "10"}));
  expect_usage_error_naming("--encoding", with({"watch", "--encoding", "full"}));
  expect_usage_error_naming("--bodies", with({"watch", "--bodies", "1"}));
  // Over TCP they stay what they were.
  EXPECT_TRUE(parse({"subscribe", "--rate", "10", "--encoding", "delta"}).invocation);
}

}  // namespace
}  // namespace tumble::cli
