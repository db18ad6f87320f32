// The world-editing, clock and monitoring subcommands of the tumble CLI
// against the real tumbled. Where motion is checked the world is paused and
// stepped, so every number is a function of ticks, not of timing.
#include <gtest/gtest.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <thread>

#include "cli_helpers.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using nlohmann::json;

class ControlCliTest : public FloatingSceneTest {
 protected:
  // A command that must fail with exit status 1 and name `code` on stderr.
  void expect_server_error(const std::vector<std::string>& args, const std::string& code) {
    const CommandResult result = server_.cli(args);
    EXPECT_EQ(result.exit_code, 1) << result.out;
    EXPECT_NE(result.err.find(code), std::string::npos) << result.err;
  }

  // Pauses the server and returns the tick it stays at.
  std::uint64_t pause() { return run_json({"pause"})["applied_tick"].get<std::uint64_t>(); }
};

TEST_F(ControlCliTest, SpawnedBodiesAppearInBodies) {
  const json ack = run_json(
      {"spawn", "rock", "--sphere", "0.25", "--mass", "3", "--at", "1", "2", "3", "--velocity", "0", "0", "0"});
  EXPECT_EQ(ack["body_id"], 2);
  EXPECT_TRUE(ack.contains("applied_tick"));
  const json box = run_json({"spawn", "plank", "--box", "1", "0.1", "0.5", "--static", "--at", "0", "-5", "0"});
  EXPECT_EQ(box["body_id"], 3);

  const json list = run_json({"bodies"});
  ASSERT_EQ(list["bodies"].size(), 4u);
  const json* rock = find_body(list, "rock");
  ASSERT_NE(rock, nullptr) << list.dump();
  EXPECT_EQ((*rock)["id"], 2);
  EXPECT_EQ((*rock)["shape"], "sphere");
  EXPECT_DOUBLE_EQ((*rock)["mass"].get<double>(), 3.0);
  const json* plank = find_body(list, "plank");
  ASSERT_NE(plank, nullptr);
  EXPECT_EQ((*plank)["position"], json::array({0.0, -5.0, 0.0})) << "a static body stays put";

  const CommandResult human = server_.cli({"spawn", "pebble", "--capsule", "0.1", "0.2"});
  ASSERT_EQ(human.exit_code, 0) << human.err;
  EXPECT_NE(human.out.find("spawned body 4 at tick"), std::string::npos) << human.out;
}

TEST_F(ControlCliTest, SpawnRefusesADuplicateNameAndOneTooMany) {
  expect_server_error({"spawn", "crate", "--sphere", "1"}, "INVALID_ARGUMENT");
  TumbledProcess small(kFloatingScene, {"--max-bodies", "3"});
  ASSERT_TRUE(small.started()) << small.log();
  EXPECT_EQ(small.cli({"spawn", "one", "--sphere", "1"}).exit_code, 0);
  const CommandResult over = small.cli({"spawn", "two", "--sphere", "1"});
  EXPECT_EQ(over.exit_code, 1);
  EXPECT_NE(over.err.find("RESOURCE_EXHAUSTED"), std::string::npos) << over.err;
}

TEST_F(ControlCliTest, RemoveTakesTheBodyAway) {
  run_json({"remove", "ball"});
  const json list = run_json({"bodies"});
  EXPECT_EQ(list["bodies"].size(), 1u);
  EXPECT_EQ(find_body(list, "ball"), nullptr);
  expect_server_error({"remove", "ball"}, "UNKNOWN_BODY");
}

