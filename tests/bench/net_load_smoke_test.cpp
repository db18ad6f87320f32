// bench/net/net_load against the real tumbled on 127.0.0.1, with a few
// subscribers and bodies for a second: frames arrive and decode in every
// encoding, the bytes per body are those of the encoding, and nothing
// fails. Timing figures (latency, CPU, overruns) are printed, not checked.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "key_value_report.h"
#include "process.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

constexpr const char* kNoGravity = R"({"gravity": [0, 0, 0], "bodies": []})";
constexpr const char* kGravity = R"({"bodies": []})";

Report run_net_load(TumbledProcess& server, const std::vector<std::string>& args) {
  std::vector<std::string> argv = {TUMBLE_NET_LOAD_PATH,
                                   "--server",
                                   server.server(),
                                   "--server-pid",
                                   std::to_string(server.process().pid()),
                                   "--seconds",
                                   "1",
                                   "--spawners",
                                   "4"};
  argv.insert(argv.end(), args.begin(), args.end());
  const CommandResult result = run_command(argv, std::chrono::seconds(90));
  EXPECT_EQ(result.exit_code, 0) << result.err << result.out;
  return parse_report(result.out);
}

// A figure the report prints with exactly 2 decimals, in whole hundredths,
// read from its digits (no floating-point rounding).
std::int64_t hundredths(const Report& report, const std::string& key) {
  const auto it = report.find(key);
  if (it == report.end()) {
    ADD_FAILURE() << "no " << key << " in the report";
    return -1;
  }
  const std::string& text = it->second;
  const std::size_t point = text.find('.');
  const auto is_digit = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; };
  // Digits, a point, and two digits.
  if (point == std::string::npos || point == 0 || text.size() != point + 3 ||
      !std::all_of(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(point), is_digit) ||
      !std::all_of(text.begin() + static_cast<std::ptrdiff_t>(point) + 1, text.end(), is_digit)) {
    ADD_FAILURE() << key << "=" << text << " is not a figure with 2 decimals";
    return -1;
  }
  return std::stoll(text.substr(0, point)) * 100 + std::stoll(text.substr(point + 1));
}

// Frames came (no more than the window can hold), nothing failed.
void expect_frames_and_no_errors(const Report& report, double subscribers) {
  EXPECT_GT(number(report, "frames"), 0);
  // Not many more than the window holds: frames are counted once each. The
  // margin is generous, for the window's edges and for frames a loaded
  // machine delivers late in a bunch.
  EXPECT_LE(number(report, "frames"), 1.5 * number(report, "frames_expected") + 2 * subscribers);
  EXPECT_EQ(number(report, "errors"), 0);
  EXPECT_GE(number(report, "server_cpu_percent"), 0);  // a number: tumbled's /proc was read
  EXPECT_GE(number(report, "load_cpu_percent"), 0);
}

TEST(NetLoadSmoke, FieldInEveryEncoding) {
  std::map<std::string, double> bytes_per_body;
  for (const char* encoding : {"full", "quantized", "delta"}) {
    // A fresh server each time, into which net_load spawns 30 bodies (3 spin).
    TumbledProcess server(kNoGravity);
    ASSERT_TRUE(server.started()) << server.log();
    const Report report =
        run_net_load(server, {"--subscribers", "2", "--bodies", "30", "--rate", "30", "--encoding", encoding});
    SCOPED_TRACE(encoding);
    EXPECT_EQ(report.at("encoding"), encoding);
    expect_frames_and_no_errors(report, 2);
    bytes_per_body[encoding] = number(report, "bytes_per_body_frame");
  }
  // FULL: 28 bytes of float32 pose and an id byte, plus the frame's header shared by the bodies.
  EXPECT_GE(bytes_per_body["full"], 29);
  EXPECT_LE(bytes_per_body["full"], 35);
  // QUANTIZED: at most 10 bytes a body here (docs/protocol.md's layout), at least the 4 of its orientation.
  EXPECT_GE(bytes_per_body["quantized"], 4);
  EXPECT_LE(bytes_per_body["quantized"], 10.5);
  // DELTA: only the spinning tenth changes.
  EXPECT_GT(bytes_per_body["delta"], 0);
  EXPECT_LT(bytes_per_body["delta"], bytes_per_body["quantized"] / 2);
}

