// The real tumbled, started on an ephemeral port of 127.0.0.1 with a scene,
// for end-to-end tests; and the real tumble CLI pointed at it.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "process.h"
#include "test_paths.h"

namespace tumble::test {

class TumbledProcess {
 public:
  // Writes `scene_json` to a file and starts tumbled on it with `extra_args`,
  // listening on 127.0.0.1:`port` (0: a free port; another, e.g. the port of
  // an earlier run, to restart a server where its clients expect it).
  // Check started(); the log is in log().
  explicit TumbledProcess(const std::string& scene_json, const std::vector<std::string>& extra_args = {},
                          std::uint16_t port = 0);

  bool started() const { return port_ != 0; }
  std::uint16_t port() const { return port_; }
  std::string server() const { return "127.0.0.1:" + std::to_string(port_); }
  ChildProcess& process() { return *process_; }
  const std::string& dir() const { return dir_; }
  std::string log() const { return read_file(log_path_); }

  // Runs the tumble CLI against this server: tumble --server HOST:PORT args...
  CommandResult cli(const std::vector<std::string>& args,
                    std::chrono::milliseconds timeout = std::chrono::seconds(30)) const;

 private:
  std::string dir_;
  std::string log_path_;
  std::unique_ptr<ChildProcess> process_;
  std::uint16_t port_ = 0;
};

}  // namespace tumble::test
