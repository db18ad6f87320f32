#include "sim/log.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace tumble::sim {

spdlog::logger& sim_log() {
  static const std::shared_ptr<spdlog::logger> logger = [] {
    auto existing = spdlog::get("sim");
    return existing ? existing : spdlog::stderr_color_mt("sim");
  }();
  return *logger;
}

}  // namespace tumble::sim
