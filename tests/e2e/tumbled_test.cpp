// tumbled as a user starts it: flags, scene errors, signals.
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>

#include "tumbled_process.h"

namespace tumble::test {
namespace {

const char* kScene = R"({"bodies": [{"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2}]})";

TEST(Tumbled, StopsCleanlyOnSigterm) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  server.process().signal(SIGTERM);
  const auto code = server.process().wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value()) << "tumbled did not stop";
  EXPECT_EQ(*code, 0) << server.log();
  EXPECT_NE(server.log().find("SIGTERM"), std::string::npos) << server.log();
}

TEST(Tumbled, StopsCleanlyOnSigint) {
  TumbledProcess server(kScene);
  ASSERT_TRUE(server.started()) << server.log();
  server.process().signal(SIGINT);
  const auto code = server.process().wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0) << server.log();
}

TEST(Tumbled, InvalidSceneStopsItWithAMessageNamingTheField) {
  const std::string dir = make_temp_dir();
  const std::string path = dir + "/bad.json";
  std::ofstream(path) << R"({"bodies": [{"name": "a", "shape": {"sphere": {"radius": -2}}, "mass": 1}]})";
  const CommandResult result = run_command({tumbled_path(), "--scene", path, "--listen", "127.0.0.1:0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("bodies[0].shape.sphere.radius"), std::string::npos) << result.err;
}

TEST(Tumbled, UnreadableSceneNamesThePath) {
  const CommandResult result =
      run_command({tumbled_path(), "--scene", "/nonexistent/scene.json", "--listen", "127.0.0.1:0"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("/nonexistent/scene.json"), std::string::npos) << result.err;
}

TEST(Tumbled, BadFlagsAreUsageErrors) {
  EXPECT_EQ(run_command({tumbled_path(), "--listen", "no-port"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--tick-rate", "fast"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--log-level", "loud"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--no-such-flag"}).exit_code, 2);
  EXPECT_EQ(run_command({tumbled_path(), "--version"}).exit_code, 0);
}

TEST(Tumbled, AddressInUseIsAClearError) {
  TumbledProcess first(kScene);
  ASSERT_TRUE(first.started());
  const CommandResult second = run_command({tumbled_path(), "--listen", first.server()});
  EXPECT_EQ(second.exit_code, 1);
  EXPECT_NE(second.err.find("cannot bind"), std::string::npos) << second.err;
}

}  // namespace
}  // namespace tumble::test
