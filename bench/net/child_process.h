// A program the benchmark starts and stops itself (nats-server, tumbled):
// its standard output and error go to a file, and it is ended with SIGTERM
// (SIGKILL when it has not exited within a few seconds) when the object
// goes. It gets SIGTERM too when the thread that started it ends (Linux's
// parent-death signal): start it from the main thread, so that an exit
// without stopping it (a failure) does not leave it running.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace tumble::bench {

class ChildProcess {
 public:
  // Starts argv[0] (a path) with `argv` at nice value `nice`, its output
  // appended to `log_path`. Check started(); a program that cannot be run
  // exits at once with 127.
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path, int nice = 0);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }
  // True while the process has not exited.
  bool running();
  // SIGTERM, then SIGKILL after `grace_ms`; waits for the exit.
  void stop(int grace_ms = 5000);

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
};

// The text of a file; "" when it cannot be read.
std::string read_text(const std::string& path);

// A fresh directory under the system's temporary one, named after `prefix`.
std::string make_temp_dir(const std::string& prefix);

}  // namespace tumble::bench
