// The state file of tumbled --state: one WorldState written so that a
// crash at any moment leaves either the previous file or the new one, never
// a torn mix (written to a temporary file in the same directory, flushed to
// disk, then renamed over the old one).
//
// Layout: the 16-byte magic "tumble-state-v1\n", then the WorldState in
// protobuf's binary encoding.
//
// Thread: any; the functions share no state.
#pragma once

#include <string>

#include "sim/status.h"
#include "tumble/v1/state.pb.h"

namespace tumble::sim {

// Writes `state` to `path` atomically. Errors name the path and the cause.
Status write_state_file(const std::string& path, const tumble::v1::WorldState& state);

// Reads a state file. A missing file is not an error: *exists is set false
// and the caller starts from its scene. Anything unreadable is an error.
Status read_state_file(const std::string& path, tumble::v1::WorldState* state, bool* exists);

}  // namespace tumble::sim
