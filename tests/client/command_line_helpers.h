// Helpers shared by the tests of tumble's command line: run the parser on
// an argument list as main() would, and check what it made of it.
#pragma once

#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "command_line.h"
#include "exit_code.h"

namespace tumble::cli::testing {

// Parses `args` as the words after "tumble".
inline ParsedCommandLine parse(std::vector<std::string> args) {
  args.insert(args.begin(), "tumble");
  std::vector<const char*> argv;
  for (const std::string& arg : args) argv.push_back(arg.c_str());
  return parse_command_line(static_cast<int>(argv.size()), argv.data());
}

// Parses a command line that must be valid and returns its command.
template <typename CommandType>
CommandType parse_command(std::vector<std::string> args) {
  ParsedCommandLine parsed = parse(std::move(args));
  EXPECT_TRUE(parsed.invocation.has_value()) << parsed.text;
  if (!parsed.invocation) return CommandType{};
  const auto* command = std::get_if<CommandType>(&parsed.invocation->command);
  EXPECT_NE(command, nullptr);
  return command ? *command : CommandType{};
}

// Expects a usage error reported on one line.
inline void expect_usage_error(std::vector<std::string> args) {
  std::string joined;
  for (const std::string& arg : args) joined += arg + " ";
  ParsedCommandLine parsed = parse(std::move(args));
  EXPECT_FALSE(parsed.invocation.has_value()) << joined;
  EXPECT_EQ(parsed.exit_code, kExitUsage) << joined;
  EXPECT_FALSE(parsed.text.empty()) << joined;
  EXPECT_EQ(parsed.text.find('\n'), std::string::npos) << parsed.text;
}

}  // namespace tumble::cli::testing
