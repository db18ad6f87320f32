// Child processes for end-to-end tests: the real tumbled and tumble
// binaries, started with posix_spawn, bounded in time, never left behind.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace tumble::test {

// What a finished command did.
struct CommandResult {
  int exit_code = -1;  // -1 when killed for running past its timeout
  std::string out;     // stdout
  std::string err;     // stderr
};

// Runs `argv` to completion (killed after `timeout`), capturing its output.
CommandResult run_command(const std::vector<std::string>& argv,
                          std::chrono::milliseconds timeout = std::chrono::seconds(30));

// A process that runs while the test does. The destructor kills it.
class ChildProcess {
 public:
  // Starts `argv` with stdout and stderr appended to `log_path`, in the
  // test's environment with `env` ("NAME=VALUE" each) added or replacing
  // what the test has under those names.
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path,
               const std::vector<std::string>& env = {});
  // Starts `argv` with stdout appended to `out_path` and stderr to `err_path`.
  ChildProcess(const std::vector<std::string>& argv, const std::string& out_path, const std::string& err_path,
               const std::vector<std::string>& env = {});
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }

  void signal(int signal_number);

  // The exit code once the process ends within `timeout` (128 + n for death
  // by signal n); nullopt if it is still running.
  std::optional<int> wait(std::chrono::milliseconds timeout);

  // True while the process has not exited.
  bool running();

 private:
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
};

// A unique scratch directory under the system's temporary directory, in
// one root for the whole test program that is removed after the last test
// when all passed and kept, its path printed, when one failed.
std::string make_temp_dir();

// The contents of a file, or "" if it cannot be read.
std::string read_file(const std::string& path);

}  // namespace tumble::test
