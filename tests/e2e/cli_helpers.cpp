#include "cli_helpers.h"

#include <csignal>
#include <cstdio>
#include <optional>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "poll_until.h"
#include "sim/state_file.h"

namespace tumble::test {

using nlohmann::json;

const char* const kFloatingScene = R"({"gravity": [0, 0, 0], "bodies": [
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2},
    {"name": "ball", "shape": {"sphere": {"radius": 0.5}}, "mass": 1, "position": [0, 0, 50]}]})";

json run_json(const TumbledProcess& server, std::vector<std::string> args) {
  args.insert(args.begin(), "--json");
  const CommandResult result = server.cli(args);
  EXPECT_EQ(result.exit_code, 0) << "tumble " << args[1] << ": " << result.err;
  const json parsed = json::parse(result.out, nullptr, false);
  EXPECT_FALSE(parsed.is_discarded()) << "stdout: " << result.out;
  return parsed;
}

void run_ok(const TumbledProcess& server, const std::vector<std::string>& args) {
  const CommandResult result = server.cli(args);
  EXPECT_EQ(result.exit_code, 0) << "tumble " << args[0] << ": " << result.err;
}

int terminate(TumbledProcess& server) {
  server.process().signal(SIGTERM);
  return server.process().wait(std::chrono::seconds(30)).value_or(-1);
}

std::uint64_t checkpoint_tick(const std::string& path) {
  tumble::v1::WorldState state;
  bool exists = false;
  if (!sim::read_state_file(path, &state, &exists).ok() || !exists) return 0;
  return state.tick();
}

const json* find_body(const json& list, const std::string& name) {
  if (!list.contains("bodies")) return nullptr;
  for (const json& b : list["bodies"]) {
    if (b["name"] == name) return &b;
  }
  return nullptr;
}

const json& body(const json& list, const std::string& name) {
  if (const json* found = find_body(list, name)) return *found;
  ADD_FAILURE() << "no body " << name << " in " << list.dump();
  static const json kNone;
  return kNone;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<json> json_lines(const std::string& text) {
  std::vector<json> values;
  for (const std::string& line : lines_of(text)) values.push_back(json::parse(line, nullptr, false));
  return values;
}

BackgroundCli::BackgroundCli(const TumbledProcess& server, const std::vector<std::string>& args)
    : dir_(make_temp_dir()), out_path_(dir_ + "/out"), err_path_(dir_ + "/err") {
  std::vector<std::string> argv = {tumble_cli_path(), "--server", server.server()};
  argv.insert(argv.end(), args.begin(), args.end());
  process_ = std::make_unique<ChildProcess>(argv, out_path_, err_path_);
}

BackgroundCli::~BackgroundCli() {
  process_.reset();  // kills the command if it still runs
  std::remove(out_path_.c_str());
  std::remove(err_path_.c_str());
  ::rmdir(dir_.c_str());
}

std::vector<std::string> BackgroundCli::lines() const {
  std::string text = read_file(out_path_);
  text.erase(text.find_last_of('\n') + 1);  // a line still being written is not one yet (npos + 1 is 0)
  return lines_of(text);
}

bool BackgroundCli::wait_for_lines(std::size_t count, std::chrono::milliseconds timeout) {
  const bool printed = poll_until([&] { return lines().size() >= count || !process_->running(); }, timeout);
  return printed && lines().size() >= count;
}

CommandResult BackgroundCli::finish(std::chrono::milliseconds timeout) {
  CommandResult result;
  if (const std::optional<int> code = process_->wait(timeout)) {
    result.exit_code = *code;
  } else {
    process_->signal(SIGKILL);
    process_->wait(std::chrono::seconds(10));
  }
  result.out = read_file(out_path_);
  result.err = read_file(err_path_);
  return result;
}

}  // namespace tumble::test
