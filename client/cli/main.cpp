// tumble: the command-line client of tumbled. Parse, run one subcommand,
// turn the outcome into an exit status (see exit_code.h).
#include <unistd.h>

#include <exception>
#include <iostream>

#include "command_line.h"
#include "commands.h"
#include "exit_code.h"
#include "tumble_client/nats_connection.h"

namespace {

// Over NATS, the run ends with nats.c's threads finished, not still in
// OpenSSL while the process exits.
struct NatsLibraryScope {
  bool used;
  ~NatsLibraryScope() {
    if (used) tumble::client::close_nats_library();
  }
};

}  // namespace

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
    const NatsLibraryScope nats_library{!parsed.invocation->global.nats.empty()};
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
