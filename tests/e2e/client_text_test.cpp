// Text from clients and files through the real tumbled and tumble: a forged
// log line stays one escaped line, names of digits only are refused in
// scenes and cleared from old state files, and `tumble bodies` lists a
// world of 100,000 bodies whole, page after page.
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"
#include "raw_client.h"
#include "replies.h"
#include "requests.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/state_file.h"
#include "tumbled_process.h"

namespace tumble::test {
namespace {

using tumble::v1::ServerMessage;

// The lines of the log that contain `text`.
std::vector<std::string> log_lines_with(const TumbledProcess& server, const std::string& text) {
  std::vector<std::string> found;
  for (const std::string& line : lines_of(server.log())) {
    if (line.find(text) != std::string::npos) found.push_back(line);
  }
  return found;
}

TEST(ClientText, AForgedLogLineInAClientNameStaysOneEscapedLine) {
  TumbledProcess server(kFloatingScene);
  ASSERT_TRUE(server.started()) << server.log();
  RawClient client(server.port());
  const auto welcome = client.handshake("bob\n2099-01-01 info [net] FAKE LINE\x1b[2J\x1b]0;owned\x07");
  ASSERT_TRUE(welcome && welcome->has_welcome());
  // The server logs the join before it reads the next request; once that is
  // answered, the line is written.
  ASSERT_TRUE(client.send(get_stats(2)));
  ASSERT_TRUE(client.read_until([](const ServerMessage& m) { return is_reply_to(m, 2); }));

  const std::vector<std::string> lines = log_lines_with(server, "FAKE LINE");
  ASSERT_EQ(lines.size(), 1u) << server.log();
  EXPECT_NE(lines[0].find("'bob\\n2099-01-01 info [net] FAKE LINE\\x1b[2J\\x1b]0;owned\\x07' joined"),
            std::string::npos)
      << lines[0];
  EXPECT_EQ(server.log().find('\x1b'), std::string::npos) << "a raw escape reached the log";
}

TEST(ClientText, ASceneWithANameOfDigitsOnlyIsRefusedAtStart) {
  const std::string dir = make_temp_dir();
  const std::string path = dir + "/digits.json";
  std::ofstream(path) << R"({"bodies": [{"name": "123", "shape": {"sphere": {"radius": 1}}, "mass": 1}]})";
  const CommandResult result = run_command({tumbled_path(), "--scene", path, "--listen", "127.0.0.1:0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("bodies[0].name: '123' is digits only, which clients read as a body id"), std::string::npos)
      << result.err;
}

TEST(ClientText, AStateFileWithANameOfDigitsOnlyLoadsWithoutIt) {
  // A state file as a server without name limits wrote it: body 1 is "42".
  tumble::v1::Scene scene;
  ASSERT_TRUE(sim::parse_scene_json(kFloatingScene, &scene).ok());
  std::unique_ptr<sim::Simulation> sim;
  ASSERT_TRUE(sim::Simulation::create(scene, sim::SimConfig{}, &sim).ok());
  tumble::v1::WorldState state;
  sim->capture(&state);
  ASSERT_EQ(state.bodies(1).spec().name(), "ball");
  state.mutable_bodies(1)->mutable_spec()->set_name("42");
  const std::string path = make_temp_dir() + "/old.state";
  ASSERT_TRUE(sim::write_state_file(path, state).ok());

  TumbledProcess server(kFloatingScene, {"--state", path});
  ASSERT_TRUE(server.started()) << server.log();
  EXPECT_EQ(log_lines_with(server, "bodies[1].spec.name: '42' is digits only").size(), 1u) << server.log();
  const nlohmann::json list = run_json(server, {"bodies"});
  ASSERT_EQ(list["bodies"].size(), 2u) << list;
  EXPECT_EQ(list["bodies"][0]["name"], "crate");
  EXPECT_EQ(list["bodies"][1]["name"], "");
  EXPECT_EQ(list["bodies"][1]["id"], 1);
}

// 100,000 static crates, 2 m apart on a 1000 x 100 grid, each turned about
// y: about 10 MB of BodyInfo, more than a client may leave unread
// (--max-pending-bytes, 8 MiB), and nothing for the physics to do.
std::string hundred_thousand_bodies() {
  std::ostringstream scene;
  scene << R"({"gravity": [0, 0, 0], "bodies": [)";
  for (int i = 0; i < 100000; ++i) {
    scene << (i ? "," : "") << R"({"name": "crate-)" << i << R"(", "static": true,)"
          << R"( "shape": {"box": {"half_extents": [0.5, 0.25, 0.4]}}, "orientation": [0.8, 0, 0.6, 0],)"
          << R"( "position": [)" << 2 * (i % 1000) << ", 0.25, " << 2 * (i / 1000) << "]}";
  }
  scene << "]}";
  return scene.str();
}

TEST(ClientText, TumbleBodiesListsAHundredThousandBodiesWhole) {
  TumbledProcess server(hundred_thousand_bodies());
  ASSERT_TRUE(server.started()) << server.log();
  const CommandResult result = server.cli({"--json", "bodies"}, std::chrono::seconds(120));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json list = nlohmann::json::parse(result.out, nullptr, false);
  ASSERT_TRUE(list.is_object()) << result.out.substr(0, 200);
  const nlohmann::json& bodies = list["bodies"];
  ASSERT_EQ(bodies.size(), 100000u);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    ASSERT_EQ(bodies[i]["id"], i);
    ASSERT_EQ(bodies[i]["name"], "crate-" + std::to_string(i));
  }
  EXPECT_EQ(bodies[99999]["position"], nlohmann::json::array({1998.0, 0.25, 198.0}));
  EXPECT_EQ(bodies[99999]["orientation"], nlohmann::json::array({0.8, 0.0, 0.6, 0.0}));
}

}  // namespace
}  // namespace tumble::test
