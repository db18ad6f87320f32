// The net layer's logger ("net"), created on first use and writing to
// stderr. Thread-safe.
#pragma once

#include <spdlog/logger.h>

namespace tumble::net {

spdlog::logger& net_log();

}  // namespace tumble::net
