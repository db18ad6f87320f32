// The version in one place: tumbled and tumble say the version CMake's
// project() declares, passed to this test by CMake, not read from the
// header the binaries use.
#include <gtest/gtest.h>

#include <csignal>
#include <string>

#include "raw_client.h"
#include "sim/journal.h"
#include "test_scenes.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

TEST(Version, TumbledAndTumblePrintTheProjectVersion) {
  for (const char* program : {tumbled_path(), tumble_cli_path()}) {
    const CommandResult result = run_command({program, "--version"});
    EXPECT_EQ(result.exit_code, 0) << program << ": " << result.err;
    EXPECT_EQ(result.out, std::string(TUMBLE_PROJECT_VERSION) + "\n") << program;
  }
}

TEST(Version, WelcomeAndJournalCarryTheProjectVersion) {
  const std::string journal_path = make_temp_dir() + "/run.journal";
  TumbledProcess server(kFallingCrateScene, {"--record", journal_path});
  ASSERT_TRUE(server.started()) << server.log();
  RawClient client(server.port());
  const auto welcome = client.handshake();
  ASSERT_TRUE(welcome && welcome->has_welcome()) << server.log();
  EXPECT_EQ(welcome->welcome().server_version(), TUMBLE_PROJECT_VERSION);

  server.process().signal(SIGTERM);
  ASSERT_EQ(server.process().wait(std::chrono::seconds(20)), 0) << server.log();
  sim::JournalReader journal;
  ASSERT_TRUE(journal.open(journal_path).ok());
  EXPECT_EQ(journal.header().server_version(), TUMBLE_PROJECT_VERSION);
}

}  // namespace
}  // namespace tumble::test
