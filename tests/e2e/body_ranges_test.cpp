// Bodies within their physical ranges, against the real tumbled and tumble:
// a body outside them is refused with the field and the range, from a
// client, a scene file or a state file; a body whose state diverges in a
// step is removed with an event and never reaches the state file.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "poll_until.h"
#include "sim/state_file.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using nlohmann::json;

// Every number of every body in a `tumble --json bodies` list is a finite number (JSON has no NaN: it prints null).
void expect_finite_bodies(const json& list) {
  for (const json& body : list["bodies"]) {
    for (const char* field : {"position", "orientation", "linear_velocity", "angular_velocity"}) {
      for (const json& value : body[field]) {
        EXPECT_TRUE(value.is_number() && std::isfinite(value.get<double>())) << body.dump();
      }
    }
  }
}

// tumbled started on a scene or state file that it must refuse: exit
// status 1 and the error on stderr. A server that starts is killed after 15 s.
CommandResult refused_start(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {tumbled_path(), "--listen", "127.0.0.1:0"};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command(argv, std::chrono::seconds(15));
}

TEST_F(FloatingSceneTest, ATinyOrHugeMassIsRefusedWithItsRange) {
  // The mass that used to turn the body's pose into NaN within a tick.
  CommandResult result = server_.cli({"spawn", "tiny", "--sphere", "0.3", "--mass", "1e-40", "--at", "14", "1", "14"});
  EXPECT_EQ(result.exit_code, 1) << result.out;
  EXPECT_NE(result.err.find("body.mass: 1e-40 kg is outside 1e-6 .. 1e9 kg"), std::string::npos) << result.err;
  // A huge one is told the range, not that it is not a positive number.
  result = server_.cli({"spawn", "huge", "--sphere", "0.3", "--mass", "1e30"});
  EXPECT_EQ(result.exit_code, 1) << result.out;
  EXPECT_NE(result.err.find("body.mass: 1e30 kg is outside 1e-6 .. 1e9 kg"), std::string::npos) << result.err;
  // Too dense for its size.
  result = server_.cli({"spawn", "dense", "--sphere", "0.01", "--mass", "1e9"});
  EXPECT_EQ(result.exit_code, 1) << result.out;
  EXPECT_NE(result.err.find("body.mass: 1e9 kg in 4.18879e-6 m^3 is a density of 2.38732e14 kg/m^3, outside 1e-6 .. "
                            "3e10 kg/m^3"),
            std::string::npos)
      << result.err;

  // Nothing was added, and the world goes on stepping and serving.
  const std::uint64_t tick = run_json({"stats"})["tick"].get<std::uint64_t>();
  const json list = run_json({"bodies"});
  EXPECT_EQ(list["bodies"].size(), 2u) << list.dump();
  expect_finite_bodies(list);
  EXPECT_TRUE(poll_until([&] { return run_json({"stats"})["tick"].get<std::uint64_t>() > tick; }));
}

TEST(BodyRanges, ASceneWithABodyOutsideTheRangesIsRefusedNamingIt) {
  const std::string scene = make_temp_dir() + "/scene.json";
  std::ofstream(scene) << R"({"bodies": [
      {"name": "ground", "static": true, "shape": {"plane": {}}},
      {"name": "tiny", "shape": {"sphere": {"radius": 0.3}}, "mass": 1e-40, "position": [14, 1, 14]}]})";
  const CommandResult result = refused_start({"--scene", scene});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("bodies[1].mass: 1e-40 kg is outside 1e-6 .. 1e9 kg"), std::string::npos) << result.err;
}

TEST(BodyRanges, AStateFileWithABodyOutsideTheRangesIsRefusedNamingIt) {
  const std::string state = make_temp_dir() + "/world.state";
  {
    TumbledProcess saving(kFloatingScene, {"--state", state});
    ASSERT_TRUE(saving.started()) << saving.log();
    ASSERT_EQ(terminate(saving), 0) << saving.log();
  }
  // As a file of an older server could hold it: the ball made far too light.
  tumble::v1::WorldState world;
  bool exists = false;
  ASSERT_TRUE(sim::read_state_file(state, &world, &exists).ok());
  ASSERT_EQ(world.bodies_size(), 2);
  ASSERT_EQ(world.bodies(1).spec().name(), "ball");
  world.mutable_bodies(1)->mutable_spec()->set_mass(1e-40);
  ASSERT_TRUE(sim::write_state_file(state, world).ok());
  // Without the last good file beside it (tumbled would resume from that:
  // the damaged state files' own tests hold that case), the server refuses.
  std::filesystem::remove(state + ".prev");

  const CommandResult result = refused_start({"--state", state});
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("bodies[1].spec.mass: 1e-40 kg is outside 1e-6 .. 1e9 kg"), std::string::npos)
      << result.err;
  // Refused, not rewritten: the file is as it was.
  tumble::v1::WorldState after;
  ASSERT_TRUE(sim::read_state_file(state, &after, &exists).ok());
  EXPECT_EQ(after.SerializeAsString(), world.SerializeAsString());
}