TEST_F(ControlCliTest, SetMovesTheBodyAndKeepsWhatIsNotGiven) {
  pause();
  run_json({"set", "crate", "--position", "1", "2", "3", "--velocity", "0.5", "0", "0"});
  json crate = *find_body(run_json({"bodies"}), "crate");
  EXPECT_EQ(crate["position"], json::array({1.0, 2.0, 3.0}));
  EXPECT_EQ(crate["linear_velocity"], json::array({0.5, 0.0, 0.0}));
  EXPECT_EQ(crate["asleep"], false);  // moving

  run_json({"set", "crate", "--orientation", "0", "0", "1", "0"});  // half a turn about y
  crate = *find_body(run_json({"bodies"}), "crate");
  EXPECT_EQ(crate["position"], json::array({1.0, 2.0, 3.0}));
  EXPECT_EQ(crate["linear_velocity"], json::array({0.5, 0.0, 0.0}));
  EXPECT_EQ(crate["orientation"], json::array({0.0, 0.0, 1.0, 0.0}));
  expect_server_error({"set", "crate", "--orientation", "2", "0", "0", "0"}, "INVALID_ARGUMENT");
}

TEST_F(ControlCliTest, APersistentForceAcceleratesUntilCleared) {
  pause();
  // 2 N on 2 kg: 1 m/s^2, so 1 m/s after 240 ticks.
  run_json({"force", "crate", "--force", "2", "0", "0", "--persistent"});
  run_json({"step", "240"});
  double v = find_body(run_json({"bodies"}), "crate")->at("linear_velocity")[0].get<double>();
  EXPECT_NEAR(v, 1.0, 1e-12);
  run_json({"step", "240"});
  v = find_body(run_json({"bodies"}), "crate")->at("linear_velocity")[0].get<double>();
  EXPECT_NEAR(v, 2.0, 1e-12) << "still pushing";

  run_json({"clear", "crate"});
  run_json({"step", "240"});
  v = find_body(run_json({"bodies"}), "crate")->at("linear_velocity")[0].get<double>();
  EXPECT_NEAR(v, 2.0, 1e-12) << "no more push after clear";

  run_json({"torque", "ball", "--torque", "0", "0.1", "0", "--persistent"});
  run_json({"clear"});
  run_json({"step", "10"});
  EXPECT_EQ(find_body(run_json({"bodies"}), "ball")->at("angular_velocity"), json::array({0.0, 0.0, 0.0}));
}

TEST_F(ControlCliTest, PausedTheTickStaysTheSameAcrossFrames) {
  const std::uint64_t tick = pause();
  // A subscriber gets the current state, then a frame for each edit; the tick never moves.
  BackgroundCli subscriber(server_, {"--json", "subscribe", "--bodies", "ball", "--count", "3"});
  ASSERT_TRUE(subscriber.wait_for_lines(1)) << "the subscriber printed no frame";
  run_json({"impulse", "ball", "--impulse", "0", "0", "1"});
  // The impulse's frame is printed before the next edit: two frames, not one that replaced the other.
  ASSERT_TRUE(subscriber.wait_for_lines(2)) << "no frame for the impulse";
  run_json({"set", "ball", "--position", "0", "0", "40"});
  const CommandResult frames = subscriber.finish();
  ASSERT_EQ(frames.exit_code, 0) << frames.err;
  const auto lines = lines_of(frames.out);
  ASSERT_EQ(lines.size(), 3u) << frames.out;
  for (const std::string& line : lines) EXPECT_EQ(json::parse(line)["tick"], tick) << line;
  EXPECT_EQ(json::parse(lines[1])["bodies"][0]["linear_velocity"], json::array({0.0, 0.0, 1.0}));
  EXPECT_EQ(json::parse(lines[2])["bodies"][0]["position"], json::array({0.0, 0.0, 40.0}));

  // Each request is answered by a later pass of the sim loop than the
  // edits: had the loop stepped in between, the tick would have moved.
  EXPECT_EQ(run_json({"stats"})["tick"], tick);
  EXPECT_EQ(run_json({"bodies"})["tick"], tick);
}

