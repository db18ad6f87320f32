// The tumble CLI against the real tumbled, as a user runs them: every
// number checked against the closed-form answer for a free body.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <thread>

#include "cli_helpers.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using nlohmann::json;

class CliTest : public FloatingSceneTest {
 protected:
  // The body list once the server has stepped at least to `tick`.
  json bodies_at_or_after(std::uint64_t tick) {
    for (int attempt = 0; attempt < 600; ++attempt) {
      json list = run_json({"bodies"});
      if (list.value("tick", std::uint64_t{0}) >= tick) return list;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ADD_FAILURE() << "the server never reached tick " << tick;
    return {};
  }
};

TEST_F(CliTest, BodiesListsTheScene) {
  const json list = run_json({"bodies"});
  ASSERT_EQ(list["bodies"].size(), 2u);
  const json& crate = body(list, "crate");
  EXPECT_EQ(crate["shape"], "box");
  EXPECT_DOUBLE_EQ(crate["mass"].get<double>(), 2.0);
  EXPECT_EQ(crate["orientation"], json::array({1.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(body(list, "ball")["position"], json::array({0.0, 0.0, 50.0}));
}

TEST_F(CliTest, HumanReadableBodiesNameEveryBody) {
  const CommandResult result = server_.cli({"bodies"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("crate"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("ball"), std::string::npos) << result.out;
}

TEST_F(CliTest, ForceForOneSecondGivesMomentumFTimesT) {
  // 10 N for 1 s on 2 kg: v = F t / M = 5 m/s, exactly, once the 240 ticks are over.
  const json ack = run_json({"force", "crate", "--force", "10", "0", "0", "--duration", "1"});
  ASSERT_TRUE(ack.contains("applied_tick")) << ack.dump();
  const std::uint64_t applied = ack["applied_tick"];
  const json list = bodies_at_or_after(applied + 240);
  const json& crate = body(list, "crate");
  EXPECT_NEAR(crate["linear_velocity"][0].get<double>(), 5.0, 1e-9);
  EXPECT_DOUBLE_EQ(crate["linear_velocity"][1].get<double>(), 0.0);
  // Semi-implicit Euler: after the force, x = (F/M) dt^2 n(n+1)/2 + v (ticks since) dt.
  const double ticks_after = static_cast<double>(list["tick"].get<std::uint64_t>() - (applied + 239));
  const double expected_x = 5.0 * kDt * kDt * 240 * 241 / 2 + 5.0 * ticks_after * kDt;
  EXPECT_NEAR(crate["position"][0].get<double>(), expected_x, 1e-9);
  EXPECT_EQ(body(list, "ball")["linear_velocity"], json::array({0.0, 0.0, 0.0})) << "only the crate moved";
}

TEST_F(CliTest, ForceForTicksLastsExactlyThatMany) {
  const json ack = run_json({"force", "1", "--force", "0", "0", "-3", "--ticks", "12"});
  const json list = bodies_at_or_after(ack["applied_tick"].get<std::uint64_t>() + 12);
  // Body 1 is the ball (1 kg): v = F n dt / M.
  EXPECT_NEAR(body(list, "ball")["linear_velocity"][2].get<double>(), -3.0 * 12 * kDt, 1e-12);
}

TEST_F(CliTest, ImpulseAtABodyPointSpinsTheCrate) {
  // J = (0, 2, 0) N s at body point (0.5, 0, 0): L = r x J = (0, 0, 1); a cube of
  // 2 kg and half extent 0.5 has I = M/3 (h^2 + h^2) = 1/3, so w = 3 rad/s about z.
  const json ack = run_json({"impulse", "crate", "--impulse", "0", "2", "0", "--at", "0.5", "0", "0", "--local"});
  const json list = bodies_at_or_after(ack["applied_tick"]);
  const json& crate = body(list, "crate");
  EXPECT_NEAR(crate["angular_velocity"][2].get<double>(), 3.0, 1e-9);
  EXPECT_NEAR(crate["linear_velocity"][1].get<double>(), 1.0, 1e-12);
}

TEST_F(CliTest, TorqueSpinsUpTheBall) {
  // tau = 0.4 N m for 60 ticks on a solid sphere, I = 2/5 M r^2 = 0.1: w = tau t / I = 1 rad/s.
  const json ack = run_json({"torque", "ball", "--torque", "0", "0.4", "0", "--ticks", "60"});
  const json list = bodies_at_or_after(ack["applied_tick"].get<std::uint64_t>() + 60);
  EXPECT_NEAR(body(list, "ball")["angular_velocity"][1].get<double>(), 1.0, 1e-9);
}

TEST_F(CliTest, SubscribePrintsOneJsonLinePerFrameAtTheRate) {
  const CommandResult result =
      server_.cli({"--json", "subscribe", "--bodies", "crate", "--rate", "30", "--count", "4"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::vector<std::uint64_t> ticks;
  for (const std::string& line : lines_of(result.out)) {
    const json frame = json::parse(line, nullptr, false);
    ASSERT_FALSE(frame.is_discarded()) << line;
    ASSERT_EQ(frame["bodies"].size(), 1u) << line;
    const json& crate = frame["bodies"][0];
    EXPECT_EQ(crate["name"], "crate");
    EXPECT_EQ(crate["id"], 0);
    EXPECT_EQ(crate["position"].size(), 3u);
    EXPECT_EQ(crate["orientation"], json::array({1.0, 0.0, 0.0, 0.0}));
    EXPECT_EQ(crate["linear_velocity"].size(), 3u);
    EXPECT_EQ(crate["angular_velocity"].size(), 3u);
    EXPECT_NEAR(frame["time"].get<double>(), static_cast<double>(frame["tick"].get<std::uint64_t>()) * kDt, 1e-6);
    ticks.push_back(frame["tick"]);
  }
  ASSERT_EQ(ticks.size(), 4u) << result.out;
  // 30 Hz at 240 Hz is a frame every 8 ticks; the first frame is the state at subscription.
  for (std::size_t i = 2; i < ticks.size(); ++i) EXPECT_EQ(ticks[i] - ticks[i - 1], 8u);
  EXPECT_EQ(ticks[1] % 8, 0u);
}

TEST_F(CliTest, SubscribeShowsAForceTakingEffect) {
  // A subscriber prints the 1 kg ball at 60 Hz while 3 N along z push it
  // for 24 ticks. Frame by frame: at rest before the tick the Ack names;
  // from that tick on, after n ticks of force, v = F n dt / m and (semi-
  // implicit Euler) z = 50 + (F / m) dt^2 n (n + 1) / 2; once the force is
  // over, coasting at 0.3 m/s.
  constexpr double kForce = 3;
  constexpr std::uint64_t kTicks = 24;
  BackgroundCli subscriber(server_, {"--json", "subscribe", "--bodies", "ball", "--rate", "60", "--count", "120"});
  ASSERT_TRUE(subscriber.wait_for_lines(1)) << "the subscriber printed no frame";  // it is subscribed
  const json ack = run_json({"force", "ball", "--force", "0", "0", "3", "--ticks", std::to_string(kTicks)});
  ASSERT_TRUE(ack.contains("applied_tick")) << ack.dump();
  const std::uint64_t applied = ack["applied_tick"];
  const CommandResult result = subscriber.finish();
  ASSERT_EQ(result.exit_code, 0) << result.err;

  std::size_t at_rest = 0, pushed = 0, coasting = 0;
  for (const json& frame : json_lines(result.out)) {
    ASSERT_FALSE(frame.is_discarded()) << result.out;
    const std::uint64_t tick = frame["tick"];
    const double n = tick < applied ? 0.0 : static_cast<double>(std::min(tick - applied + 1, kTicks));
    const double coast = tick < applied + kTicks ? 0.0 : static_cast<double>(tick - (applied + kTicks - 1));
    const double v = kForce * n * kDt;
    const double z = 50 + kForce * kDt * kDt * n * (n + 1) / 2 + v * coast * kDt;
    if (tick < applied) {
      ++at_rest;
    } else if (coast > 0) {
      ++coasting;
    } else {
      ++pushed;
    }
    const json& ball = body(frame, "ball");
    SCOPED_TRACE("tick " + std::to_string(tick) + ", force applied at tick " + std::to_string(applied));
    // The frame's numbers are float32: 50 m is good to 4e-6 m.
    EXPECT_NEAR(ball["linear_velocity"][2].get<double>(), v, 1e-6);
    EXPECT_NEAR(ball["position"][2].get<double>(), z, 1e-5);
    EXPECT_EQ(ball["linear_velocity"][0], 0.0);
    EXPECT_EQ(ball["linear_velocity"][1], 0.0);
    EXPECT_EQ(ball["position"][0], 0.0);
    EXPECT_EQ(ball["position"][1], 0.0);
  }
  EXPECT_GE(at_rest, 1u) << "the frame printed before the force";
  EXPECT_GE(pushed, 3u) << "24 ticks at a frame every 4";
  EXPECT_GE(coasting, 1u) << result.out;
}

// The JSON lines `tumble --json subscribe ARGS...` prints.
std::vector<json> subscribe_lines(TumbledProcess& server, std::vector<std::string> args) {
  args.insert(args.begin(), {"--json", "subscribe"});
  const CommandResult result = server.cli(args);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  return json_lines(result.out);
}

// Largest |a[k] - b[k]| of two JSON arrays of numbers.
double largest_difference(const json& a, const json& b) {
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k].get<double>() - b[k].get<double>()));
  return worst;
}

TEST_F(CliTest, QuantizedAndDeltaSubscriptionsPrintTheBodiesFullDoesWithinTheGrid) {
  // Paused, so that every encoding shows the same tick: an odd position, a
  // turned orientation and velocities off every grid.
  run_json({"pause"});
  run_json({"set", "crate", "--position", "1.23456", "-2.34567", "3.45678", "--orientation", "0.8", "0.2", "-0.4",
            "0.4", "--velocity", "0.123", "-4.567", "8.9", "--angular-velocity", "1.234", "0", "-0.5"});
  const std::vector<json> full = subscribe_lines(server_, {"--count", "1"});
  ASSERT_EQ(full.size(), 1u);
  for (const char* encoding : {"quantized", "delta"}) {
    const std::vector<json> lines = subscribe_lines(server_, {"--encoding", encoding, "--count", "1"});
    ASSERT_EQ(lines.size(), 1u) << encoding;
    const json& got = lines[0];
    EXPECT_EQ(got["tick"], full[0]["tick"]) << encoding;
    ASSERT_EQ(got["bodies"].size(), full[0]["bodies"].size()) << encoding;
    for (std::size_t i = 0; i < got["bodies"].size(); ++i) {
      const json& q = got["bodies"][i];
      const json& f = full[0]["bodies"][i];
      EXPECT_EQ(q["id"], f["id"]);
      EXPECT_EQ(q["name"], f["name"]);
      // Half a 1/1024 m step, plus float32 rounding of the printed values.
      EXPECT_LE(largest_difference(q["position"], f["position"]), 0.5 / 1024 + 1e-6) << encoding << " " << q;
      // Smallest three: |q' - q| <= 2.4e-3 (proto/wire/smallest_three.h); both have w > 0 here.
      EXPECT_LE(largest_difference(q["orientation"], f["orientation"]), 2.4e-3) << encoding << " " << q;
      EXPECT_LE(largest_difference(q["linear_velocity"], f["linear_velocity"]), 0.5 / 128 + 1e-6) << encoding;
      EXPECT_LE(largest_difference(q["angular_velocity"], f["angular_velocity"]), 0.5 / 256 + 1e-6) << encoding;
    }
  }
}

TEST_F(CliTest, DeltaSubscriptionPrintsEveryBodyInEveryFrame) {
  // The crate rests and only the ball moves, so the frames after the first
  // carry the ball alone: the CLI fills in the crate from the key frame.
  run_json({"set", "ball", "--velocity", "0", "0", "1"});
  const std::vector<json> lines = subscribe_lines(server_, {"--encoding", "delta", "--rate", "60", "--count", "5"});
  ASSERT_EQ(lines.size(), 5u);
  double last_z = -1;
  for (const json& frame : lines) {
    ASSERT_EQ(frame["bodies"].size(), 2u) << frame;
    EXPECT_EQ(body(frame, "crate")["position"], json::array({0.0, 0.0, 0.0})) << frame;
    const double z = body(frame, "ball")["position"][2].get<double>();
    EXPECT_GT(z, last_z);
    last_z = z;
  }
}

TEST_F(CliTest, UnknownBodyIsAOneLineErrorAndAFailure) {
  const CommandResult result = server_.cli({"force", "ghost", "--force", "1", "0", "0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("UNKNOWN_BODY"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("ghost"), std::string::npos) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

TEST_F(CliTest, NaNForceIsRefusedByTheServer) {
  const CommandResult result = server_.cli({"force", "crate", "--force", "nan", "0", "0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("INVALID_ARGUMENT"), std::string::npos) << result.err;
  const json list = run_json({"bodies"});
  EXPECT_EQ(body(list, "crate")["linear_velocity"], json::array({0.0, 0.0, 0.0}));
}

TEST_F(CliTest, UsageErrorsExitTwo) {
  EXPECT_EQ(server_.cli({"force", "crate"}).exit_code, 2) << "missing --force";
  EXPECT_EQ(server_.cli({"force", "crate", "--force", "1", "x", "0"}).exit_code, 2);
  EXPECT_EQ(server_.cli({"force", "crate", "--force", "1", "0", "0", "--local"}).exit_code, 2);
  EXPECT_EQ(server_.cli({"juggle"}).exit_code, 2);
}

TEST(CliConnection, RefusedConnectionIsAOneLineFailure) {
  // Port 1 on loopback: nothing listens there.
  const CommandResult result = run_command({tumble_cli_path(), "--server", "127.0.0.1:1", "bodies"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("127.0.0.1:1"), std::string::npos) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

TEST(CliConnection, ServerFromTheEnvironment) {
  TumbledProcess server(kFloatingScene);
  ASSERT_TRUE(server.started());
  ::setenv("TUMBLE_SERVER", server.server().c_str(), 1);
  const CommandResult result = run_command({tumble_cli_path(), "--json", "bodies"});
  ::unsetenv("TUMBLE_SERVER");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("crate"), std::string::npos);
}

}  // namespace
}  // namespace tumble::test
