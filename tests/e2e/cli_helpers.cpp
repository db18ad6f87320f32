#include "cli_helpers.h"

#include <sstream>

#include <gtest/gtest.h>

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

}  // namespace tumble::test
