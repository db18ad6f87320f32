// What every fuzz target does before its first input: silence protobuf's
// and spdlog's logging. Parse failures are expected by the thousand, and
// their log lines only slow the run.
#pragma once

#include <google/protobuf/stubs/logging.h>
#include <spdlog/spdlog.h>

namespace tumble::fuzz {

// Turns both loggers off for the rest of the process. Returns 0, what
// LLVMFuzzerInitialize returns, so a target's initializer is one line.
inline int silence_logs() {
  google::protobuf::SetLogHandler(nullptr);
  spdlog::set_level(spdlog::level::off);
  return 0;
}

}  // namespace tumble::fuzz