TEST_F(ControlCliTest, StepFiveAdvancesExactlyFiveTicks) {
  expect_server_error({"step", "5"}, "FAILED_PRECONDITION");
  const std::uint64_t tick = pause();
  const json stepped = run_json({"step", "5"});
  EXPECT_EQ(stepped["applied_tick"], tick + 5);
  EXPECT_EQ(run_json({"stats"})["tick"], tick + 5);
  const CommandResult one = server_.cli({"step"});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(one.out, "stepped to tick " + std::to_string(tick + 6) + "\n");

  run_json({"resume"});
  std::uint64_t later = tick + 6;
  for (int i = 0; i < 200 && later <= tick + 30; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    later = run_json({"stats"})["tick"].get<std::uint64_t>();
  }
  EXPECT_GT(later, tick + 30) << "running again after resume";
}

TEST_F(ControlCliTest, AStepCutShortByAnotherClientsResumeSaysSo) {
  const std::uint64_t tick = pause();
  BackgroundCli stepper(server_, {"--timeout", "120", "step", "1000000"});
  // Under way once the paused tick moves.
  std::uint64_t now = tick;
  for (int i = 0; i < 500 && now == tick; ++i) now = run_json({"stats"})["tick"].get<std::uint64_t>();
  ASSERT_GT(now, tick) << "the step never started";
  const std::uint64_t resumed = run_json({"resume"})["applied_tick"].get<std::uint64_t>();
  const CommandResult stepped = stepper.finish();
  ASSERT_EQ(stepped.exit_code, 0) << stepped.err;
  // "stepped to tick T, cut short by a resume with L ticks left", T + L = tick + 1000000.
  unsigned long long reached = 0;
  unsigned long long left = 0;
  ASSERT_EQ(std::sscanf(stepped.out.c_str(), "stepped to tick %llu, cut short by a resume with %llu ticks left\n",
                        &reached, &left),
            2)
      << stepped.out;
  EXPECT_EQ(reached + left, tick + 1000000) << stepped.out;
  EXPECT_EQ(resumed, reached + 1) << "the Resume's first tick follows the last the step reached";
  EXPECT_FALSE(run_json({"stats"})["paused"].get<bool>());
}

TEST_F(ControlCliTest, ResetRestoresTheScene) {
  const json initial = run_json({"bodies"});
  run_json({"impulse", "crate", "--impulse", "4", "0", "0"});
  run_json({"spawn", "rock", "--sphere", "1", "--at", "0", "9", "0"});
  run_json({"remove", "ball"});
  run_json({"force", "crate", "--force", "1", "1", "1", "--persistent"});
  pause();
  run_json({"reset"});
  const json after = run_json({"bodies"});
  ASSERT_EQ(after["bodies"].size(), 2u) << after.dump();
  for (std::size_t i = 0; i < 2; ++i) {
    const json& was = initial["bodies"][i];
    const json& is = after["bodies"][i];
    EXPECT_EQ(is["id"], was["id"]);
    EXPECT_EQ(is["name"], was["name"]);
    EXPECT_EQ(is["position"], was["position"]);
    EXPECT_EQ(is["orientation"], was["orientation"]);
    EXPECT_EQ(is["linear_velocity"], json::array({0.0, 0.0, 0.0}));
  }
  run_json({"step", "10"});
  EXPECT_EQ(find_body(run_json({"bodies"}), "crate")->at("position"), json::array({0.0, 0.0, 0.0}))
      << "the persistent force went with the reset";
  EXPECT_EQ(run_json({"spawn", "rock", "--sphere", "1"})["body_id"], 3) << "ids are not handed out twice";
}

