// Three nats-server processes on 127.0.0.1 routed into one cluster, for
// the NATS benchmarks. Each node listens for clients on a free port and for
// its peers on another, with routes to the other two (a configuration file
// per node: listen, cluster { name, listen, routes }, and with JetStream a
// store directory of its own); everything else is nats-server's default
// unless NatsClusterOptions says otherwise (max_payload 1 MiB, a client's
// outbound buffer max_pending 64 MiB, write_deadline 10 s: past either a
// client is closed as a slow consumer). The nodes stop when the object goes.
#pragma once

#include <sys/types.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "child_process.h"

namespace tumble::bench {

struct NatsClusterOptions {
  int nice = 0;                  // the nodes' nice value
  bool jetstream = false;        // each node runs JetStream, its store under the cluster's directory
  std::int64_t max_payload = 0;  // bytes a message may carry; 0: nats-server's default (1 MiB)
};

class NatsCluster {
 public:
  static constexpr std::size_t kNodes = 3;

  // Writes the nodes' configuration files under `dir`; nothing runs yet.
  NatsCluster(std::string nats_server_path, std::string dir, NatsClusterOptions options = {});

  // Starts the three nodes and waits until each is ready and routed to both
  // others (with JetStream, until the metadata leader is known to each); a
  // start that has not got there in half the timeout is made once more.
  // Empty on success, else why not (with the failing node's log).
  std::string start(std::chrono::seconds timeout);

  // nats://127.0.0.1:PORT of node i.
  std::string url(std::size_t i) const;
  // The three URLs, comma-separated, node 0 first.
  std::string urls() const;
  pid_t pid(std::size_t i) const { return nodes_[i] ? nodes_[i]->pid() : 0; }

 private:
  std::string start_once(std::chrono::seconds timeout);

  std::string path_;
  std::string dir_;
  NatsClusterOptions options_;
  std::array<std::uint16_t, kNodes> client_ports_{};
  std::array<std::uint16_t, kNodes> cluster_ports_{};
  std::array<std::unique_ptr<ChildProcess>, kNodes> nodes_;
};

}  // namespace tumble::bench
