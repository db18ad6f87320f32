// bench/net/nats_load end to end, small and short: it starts its own three
// nats-server nodes and tumbled, and a few subscriptions spread over the
// nodes read the stream for a second. Checked: every subscription got going
// and decoded frames, none more than the window holds, the CPU of every
// process was read, and nothing failed. Timing figures (latency, CPU,
// delivery under load) are printed, never checked.
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

Report run_nats_load(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {
      TUMBLE_NATS_LOAD_PATH, "--tumbled", tumbled_path(), "--nats-server", nats_server_path(), "--seconds", "1",
      "--spawners",          "4"};
  argv.insert(argv.end(), args.begin(), args.end());
  const CommandResult result = run_command(argv, std::chrono::seconds(100));
  EXPECT_EQ(result.exit_code, 0) << result.err << result.out;
  return parse_report(result.out);
}

// Every subscription held a whole frame before the window and decoded
// frames in it; no more arrived than the window holds; nothing failed.
void expect_every_subscription_read(const Report& report, double subscribers) {
  EXPECT_EQ(number(report, "subscribers_ready"), subscribers);
  EXPECT_GT(number(report, "frames"), 0);
  EXPECT_GT(number(report, "frames_shown"), 0);
  EXPECT_LE(number(report, "frames_shown"), number(report, "frames"));
  // Frames are counted once each: not many more than the window holds (its
  // edges, and frames a loaded machine delivers late in a bunch).
  EXPECT_LE(number(report, "frames"), 1.5 * number(report, "frames_expected") + 2 * subscribers);
  EXPECT_GT(number(report, "bytes_per_body_frame"), 0);
  EXPECT_EQ(number(report, "errors"), 0);
  // Read from /proc: tumbled's, the three nodes' and its own.
  EXPECT_GE(number(report, "server_cpu_percent"), 0);
  EXPECT_GE(number(report, "nats_cpu_percent"), 0);
  EXPECT_GE(number(report, "load_cpu_percent"), 0);
  // The probe was changed over .rpc at least once in the window.
  EXPECT_GE(number(report, "latency_samples") + number(report, "latency_lost"), 1);
}

TEST(NatsLoadSmoke, FieldDeltaStreamThroughEveryNode) {
  if (nats_server_path().empty()) GTEST_SKIP() << "nats-server is not installed";
  // Six subscriptions on three connections: two through each node.
  const Report report = run_nats_load({"--bodies", "30", "--subscribers", "6", "--connections", "3"});
  EXPECT_EQ(report.at("transport"), "nats");
  EXPECT_EQ(report.at("encoding"), "delta");
  EXPECT_EQ(number(report, "connections"), 3);
  expect_every_subscription_read(report, 6);
}

TEST(NatsLoadSmoke, RestingCubesWithRareKeyFrames) {
  if (nats_server_path().empty()) GTEST_SKIP() << "nats-server is not installed";
  const Report report =
      run_nats_load({"--world", "cubes", "--bodies", "10", "--settle", "--subscribers", "2", "--key-interval", "5"});
  EXPECT_EQ(report.at("world"), "cubes");
  EXPECT_EQ(number(report, "key_interval_s"), 5);
  expect_every_subscription_read(report, 2);
  // The payload without NATS's MSG lines is the smaller figure.
  EXPECT_LT(number(report, "kbit_per_s_per_subscriber"), number(report, "wire_kbit_per_s_per_subscriber"));
}

}  // namespace
}  // namespace tumble::test