TEST_F(ControlCliTest, StatsJsonIsOneObjectWithTheServersFigures) {
  const CommandResult result = server_.cli({"--json", "stats"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  ASSERT_EQ(lines_of(result.out).size(), 1u) << result.out;
  const json stats = json::parse(result.out);
  ASSERT_TRUE(stats.is_object());
  EXPECT_TRUE(stats["tick"].is_number_unsigned());
  EXPECT_NEAR(stats["sim_time"].get<double>(), static_cast<double>(stats["tick"].get<std::uint64_t>()) * kDt, 1e-9);
  EXPECT_EQ(stats["paused"], false);
  EXPECT_EQ(stats["bodies"], 2);
  EXPECT_EQ(stats["clients"], 1) << "this very connection";
  EXPECT_TRUE(stats["overruns"].is_number_unsigned());
  EXPECT_TRUE(stats["tick_ms_p99"].is_number());
  EXPECT_GE(stats["tick_ms_p99"].get<double>(), stats["tick_ms_p50"].get<double>());
  // A tick's CPU time is read inside its wall-clock span; a pass woken by a
  // timer begins after its deadline, never before.
  EXPECT_GT(stats["tick_cpu_ms_p99"].get<double>(), 0.0);
  EXPECT_LE(stats["tick_cpu_ms_p99"].get<double>(), stats["tick_ms_p99"].get<double>());
  EXPECT_LE(stats["tick_cpu_ms_p50"].get<double>(), stats["tick_ms_p50"].get<double>());
  EXPECT_GT(stats["tick_start_late_ms_p99"].get<double>(), 0.0);
  EXPECT_GE(stats["tick_start_late_ms_p99"].get<double>(), stats["tick_start_late_ms_p50"].get<double>());
  EXPECT_DOUBLE_EQ(stats["tick_rate_hz"].get<double>(), 240);
  EXPECT_GT(stats["bytes_sent"].get<std::uint64_t>(), 0u);

  pause();
  EXPECT_EQ(run_json({"stats"})["paused"], true);
  const CommandResult human = server_.cli({"stats"});
  ASSERT_EQ(human.exit_code, 0);
  EXPECT_NE(human.out.find("paused            yes"), std::string::npos) << human.out;
}

TEST_F(ControlCliTest, TickRateChangesTheServersRate) {
  run_json({"tick-rate", "120"});
  EXPECT_DOUBLE_EQ(run_json({"stats"})["tick_rate_hz"].get<double>(), 120);
  expect_server_error({"tick-rate", "0"}, "INVALID_ARGUMENT");
}

TEST_F(ControlCliTest, WatchPrintsCountTablesSeparatedByBlankLines) {
  const CommandResult result = server_.cli({"watch", "--count", "3", "--rate", "30"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out.find('\x1b'), std::string::npos) << "no terminal codes into a pipe";
  std::vector<std::string> tables;
  std::string current;
  for (const std::string& line : lines_of(result.out)) {
    if (line.empty()) {
      tables.push_back(current);
      current.clear();
    } else {
      current += line + "\n";
    }
  }
  tables.push_back(current);
  ASSERT_EQ(tables.size(), 3u) << result.out;
  for (const std::string& table : tables) {
    const auto lines = lines_of(table);
    ASSERT_EQ(lines.size(), 4u) << table;  // tick line, header, crate, ball
    EXPECT_EQ(lines[0].rfind("tick ", 0), 0u) << table;
    EXPECT_NE(lines[1].find("NAME"), std::string::npos);
    EXPECT_NE(lines[1].find("ASLEEP"), std::string::npos);
    EXPECT_EQ(lines[2].rfind("crate", 0), 0u) << table;
    EXPECT_EQ(lines[3].rfind("ball", 0), 0u) << table;
    EXPECT_NE(lines[3].find("(0.000, 0.000, 50.000)"), std::string::npos) << table;
  }
}

TEST_F(ControlCliTest, WatchJsonShowsSpeedAndSleep) {
  pause();
  run_json({"set", "ball", "--velocity", "3", "4", "0"});
  const CommandResult result = server_.cli({"--json", "watch", "--bodies", "ball", "--count", "1"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const json table = json::parse(result.out);
  ASSERT_EQ(table["bodies"].size(), 1u);
  EXPECT_EQ(table["bodies"][0]["name"], "ball");
  EXPECT_NEAR(table["bodies"][0]["speed"].get<double>(), 5.0, 1e-6);
  EXPECT_EQ(table["bodies"][0]["asleep"], false);
}

TEST_F(ControlCliTest, WatchShowsTheSameTableInEveryEncoding) {
  // Paused at a speed of 5 m/s off every grid; every encoding prints it
  // within the quantization's error (1/128 m/s a component).
  pause();
  run_json({"set", "ball", "--velocity", "3.001", "4.002", "0"});
  for (const char* encoding : {"full", "quantized", "delta"}) {
    const CommandResult result = server_.cli({"--json", "watch", "--encoding", encoding, "--count", "1"});
    ASSERT_EQ(result.exit_code, 0) << encoding << ": " << result.err;
    const json table = json::parse(result.out);
    ASSERT_EQ(table["bodies"].size(), 2u) << encoding;
    EXPECT_EQ(table["bodies"][0]["name"], "crate") << encoding;
    EXPECT_EQ(table["bodies"][1]["name"], "ball") << encoding;
    EXPECT_NEAR(table["bodies"][1]["speed"].get<double>(), 5.0022, 0.01) << encoding;
    EXPECT_NEAR(table["bodies"][1]["position"][2].get<double>(), 50.0, 0.5 / 1024 + 1e-6) << encoding;
  }
}

TEST_F(ControlCliTest, SubscribeCanAskForPosesOnlyAndEvents) {
  // Paused, the frames are the state at once and the one the spawn makes.
  pause();
  BackgroundCli subscriber(server_, {"--json", "subscribe", "--fields", "pose", "--events", "--count", "2"});
  ASSERT_TRUE(subscriber.wait_for_lines(1)) << "the subscriber printed no frame";  // it is subscribed
  run_json({"spawn", "rock", "--sphere", "1", "--at", "0", "20", "0"});
  const CommandResult result = subscriber.finish();
  ASSERT_EQ(result.exit_code, 0) << result.err;
  bool saw_spawn = false;
  std::size_t frames = 0;
  for (const std::string& line : lines_of(result.out)) {
    const json message = json::parse(line);
    if (message.contains("event")) {
      EXPECT_EQ(message["event"], "spawned") << line;
      EXPECT_EQ(message["name"], "rock");
      EXPECT_EQ(message["id"], 2);
      saw_spawn = true;
      continue;
    }
    ++frames;
    for (const json& body : message["bodies"]) {
      EXPECT_TRUE(body.contains("position"));
      EXPECT_FALSE(body.contains("linear_velocity")) << line;
    }
  }
  EXPECT_EQ(frames, 2u);
  EXPECT_TRUE(saw_spawn) << result.out;
  EXPECT_EQ(json::parse(lines_of(result.out).back())["bodies"].size(), 3u) << "the last frame shows the rock";
}

TEST_F(ControlCliTest, UsageErrorsOfTheNewSubcommandsExitTwo) {
  EXPECT_EQ(server_.cli({"spawn", "rock"}).exit_code, 2) << "no shape";
  EXPECT_EQ(server_.cli({"spawn", "rock", "--sphere", "1", "--box", "1", "1", "1"}).exit_code, 2) << "two shapes";
  EXPECT_EQ(server_.cli({"spawn", "42", "--sphere", "1"}).exit_code, 2) << "a name that reads as an id";
  EXPECT_EQ(server_.cli({"spawn", "rock", "--sphere", "1", "--static", "--kinematic"}).exit_code, 2);
  EXPECT_EQ(server_.cli({"force", "crate", "--force", "1", "0", "0", "--persistent", "--ticks", "3"}).exit_code, 2);
  EXPECT_EQ(server_.cli({"subscribe", "--fields", "speed"}).exit_code, 2);
  EXPECT_EQ(server_.cli({"step", "many"}).exit_code, 2);
  EXPECT_EQ(server_.cli({"tick-rate"}).exit_code, 2);
  EXPECT_EQ(run_json({"bodies"})["bodies"].size(), 2u) << "nothing was sent";
}

}  // namespace
}  // namespace tumble::test
