// The state file of tumbled --state: one WorldState written so that a
// crash at any moment leaves either the previous file or the new one, never
// a torn mix (written to a temporary file in the same directory, flushed to
// disk, then renamed over the old one), and checked on reading so that a
// damaged file is refused, never loaded as a different world.
//
// Layout of version 2, integers little-endian:
//   16 bytes  the magic "tumble-state-v2\n"
//    8 bytes  L, the payload's length in bytes (at most 1 GiB)
//    L bytes  the payload: the WorldState in protobuf's binary encoding
//    4 bytes  the payload's CRC32C, masked (sim/crc32c.h)
// The file is exactly 28 + L bytes. Version 1 (the magic
// "tumble-state-v1\n", then the payload, with no length and no checksum)
// is still read; it is always written as version 2.
//
// Writing keeps the file it replaces as <path>.prev (see
// sim/state_resume.h for how a start uses it).
//
// Thread: any; the functions share no state.
#pragma once

#include <string>
#include <string_view>

#include "sim/status.h"
#include "tumble/v1/state.pb.h"

namespace tumble::sim {

// The framing a state file was read in.
enum class StateFileFormat {
  v1,  // no length, no checksum: damage can go unnoticed
  v2,  // length and CRC32C checked
};

// The file suffix of the previous good state file.
inline constexpr std::string_view kPreviousSuffix = ".prev";

// The bytes of a version 2 state file holding `state`; false when the
// state cannot be encoded (over protobuf's 2 GiB).
bool encode_state_file(const tumble::v1::WorldState& state, std::string* bytes);

// Parses the bytes of a whole state file of either version. Refuses, with
// one sentence saying which check failed (no path in it), a file that is
// short, long, has no magic, a bad length, a bad checksum, or a payload that
// is not a WorldState of format 1.
Status parse_state_file(std::string_view bytes, tumble::v1::WorldState* state, StateFileFormat* format);

// Writes `state` to `path` atomically: to <path>.tmp, synced, then the
// current <path> (if any) renamed to <path>.prev and <path>.tmp to <path>.
// Errors name the path and the cause; on error <path> is left as it was.
Status write_state_file(const std::string& path, const tumble::v1::WorldState& state);

// Reads a state file. A missing file is not an error: *exists is set false
// and the caller starts from its scene. Anything unreadable is an error
// whose message starts with the path. `format`, when given, is set to the
// framing the file was read in.
Status read_state_file(const std::string& path, tumble::v1::WorldState* state, bool* exists,
                       StateFileFormat* format = nullptr);

}  // namespace tumble::sim
