#include "net/log.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace tumble::net {

spdlog::logger& net_log() {
  static const std::shared_ptr<spdlog::logger> logger = [] {
    auto existing = spdlog::get("net");
    return existing ? existing : spdlog::stderr_color_mt("net");
  }();
  return *logger;
}

}  // namespace tumble::net
