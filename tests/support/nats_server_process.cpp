#include "nats_server_process.h"

#include <signal.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <thread>

namespace tumble::test {

std::uint16_t free_loopback_port() { return free_loopback_ports(1)[0]; }

std::string nats_server_path() {
  for (const char* path : {"/usr/sbin/nats-server", "/usr/bin/nats-server", "/usr/local/bin/nats-server"}) {
    if (::access(path, X_OK) == 0) return path;
  }
  return "";
}

NatsServerProcess::NatsServerProcess(NatsConfig config, std::uint16_t port, std::uint16_t cluster_port,
                                     std::vector<std::uint16_t> routes)
    : dir_(make_temp_dir()),
      config_path_(dir_ + "/nats.conf"),
      env_(std::move(config.env)),
      port_(port != 0 ? port : free_loopback_port()),
      cluster_port_(cluster_port),
      routes_(std::move(routes)) {
  std::ofstream(config_path_) << config.text << "\n";
}

NatsServerProcess::~NatsServerProcess() { kill(); }

std::string NatsServerProcess::url() const { return "nats://127.0.0.1:" + std::to_string(port_); }

bool NatsServerProcess::start(std::chrono::milliseconds timeout) {
  kill();
  // A log of its own for each run: "Server is ready" is then this run's.
  log_path_ = dir_ + "/nats-" + std::to_string(++runs_) + ".log";
  out_path_ = dir_ + "/nats-" + std::to_string(runs_) + ".out";
  std::vector<std::string> argv = {nats_server_path(),    "-c", config_path_, "-a", "127.0.0.1", "-p",
                                   std::to_string(port_), "-l", log_path_};
  if (jetstream_) {
    argv.insert(argv.end(), {"-js", "-sd", dir_ + "/jetstream", "-n", "node-" + std::to_string(port_)});
  }
  if (cluster_port_ != 0) {
    argv.insert(argv.end(),
                {"--cluster_name", "tumble-test", "--cluster", "nats://127.0.0.1:" + std::to_string(cluster_port_)});
    std::string routes;
    for (const std::uint16_t route : routes_) {
      if (!routes.empty()) routes += ",";
      routes += "nats-route://127.0.0.1:" + std::to_string(route);
    }
    if (!routes.empty()) argv.insert(argv.end(), {"--routes", routes});
  }
  process_ = std::make_unique<ChildProcess>(argv, out_path_, env_);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline && process_->running()) {
    if (log().find("Server is ready") != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return log().find("Server is ready") != std::string::npos && process_->running();
}

void NatsServerProcess::kill() {
  if (!process_) return;
  process_->signal(SIGKILL);
  process_->wait(std::chrono::seconds(10));
  process_.reset();
}

NatsCluster::NatsCluster(const NatsConfig& config, bool jetstream) : jetstream_(jetstream) {
  // Client ports 0-2 and cluster ports 3-5, all different.
  const std::vector<std::uint16_t> ports = free_loopback_ports(6);
  for (std::size_t i = 0; i < 3; ++i) {
    std::vector<std::uint16_t> routes;
    for (std::size_t j = 0; j < 3; ++j) {
      if (j != i) routes.push_back(ports[3 + j]);
    }
    nodes_.push_back(std::make_unique<NatsServerProcess>(config, ports[i], ports[3 + i], routes));
    if (jetstream) nodes_.back()->enable_jetstream();
  }
}

bool NatsCluster::start(std::chrono::milliseconds timeout) {
  for (auto& node : nodes_) {
    if (!node->start(timeout)) return false;
  }
  // A route is up on both ends when each logs it; wait for two a node.
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  const auto routed = [](const std::string& log) {
    std::size_t count = 0;
    for (std::size_t at = log.find("Route connection created"); at != std::string::npos;
         at = log.find("Route connection created", at + 1)) {
      ++count;
    }
    return count >= 2;
  };
  // A JetStream node logs the metadata leader once the three have elected one.
  const auto led = [this](const std::string& log) {
    return !jetstream_ || log.find("JetStream cluster new metadata leader") != std::string::npos ||
           log.find("Self is new JetStream cluster metadata leader") != std::string::npos;
  };
  for (auto& node : nodes_) {
    while (!routed(node->log()) || !led(node->log())) {
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  return true;
}

std::string NatsCluster::urls() const {
  std::string urls;
  for (const auto& node : nodes_) {
    if (!urls.empty()) urls += ",";
    urls += node->url();
  }
  return urls;
}

}  // namespace tumble::test
