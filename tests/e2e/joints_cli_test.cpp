// Joints end to end: a scene file's joints loaded by the real tumbled (and
// a bad one stopping it), and the joint requests through the real tumble
// CLI: joint add, joints, motor, joint remove, their errors, and the joint
// events a subscriber is sent. The world is paused and stepped wherever
// motion is checked, so every number is a function of ticks.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "process.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using nlohmann::json;

class JointsCliTest : public FloatingSceneTest {
 protected:
  // A command that must fail with exit status `exit_code` and say `text` on stderr.
  void expect_failure(const std::vector<std::string>& args, const std::string& text, int exit_code = 1) {
    const CommandResult result = server_.cli(args);
    EXPECT_EQ(result.exit_code, exit_code) << result.out;
    EXPECT_NE(result.err.find(text), std::string::npos) << result.err;
  }
};

TEST_F(JointsCliTest, AHingeDrivenByItsMotorTurnsAndGoesAway) {
  run_json({"pause"});
  const json added = run_json({"joint", "add", "hinge", "--hinge", "world", "crate", "--anchor", "0", "0", "0",
                               "--axis", "0", "1", "0", "--limits", "-3", "3"});
  EXPECT_EQ(added["joint_id"], 0);
  run_json({"motor", "hinge", "--speed", "2", "--max-torque", "100"});
  run_json({"step", "120"});

  const json list = run_json({"joints"});
  ASSERT_EQ(list["joints"].size(), 1u) << list.dump();
  const json& hinge = list["joints"][0];
  EXPECT_EQ(hinge["name"], "hinge");
  EXPECT_EQ(hinge["type"], "hinge");
  EXPECT_EQ(hinge["body_a"], nullptr);
  EXPECT_EQ(hinge["body_a_name"], "world");
  EXPECT_EQ(hinge["body_b_name"], "crate");
  EXPECT_EQ(hinge["limits"], json::array({-3.0, 3.0}));
  EXPECT_EQ(hinge["motor"]["speed"], 2.0);
  EXPECT_EQ(hinge["motor"]["max_torque"], 100.0);
  EXPECT_NEAR(hinge["state"]["speed"].get<double>(), 2.0, 0.05);
  EXPECT_GT(hinge["state"]["position"].get<double>(), 0.5) << "0.5 s at up to 2 rad/s";
  EXPECT_NEAR(body(run_json({"bodies"}), "crate")["angular_velocity"][1].get<double>(), 2.0, 0.05);

  const CommandResult table = server_.cli({"joints"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  ASSERT_EQ(lines_of(table.out).size(), 2u) << table.out;
  EXPECT_NE(table.out.find("speed 2.000 max 100.000"), std::string::npos) << table.out;

  run_json({"motor", "0", "--off"});
  EXPECT_EQ(run_json({"joints"})["joints"][0]["motor"], nullptr);
  run_json({"joint", "remove", "hinge"});
  EXPECT_TRUE(run_json({"joints"})["joints"].empty());
  expect_failure({"joint", "remove", "hinge"}, "UNKNOWN_JOINT");
}

// `subscribe --fields pose,joints` prints the joints' states with the
// bodies: the same a `joints` listing of that tick shows, in float32.
TEST_F(JointsCliTest, SubscribeWithJointsShowsTheirStateAtTheFramesTick) {
  run_json({"pause"});
  run_json({"joint", "add", "hinge", "--hinge", "world", "crate", "--anchor", "0", "0", "0", "--axis", "0", "1", "0"});
  run_json({"motor", "hinge", "--speed", "1.5", "--max-torque", "100"});
  run_json({"step", "60"});
  const json list = run_json({"joints"});
  const CommandResult subscribed =
      server_.cli({"--json", "subscribe", "--fields", "pose,joints", "--bodies", "crate", "--count", "1"});
  ASSERT_EQ(subscribed.exit_code, 0) << subscribed.err;
  const json frame = json::parse(lines_of(subscribed.out).at(0));
  EXPECT_EQ(frame["tick"], list["tick"]) << "paused: the frame shows the tick the listing did";
  ASSERT_EQ(frame["joints"].size(), 1u) << frame.dump();
  EXPECT_EQ(frame["joints"][0]["id"], 0);
  const json& state = list["joints"][0]["state"];
  EXPECT_EQ(frame["joints"][0]["position"].get<double>(),
            static_cast<double>(static_cast<float>(state["position"].get<double>())));
  EXPECT_EQ(frame["joints"][0]["speed"].get<double>(),
            static_cast<double>(static_cast<float>(state["speed"].get<double>())));
  EXPECT_GT(frame["joints"][0]["speed"].get<double>(), 1.0) << "the motor turns it";
  EXPECT_FALSE(frame["bodies"][0].contains("linear_velocity")) << "pose only";

  const CommandResult text = server_.cli({"subscribe", "--fields", "all,joints", "--count", "1"});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("  joint #0  position "), std::string::npos) << text.out;
  const CommandResult plain = server_.cli({"subscribe", "--count", "1"});
  EXPECT_EQ(plain.out.find("joint #"), std::string::npos) << plain.out;
}

TEST_F(JointsCliTest, BadJointsAreRefusedAndNothingChanges) {
  expect_failure({"joint", "add", "j", "--ball", "crate", "ghost", "--anchor", "0", "0", "0"},
                 "no body 'ghost' in the world");
  expect_failure({"joint", "add", "j", "--hinge", "world", "crate", "--anchor", "0", "0", "0", "--limits", "1", "-1"},
                 "joint.limits: the lower limit 1 is above the upper limit -1");
  expect_failure({"joint", "add", "j", "--slider", "crate", "crate", "--anchor", "0", "0", "0"},
                 "a joint joins two different bodies");
  expect_failure({"joint", "add", "j", "--ball", "world", "crate", "--anchor", "nan", "0", "0"}, "joint.anchor.x");
  run_json({"joint", "add", "ball", "--ball", "crate", "ball", "--anchor", "0", "0", "25"});
  expect_failure({"motor", "ball", "--speed", "1", "--max-torque", "1"}, "which has no motor");
  expect_failure({"motor", "ball"}, "give --speed S or --position P", 2);
  expect_failure({"joint", "add", "j", "--ball", "--hinge", "world", "crate"}, "", 2);
  EXPECT_EQ(run_json({"joints"})["joints"].size(), 1u);
}

TEST_F(JointsCliTest, SubscribersHearOfJointsAddedAndOfABodysJointsRemovedWithIt) {
  BackgroundCli events(server_, {"--json", "subscribe", "--events", "--rate", "1"});
  ASSERT_TRUE(events.wait_for_lines(1)) << "the first frame";
  run_json(
      {"joint", "add", "tie", "--distance", "crate", "ball", "--anchor", "0", "0", "0", "--anchor-b", "0", "0", "50"});
  run_json({"remove", "ball"});
  // The events of each edit arrive before the frame of its tick; stop at the body's removal.
  // The joined pair may fall asleep between the two edits (a joint is
  // something to rest on) when the machine is slow: sleep events are not
  // the edits' and are passed over.
  std::vector<json> seen;
  for (std::size_t count = 2; seen.size() < 3 && events.wait_for_lines(count); ++count) {
    const json line = json::parse(events.lines()[count - 1]);
    if (line.contains("event") && line["event"] != "asleep" && line["event"] != "awake") seen.push_back(line);
  }
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0]["event"], "joint-added");
  EXPECT_EQ(seen[0]["joint_name"], "tie");
  EXPECT_EQ(seen[0]["body_a"], 0);
  EXPECT_EQ(seen[0]["body_b"], 1);
  EXPECT_EQ(seen[1]["event"], "joint-removed");
  EXPECT_EQ(seen[2]["event"], "removed");
  EXPECT_TRUE(run_json({"joints"})["joints"].empty());
}

