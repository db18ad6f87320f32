// The sim layer's logger ("sim"), created on first use and writing to
// stderr. Thread-safe.
#pragma once

#include <spdlog/logger.h>

namespace tumble::sim {

spdlog::logger& sim_log();

}  // namespace tumble::sim
