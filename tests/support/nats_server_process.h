// Real nats-server processes for the tests of tumbled over NATS: one node
// on a free port of 127.0.0.1, optionally with a configuration file (users
// and permissions), or three nodes routed into one cluster. A node can be
// SIGKILLed and started again on the same ports. Readiness is the server's
// own "Server is ready" log line, waited for with a deadline.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "process.h"
#include "tumble/loopback_ports.h"

namespace tumble::test {

// A free TCP port of 127.0.0.1 at the time of the call (bound to port 0,
// read back and released); free_loopback_ports (tumble/loopback_ports.h)
// for several, all different.
std::uint16_t free_loopback_port();
using tumble::free_loopback_ports;

// A node's configuration: the text of its configuration file, and what
// nats-server's environment has for the file's $VARIABLE references
// ("NAME=VALUE" each; docker/nats/auth.conf reads its passwords so).
struct NatsConfig {
  // Implicit: a string, or a literal, is a configuration without variables.
  NatsConfig(std::string file_text = "", std::vector<std::string> variables = {})
      : text(std::move(file_text)), env(std::move(variables)) {}
  NatsConfig(const char* file_text) : NatsConfig(std::string(file_text)) {}
  std::string text;
  std::vector<std::string> env;
};

class NatsServerProcess {
 public:
  // Prepares a node on 127.0.0.1:`port` (0: a free port) with `config` (may
  // be empty) that joins the cluster listening on `cluster_port` with routes
  // to `routes` (0 and empty: no cluster). Nothing runs before start().
  explicit NatsServerProcess(NatsConfig config = {}, std::uint16_t port = 0, std::uint16_t cluster_port = 0,
                             std::vector<std::uint16_t> routes = {});
  ~NatsServerProcess();
  NatsServerProcess(const NatsServerProcess&) = delete;
  NatsServerProcess& operator=(const NatsServerProcess&) = delete;

  // Starts the node (again, after kill()) and waits until it is ready;
  // false when it exited or did not get ready within `timeout`.
  bool start(std::chrono::milliseconds timeout = std::chrono::seconds(30));
  // From the next start() on, JetStream too: its store in this node's
  // directory (kept across kill() and start()), the server named by its port.
  void enable_jetstream() { jetstream_ = true; }
  // SIGKILL, and waits for the process to end.
  void kill();
  bool running() const { return process_ && process_->running(); }

  std::uint16_t port() const { return port_; }
  std::uint16_t cluster_port() const { return cluster_port_; }
  // nats://127.0.0.1:PORT
  std::string url() const;
  // The log of the current (or last) run, then what the process printed
  // (a configuration it refused is said there, before any log).
  std::string log() const { return read_file(log_path_) + read_file(out_path_); }
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  std::string config_path_;
  std::vector<std::string> env_;
  std::string log_path_;
  std::string out_path_;
  std::uint16_t port_;
  std::uint16_t cluster_port_;
  std::vector<std::uint16_t> routes_;
  int runs_ = 0;
  bool jetstream_ = false;
  std::unique_ptr<ChildProcess> process_;
};

// Three nodes routed to one another on 127.0.0.1, each with `config`.
class NatsCluster {
 public:
  // With `jetstream`, every node runs JetStream: a JetStream cluster of three.
  explicit NatsCluster(const NatsConfig& config = {}, bool jetstream = false);
  // Starts every node and waits until each is ready and sees both others as
  // routes (and, with JetStream, knows the cluster's metadata leader); false
  // otherwise.
  bool start(std::chrono::milliseconds timeout = std::chrono::seconds(30));
  NatsServerProcess& node(std::size_t i) { return *nodes_[i]; }
  // The three URLs, comma-separated, node 0 first.
  std::string urls() const;

 private:
  std::vector<std::unique_ptr<NatsServerProcess>> nodes_;
  bool jetstream_ = false;
};

// Where nats-server is, or "" when it is not installed.
std::string nats_server_path();

}  // namespace tumble::test
