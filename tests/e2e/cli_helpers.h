// What the end-to-end tests share when they drive the real tumble CLI
// against the real tumbled: the floating two-body scene and a fixture that
// serves it, running a command that must succeed, reading its JSON, and
// finding a body in a body list or a frame.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tumbled_process.h"

namespace tumble::test {

// Zero gravity, so every motion comes from the commands alone: a 2 kg cube
// of side 1 m ("crate", id 0) at the origin and a 1 kg ball of radius 0.5 m
// ("ball", id 1) at (0, 0, 50), out of the crate's way.
extern const char* const kFloatingScene;

// One tick at tumbled's default rate of 240 Hz, in seconds.
inline constexpr double kDt = 1.0 / 240.0;

// Runs `tumble --json ARGS...` against `server`; expects exit status 0 and
// one JSON value on stdout, and returns it (a discarded value if it is not JSON).
nlohmann::json run_json(const TumbledProcess& server, std::vector<std::string> args);

// Runs `tumble ARGS...` against `server` and expects exit status 0.
void run_ok(const TumbledProcess& server, const std::vector<std::string>& args);

// The body called `name` in a body list or frame (an object with a
// "bodies" array); null when there is none.
const nlohmann::json* find_body(const nlohmann::json& list, const std::string& name);

// The same, for a body that must be there: a test failure and a null JSON
// value when it is not.
const nlohmann::json& body(const nlohmann::json& list, const std::string& name);

// Sends `server` SIGTERM and returns its exit code (-1 when it has not
// ended within 30 s).
int terminate(TumbledProcess& server);

// The tick of the state file or checkpoint at `path`; 0 while there is none.
std::uint64_t checkpoint_tick(const std::string& path);

// The lines of `text`, without their newlines.
std::vector<std::string> lines_of(const std::string& text);

// Each line of `text` parsed as JSON (discarded values for lines that are not).
std::vector<nlohmann::json> json_lines(const std::string& text);

// `tumble ARGS...` against a server, running while the test does (a
// subscriber, say): its stdout goes to a file the test reads as it grows,
// so the test can wait for a line the command prints. The destructor kills
// a command still running.
class BackgroundCli {
 public:
  BackgroundCli(const TumbledProcess& server, const std::vector<std::string>& args);
  ~BackgroundCli();
  BackgroundCli(const BackgroundCli&) = delete;
  BackgroundCli& operator=(const BackgroundCli&) = delete;

  // The whole lines printed so far, without their newlines.
  std::vector<std::string> lines() const;

  // Waits until at least `count` whole lines are printed; false if the
  // command ends or `timeout` passes first.
  bool wait_for_lines(std::size_t count, std::chrono::milliseconds timeout = std::chrono::seconds(30));

  // Waits for the command to end (killing it after `timeout`) and returns
  // its exit code and output.
  CommandResult finish(std::chrono::milliseconds timeout = std::chrono::seconds(30));

 private:
  std::string dir_;
  std::string out_path_;
  std::string err_path_;
  std::unique_ptr<ChildProcess> process_;
};

// A fixture: a fresh tumbled on kFloatingScene for each test.
class FloatingSceneTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(server_.started()) << server_.log(); }

  // run_json against server_.
  nlohmann::json run_json(std::vector<std::string> args) { return test::run_json(server_, std::move(args)); }

  TumbledProcess server_{kFloatingScene};
};

}  // namespace tumble::test
