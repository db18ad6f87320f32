// tumble: the command-line client of tumbled. Parse, run one subcommand,
// turn the outcome into an exit status (see exit_code.h).
#include <unistd.h>

#include <exception>
#include <iostream>

#include "command_line.h"
#include "commands.h"
#include "exit_code.h"

int main(int argc, char** argv) {
  try {
    const tumble::cli::ParsedCommandLine parsed = tumble::cli::parse_command_line(argc, argv);
    if (!parsed.invocation) {
      if (parsed.exit_code == tumble::cli::kExitSuccess) {
        std::cout << parsed.text << std::flush;
      } else {
        std::cerr << "tumble: " << parsed.text << std::endl;
      }
      return parsed.exit_code;
    }
    if (auto failure = tumble::cli::run(*parsed.invocation, std::cout, ::isatty(STDOUT_FILENO) == 1)) {
      std::cerr << "tumble: " << failure->message << std::endl;
      return tumble::cli::kExitFailure;
    }
    return tumble::cli::kExitSuccess;
  } catch (const std::exception& error) {
    std::cerr << "tumble: internal error: " << error.what() << std::endl;
    return tumble::cli::kExitFailure;
  }
}
