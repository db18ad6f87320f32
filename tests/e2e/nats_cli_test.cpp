// tumble --nats against real nats-server processes: what it says when NATS
// cannot be reached or refuses it, one line each and a non-zero exit.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "nats_server_process.h"
#include "process.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

// Users as docker/nats/auth.conf has them, with fixed test passwords.
constexpr const char* kAuthConfig = R"(
authorization {
  users = [
    { user: observer, password: obs-pass,
      permissions: { publish: ["tumble.v1.worlds", "tumble.v1.*.key.>"],
                     subscribe: ["tumble.v1.*.poses.>", "tumble.v1.*.events", "_INBOX.>"] } }
    { user: controller, password: ctl-pass,
      permissions: { publish: ["tumble.v1.worlds", "tumble.v1.*.key.>", "tumble.v1.*.rpc"],
                     subscribe: ["tumble.v1.*.poses.>", "tumble.v1.*.events", "_INBOX.>"] } }
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
  const CommandResult json = tumble({"--nats", as_user(nats, "observer", "obs-pass"), "--json", "worlds"});
  EXPECT_EQ(json.exit_code, 0) << json.err;
  EXPECT_EQ(json.out, "");
}

}  // namespace
}  // namespace tumble::test
