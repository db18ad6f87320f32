#include "test_server.h"

#include <algorithm>
#include <future>
#include <stdexcept>

#include "sim/scene_file.h"

namespace tumble::test {

namespace {

net::ServerConfig config_with(net::SessionLimits limits) {
  net::ServerConfig config;
  config.limits = limits;
  return config;
}

}  // namespace

TestServer::TestServer(const std::string& scene_json, double tick_rate_hz, net::SessionLimits limits)
    : TestServer(scene_json, tick_rate_hz, config_with(limits)) {}

TestServer::TestServer(const std::string& scene_json, double tick_rate_hz, net::ServerConfig config) {
  tumble::v1::Scene scene;
  if (auto status = sim::parse_scene_json(scene_json, &scene); !status.ok()) {
    throw std::runtime_error("test scene: " + status.message());
  }
  sim::SimConfig sim_config;
  sim_config.tick_rate_hz = tick_rate_hz;
  // As tumbled sizes ListBodies pages (server/startup.cpp).
  sim_config.list_page_bytes = std::min(sim_config.list_page_bytes, config.limits.max_pending_bytes / 2);
  if (auto status = sim::Simulation::create(scene, sim_config, &sim_); !status.ok()) {
    throw std::runtime_error("test scene: " + status.message());
  }
  config.host = "127.0.0.1";
  config.port = 0;
  config.http_host = "127.0.0.1";
  config.http_port = 0;
  config.server_version = "test";
  server_ = std::make_unique<net::Server>(io_, *sim_, config);
  if (auto status = server_->start(); !status.ok()) throw std::runtime_error(status.message());
  port_ = server_->port();
  http_port_ = server_->http_port();
  sim_->start();
  io_thread_ = std::thread([this] {
    auto guard = boost::asio::make_work_guard(io_);
    io_.run();
  });
}

TestServer::~TestServer() {
  run_on_io([this] { server_->stop(); });
  io_.stop();
  io_thread_.join();
  sim_->stop();
}

void TestServer::run_on_io(const std::function<void()>& task) {
  std::promise<void> done;
  boost::asio::post(io_, [&] {
    task();
    done.set_value();
  });
  done.get_future().wait();
}

}  // namespace tumble::test