TEST(NetLoadSmoke, FallingCubesWithCommandsAndMixedEncodings) {
  TumbledProcess server(kGravity);
  ASSERT_TRUE(server.started()) << server.log();
  const Report report = run_net_load(server, {"--world", "cubes", "--subscribers", "3", "--bodies", "10", "--rate",
                                              "60", "--encoding", "mixed", "--commands-per-second", "20"});
  expect_frames_and_no_errors(report, 3);
  EXPECT_GT(number(report, "commands"), 0);
  EXPECT_GT(number(report, "bytes_per_body_frame"), 0);
}

// --latency-log: a CSV line for each change timed, the same samples the
// report's quantiles come from.
TEST(NetLoadSmoke, LatencyLogHoldsEveryTimedChange) {
  const std::filesystem::path log =
      std::filesystem::temp_directory_path() / ("tumble-latency-log-" + std::to_string(::getpid()) + ".csv");
  TumbledProcess server(kNoGravity);
  ASSERT_TRUE(server.started()) << server.log();
  const Report report = run_net_load(server, {"--subscribers", "1", "--bodies", "10", "--latency-log", log.string()});
  std::ifstream in(log);
  std::string line;
  ASSERT_TRUE(std::getline(in, line)) << "no " << log;
  EXPECT_EQ(line, "sent_s,latency_ms,applied_tick");
  std::vector<double> sent, latency;
  std::vector<unsigned long long> tick;
  while (std::getline(in, line)) {
    double s = 0, l = 0;
    unsigned long long t = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%llu", &s, &l, &t), 3) << line;
    sent.push_back(s);
    latency.push_back(l);
    tick.push_back(t);
  }
  std::filesystem::remove(log);
  // About 20 changes a second; a second's window holds several.
  ASSERT_GE(sent.size(), 3u);
  EXPECT_EQ(static_cast<double>(sent.size()), number(report, "latency_samples"));
  for (std::size_t i = 0; i < sent.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_GE(sent[i], 0);
    EXPECT_LT(sent[i], 1.0);  // within the one-second window
    EXPECT_GT(latency[i], 0);
    EXPECT_GT(tick[i], 0u);
    if (i == 0) continue;
    // Sent at least 20 ms apart, so at later ticks (240 Hz).
    EXPECT_GE(sent[i] - sent[i - 1], 0.019);
    EXPECT_GT(tick[i], tick[i - 1]);
  }
  // The report's p99 is the nearest-rank quantile of these samples.
  std::sort(latency.begin(), latency.end());
  const double p99 = latency[static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(latency.size()))) - 1];
  EXPECT_NEAR(number(report, "latency_ms_p99"), p99, 0.006);
}

