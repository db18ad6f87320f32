// Resuming from the --state file at start, with the last good state as a
// fallback: when <path> is damaged (or cannot be resumed), the world comes
// from <path>.prev, the file the last save replaced, and the damaged file is
// renamed <path>.damaged (or .damaged.1, .2, ..., never over another file)
// so that the evidence is kept and the next save does not rotate it into
// <path>.prev. When both are unusable nothing is renamed and the error
// gives both reasons.
//
// Thread: tumbled's main thread, before the simulation starts.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim/status.h"
#include "tumble/v1/state.pb.h"

namespace tumble::sim {

// What resume_state found.
struct ResumedState {
  bool resumed = false;               // a state was accepted; false: no state file, start afresh
  std::string from;                   // the file it came from: <path> or <path>.prev
  std::uint64_t tick = 0;             // the tick it was saved at
  std::vector<std::string> warnings;  // for the log: a fallback, a version 1 file, the file renamed
};

// Takes a state read from a file (builds the world from it, say), or
// refuses it with the reason, which resume_state then treats as damage.
using AcceptState = std::function<Status(const tumble::v1::WorldState&)>;

// Reads <path>, else <path>.prev, and hands the first good one to `accept`.
// Neither file existing is not an error (out->resumed stays false). Errors
// name each file and what is wrong with it.
Status resume_state(const std::string& path, const AcceptState& accept, ResumedState* out);

}  // namespace tumble::sim