TEST(JointsScene, TumbledLoadsASceneWithJoints) {
  TumbledProcess server(R"({"gravity": [0, -9.81, 0], "bodies": [
      {"name": "bob", "shape": {"sphere": {"radius": 0.1}}, "mass": 1, "position": [1, 2, 0]}],
    "joints": [{"name": "rope", "type": "distance", "body_a": "world", "body_b": "bob",
                "anchor_a": [0, 2, 0], "anchor_b": [1, 2, 0]}]})");
  ASSERT_TRUE(server.started()) << server.log();
  run_json(server, {"pause"});
  run_json(server, {"step", "120"});  // about a quarter of its swing: near the bottom
  const json list = run_json(server, {"joints"});
  ASSERT_EQ(list["joints"].size(), 1u);
  EXPECT_EQ(list["joints"][0]["name"], "rope");
  EXPECT_EQ(list["joints"][0]["type"], "distance");
  // The bob swings on its rope: a metre from the anchor, not fallen away.
  const json bodies = run_json(server, {"bodies"});
  const json& bob = body(bodies, "bob");
  const double x = bob["position"][0].get<double>(), y = bob["position"][1].get<double>() - 2;
  EXPECT_NEAR(std::sqrt(x * x + y * y), 1.0, 0.02) << bob.dump();
  EXPECT_LT(y, -0.5);
}

TEST(JointsScene, AnInvalidJointStopsTumbledWithAMessageNamingTheJointAndField) {
  const std::string dir = make_temp_dir();
  const std::string path = dir + "/bad.json";
  std::ofstream(path) << R"({"bodies": [{"name": "a", "shape": {"sphere": {"radius": 1}}, "mass": 1}],
      "joints": [{"name": "hinge", "type": "hinge", "body_a": "world", "body_b": "a", "anchor": [0, 0, 0],
                  "motor": {"speed": 1}}]})";
  const CommandResult result = run_command({tumbled_path(), "--scene", path, "--listen", "127.0.0.1:0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("joints[0].motor: missing field 'max_torque' (joint 'hinge')"), std::string::npos)
      << result.err;
}

}  // namespace
}  // namespace tumble::test
