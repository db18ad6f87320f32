// The five clock requests, built as the clock tests send them: one
// ClientMessage each, with its request_id. Header only, so that the sim's
// tests (which link no test support) share it with the protocol's.
#pragma once

#include <cstdint>
#include <ostream>

#include "tumble/v1/protocol.pb.h"

namespace tumble::test {

enum class ClockRequest { pause, resume, step, reset, set_tick_rate };

inline const char* name_of(ClockRequest kind) {
  switch (kind) {
    case ClockRequest::pause:
      return "Pause";
    case ClockRequest::resume:
      return "Resume";
    case ClockRequest::step:
      return "Step";
    case ClockRequest::reset:
      return "Reset";
    case ClockRequest::set_tick_rate:
      return "SetTickRate";
  }
  return "?";
}

// For gtest's names of parameters.
inline void PrintTo(ClockRequest kind, std::ostream* os) { *os << name_of(kind); }

// `step_ticks` is the Step's count and ignored by the others; SetTickRate
// asks for 120 Hz.
inline tumble::v1::ClientMessage clock_request(ClockRequest kind, std::uint64_t id, std::uint32_t step_ticks) {
  tumble::v1::ClientMessage m;
  m.set_request_id(id);
  switch (kind) {
    case ClockRequest::pause:
      m.mutable_pause();
      break;
    case ClockRequest::resume:
      m.mutable_resume();
      break;
    case ClockRequest::step:
      m.mutable_step()->set_ticks(step_ticks);
      break;
    case ClockRequest::reset:
      m.mutable_reset();
      break;
    case ClockRequest::set_tick_rate:
      m.mutable_set_tick_rate()->set_rate_hz(120);
      break;
  }
  return m;
}

}  // namespace tumble::test
