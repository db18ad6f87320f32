// bench/net/nats_takeover end to end, small and short: its own three
// JetStream nodes, a leader and a standby of a world of 20 cubes killed in
// turn twice, then the checkpoints of a world of 50. Checked: both kills
// were taken over by a new epoch with no stale frame, and checkpoints were
// written and measured. Takeover times and tick figures are printed, never
// checked against a clock.
#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "key_value_report.h"
#include "nats_server_process.h"
#include "process.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

std::map<std::string, Report> run_nats_takeover(const std::vector<std::string>& args, int* exit_code) {
  std::vector<std::string> argv = {TUMBLE_NATS_TAKEOVER_PATH, "--tumbled", tumbled_path(), "--nats-server",
                                   nats_server_path()};
  argv.insert(argv.end(), args.begin(), args.end());
  const CommandResult result = run_command(argv, std::chrono::seconds(200));
  *exit_code = result.exit_code;
  std::map<std::string, Report> phases;
  std::istringstream lines(result.out);
  for (std::string line; std::getline(lines, line);) {
    Report report = parse_report(line);
    if (report.count("phase")) phases[report["phase"]] = report;
  }
  if (result.exit_code != 0) ADD_FAILURE() << result.err << result.out;
  return phases;
}

TEST(NatsTakeoverSmoke, TwoKillsTakenOverAndCheckpointsMeasured) {
  if (nats_server_path().empty()) GTEST_SKIP() << "nats-server is not installed";
  int exit_code = -1;
  const auto phases =
      run_nats_takeover({"--runs", "2", "--bodies", "20", "--sizes", "50", "--seconds", "2", "--checkpoint-interval",
                         "0.25", "--lease-renew", "0.2", "--lease-timeout", "1"},
                        &exit_code);
  EXPECT_EQ(exit_code, 0);
  ASSERT_TRUE(phases.count("takeover") && phases.count("checkpoint"));
  const Report& takeover = phases.at("takeover");
  EXPECT_EQ(number(takeover, "runs"), 2);
  EXPECT_EQ(number(takeover, "missing"), 0);
  EXPECT_EQ(number(takeover, "stale_frames"), 0);
  EXPECT_EQ(number(takeover, "undecoded"), 0);
  // Each takeover is a new epoch: a lease revision, larger every time.
  EXPECT_GE(number(takeover, "epoch_last"), number(takeover, "epoch_first") + 2);
  EXPECT_GT(number(takeover, "takeover_ms_p50"), 0);
  EXPECT_EQ(number(takeover, "checkpoint_interval_ticks"), 60);

  const Report& checkpoint = phases.at("checkpoint");
  EXPECT_EQ(number(checkpoint, "bodies"), 50);
  EXPECT_GE(number(checkpoint, "checkpoints"), 1);
  EXPECT_EQ(number(checkpoint, "failed"), 0);
  // 50 spinning cubes, each a name, a shape and a state: some kilobytes.
  EXPECT_GT(number(checkpoint, "bytes"), 50 * 40);
  EXPECT_GT(number(checkpoint, "write_ms_max"), 0);
  EXPECT_GT(number(checkpoint, "capture_ms_max"), 0);
  EXPECT_GT(number(checkpoint, "tick_ms_p99"), 0);
  EXPECT_GT(number(checkpoint, "tick_ms_p99_without"), 0);
}

}  // namespace
}  // namespace tumble::test
