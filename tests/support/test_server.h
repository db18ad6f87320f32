// A tumbled inside the test process: a Simulation and a Server on an
// ephemeral port of 127.0.0.1, with the I/O on a thread of its own.
#pragma once

#include <memory>
#include <string>
#include <thread>

#include "net/asio.h"
#include "net/server.h"
#include "sim/simulation.h"

namespace tumble::test {

// A server config that serves HTTP and WebSocket beside TCP, with `limits`.
inline net::ServerConfig with_http(net::SessionLimits limits = {}) {
  net::ServerConfig config;
  config.serve_http = true;
  config.limits = limits;
  return config;
}

class TestServer {
 public:
  // Loads `scene_json` and starts stepping at `tick_rate_hz`.
  explicit TestServer(const std::string& scene_json, double tick_rate_hz = 240,
                      net::SessionLimits limits = net::SessionLimits{});
  // The same with a whole server configuration; its ports are replaced by
  // ephemeral ones of 127.0.0.1 (the HTTP one only with serve_http).
  TestServer(const std::string& scene_json, double tick_rate_hz, net::ServerConfig config);
  ~TestServer();

  std::uint16_t port() const { return port_; }
  // The HTTP endpoint's port; 0 unless the configuration has serve_http.
  std::uint16_t http_port() const { return http_port_; }
  sim::Simulation& sim() { return *sim_; }

  // Runs `task` on the I/O thread and waits for it.
  void run_on_io(const std::function<void()>& task);

 private:
  boost::asio::io_context io_;
  std::unique_ptr<sim::Simulation> sim_;
  std::unique_ptr<net::Server> server_;
  std::thread io_thread_;
  std::uint16_t port_ = 0;
  std::uint16_t http_port_ = 0;
};

}  // namespace tumble::test