TEST(BodyRanges, ABodyThatDivergesIsRemovedWithAnEventAndNeverSaved) {
  const std::string state = make_temp_dir() + "/world.state";
  TumbledProcess server(kFloatingScene, {"--state", state});
  ASSERT_TRUE(server.started()) << server.log();
  run_ok(server, {"pause"});
  BackgroundCli subscriber(server, {"--json", "subscribe", "--fields", "pose", "--events"});
  ASSERT_TRUE(subscriber.wait_for_lines(1)) << "the subscriber printed no frame";  // it is subscribed
  // Every number within the ranges: the lightest body and the largest force,
  // 1e15 m/s^2, so one tick makes 4.2e12 m/s, beyond the world's 1e9.
  const json spawned =
      run_json(server, {"spawn", "flea", "--sphere", "0.01", "--mass", "1e-6", "--at", "0", "10", "0"});
  const std::uint32_t flea = spawned["body_id"].get<std::uint32_t>();
  run_ok(server, {"force", "flea", "--force", "1e9", "0", "0", "--persistent"});
  const std::uint64_t stepped = run_json(server, {"step", "1"})["applied_tick"].get<std::uint64_t>();

  // The subscriber hears that the flea diverged and then that it was removed, at the tick of the step.
  auto events = [&] {
    std::vector<json> out;
    for (const std::string& line : subscriber.lines()) {
      const json message = json::parse(line, nullptr, false);
      if (message.is_object() && message.contains("event") && message["event"] != "spawned") out.push_back(message);
    }
    return out;
  };
  ASSERT_TRUE(poll_until([&] { return events().size() >= 2; })) << server.log();
  const std::vector<json> heard = events();
  EXPECT_EQ(heard[0], json({{"event", "diverged"}, {"tick", stepped}, {"id", flea}, {"name", "flea"}}));
  EXPECT_EQ(heard[1], json({{"event", "removed"}, {"tick", stepped}, {"id", flea}, {"name", "flea"}}));

  // Counted, logged once, and the world goes on without it.
  const json stats = run_json(server, {"stats"});
  EXPECT_EQ(stats["bodies_diverged"], 1);
  EXPECT_EQ(stats["bodies"], 2);
  const json list = run_json(server, {"bodies"});
  EXPECT_EQ(find_body(list, "flea"), nullptr);
  expect_finite_bodies(list);
  run_ok(server, {"step", "24"});
  const std::string log = server.log();
  const std::string line = "removed body " + std::to_string(flea) + " 'flea' at tick " + std::to_string(stepped);
  EXPECT_NE(log.find(line), std::string::npos) << log;
  EXPECT_EQ(log.find(line), log.rfind(line)) << "logged more than once\n" << log;

  // Never saved: the state file holds the two others, and the server resumes from it.
  ASSERT_EQ(terminate(server), 0) << server.log();
  tumble::v1::WorldState saved;
  bool exists = false;
  ASSERT_TRUE(sim::read_state_file(state, &saved, &exists).ok());
  ASSERT_EQ(saved.bodies_size(), 2);
  for (const tumble::v1::SavedBody& body : saved.bodies()) EXPECT_NE(body.spec().name(), "flea");
  EXPECT_TRUE(saved.loads().empty()) << "the flea's persistent force went with it";
  TumbledProcess resumed(R"({"bodies": []})", {"--state", state});
  ASSERT_TRUE(resumed.started()) << resumed.log();
  EXPECT_EQ(run_json(resumed, {"bodies"})["bodies"].size(), 2u);
}

}  // namespace
}  // namespace tumble::test