// --stall-watch: the report counts the samples over the goal and those of
// them that span a stall, and the log marks each sample that spans one.
TEST(NetLoadSmoke, StallWatchMarksTheSamplesThatSpanAStall) {
  if (geteuid() != 0) GTEST_SKIP() << "the stall watch needs SCHED_FIFO at priority 90 (root here)";
  const std::filesystem::path log =
      std::filesystem::temp_directory_path() / ("tumble-stall-log-" + std::to_string(::getpid()) + ".csv");
  TumbledProcess server(kNoGravity);
  ASSERT_TRUE(server.started()) << server.log();
  const Report report =
      run_net_load(server, {"--subscribers", "1", "--bodies", "10", "--stall-watch", "--latency-log", log.string()});
  std::ifstream in(log);
  std::string line;
  ASSERT_TRUE(std::getline(in, line)) << "no " << log;
  EXPECT_EQ(line, "sent_s,latency_ms,applied_tick,in_stall");
  double over_goal = 0, over_goal_in_stall = 0, samples = 0;
  std::vector<double> outside_stalls_ms;
  while (std::getline(in, line)) {
    double s = 0, l = 0;
    unsigned long long t = 0;
    int in_stall = -1;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%llu,%d", &s, &l, &t, &in_stall), 4) << line;
    EXPECT_TRUE(in_stall == 0 || in_stall == 1) << line;
    ++samples;
    if (in_stall == 0) outside_stalls_ms.push_back(l);
    if (l > number(report, "latency_goal_ms")) {
      ++over_goal;
      over_goal_in_stall += in_stall;
    }
  }
  std::filesystem::remove(log);
  EXPECT_EQ(samples, number(report, "latency_samples"));
  EXPECT_EQ(over_goal, number(report, "latency_over_goal"));
  EXPECT_EQ(over_goal_in_stall, number(report, "latency_over_goal_in_stall"));
  EXPECT_EQ(samples - static_cast<double>(outside_stalls_ms.size()), number(report, "latency_in_stall"));
  // The p99 outside the stalls is the nearest-rank quantile of the log's
  // unmarked samples. The log has 3 decimals, the report 2, so the two
  // roundings put the quantile's log value within 5 thousandths of the
  // report's; compared in whole thousandths, as floating point would put
  // a value exactly 5 thousandths off on either side.
  ASSERT_FALSE(outside_stalls_ms.empty());
  const std::int64_t p99 = 10 * hundredths(report, "latency_ms_p99_outside_stalls");  // thousandths
  const auto rank = static_cast<std::ptrdiff_t>(std::ceil(0.99 * static_cast<double>(outside_stalls_ms.size())));
  const auto thousandths = [](double ms) { return std::llround(ms * 1000); };
  EXPECT_GE(std::count_if(outside_stalls_ms.begin(), outside_stalls_ms.end(),
                          [&](double l) { return thousandths(l) <= p99 + 5; }),
            rank);
  EXPECT_LT(std::count_if(outside_stalls_ms.begin(), outside_stalls_ms.end(),
                          [&](double l) { return thousandths(l) < p99 - 5; }),
            rank);
  // The stall figures agree with each other exactly: a whole count, and
  // the total the sum of lengths in whole hundredths of a millisecond, each
  // at least the 2 ms that makes a stall (bench/net/stall_watch.h) and none
  // longer than the longest; none at all when no sample spans one.
  const double stalls = number(report, "stalls");
  EXPECT_EQ(stalls, std::floor(stalls));
  const std::int64_t count = std::llround(stalls);
  const std::int64_t longest_cms = hundredths(report, "stall_ms_max");
  const std::int64_t total_cms = hundredths(report, "stall_ms_total");
  EXPECT_GE(total_cms, 200 * count);
  EXPECT_GE(total_cms, longest_cms);
  EXPECT_LE(total_cms, longest_cms * count);
  EXPECT_EQ(longest_cms >= 200, count > 0);
  EXPECT_EQ(longest_cms == 0, count == 0);
  if (number(report, "latency_in_stall") > 0) {
    EXPECT_GT(stalls, 0) << "a sample spans a stall that was not counted";
  }
}

// Without SCHED_FIFO (no RLIMIT_RTPRIO and, as root, no CAP_SYS_NICE after
// exec) --stall-watch is a clear error before any load.
TEST(NetLoadSmoke, StallWatchRefusedFailsFirst) {
  std::vector<std::string> argv = {"/usr/bin/prlimit", "--rtprio=0"};
  if (geteuid() == 0) argv.insert(argv.end(), {"/usr/bin/setpriv", "--bounding-set", "-sys_nice"});
  argv.insert(argv.end(), {TUMBLE_NET_LOAD_PATH, "--server", "127.0.0.1:1", "--stall-watch"});
  const CommandResult result = run_command(argv, std::chrono::seconds(30));
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_NE(result.err.find("net_load: --stall-watch: SCHED_FIFO at priority 90 refused"), std::string::npos)
      << result.err;
  EXPECT_EQ(result.out, "");
}

// A log it cannot write stops net_load before it loads the server.
// (No server listens on port 1: had it connected first, the error would be
// the refused connection.)
TEST(NetLoadSmoke, UnwritableLatencyLogFailsFirst) {
  const CommandResult result =
      run_command({TUMBLE_NET_LOAD_PATH, "--server", "127.0.0.1:1", "--latency-log", "/nonexistent-dir/latency.csv"},
                  std::chrono::seconds(30));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("/nonexistent-dir/latency.csv"), std::string::npos) << result.err;
  EXPECT_EQ(result.out, "");
}

}  // namespace
}  // namespace tumble::test
