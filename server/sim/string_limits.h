// The longest text a client or a file may give tumbled, in one place: body
// and joint names (SpawnBody, AddJoint, BodyRef, JointRef, scene and state
// files, journals), a Hello's
// client_name and token, and the server's own tokens. Lengths are in bytes
// of UTF-8, as they travel. A body name may not be digits only: clients
// read such text as a body id; likewise a joint name. Thread: any; pure functions.
#pragma once

#include <cstddef>
#include <string_view>

#include "sim/status.h"

namespace tumble::sim {

inline constexpr std::size_t kMaxBodyNameBytes = 128;    // BodySpec.name, BodyRef.name
inline constexpr std::size_t kMaxJointNameBytes = 128;   // JointSpec.name, JointRef.name
inline constexpr std::size_t kMaxClientNameBytes = 128;  // Hello.client_name
inline constexpr std::size_t kMaxTokenBytes = 256;       // Hello.token, --token, --observer-token

// Ok when `text` is at most `max_bytes` long; else "FIELD: N bytes, over the
// limit of MAX bytes", with `field` naming where the text came from.
Status check_text_length(std::string_view text, std::string_view field, std::size_t max_bytes);

// Ok for a name a new body may have: empty, or at most kMaxBodyNameBytes and
// not made only of the digits 0 to 9. Errors name `field`.
Status check_body_name(std::string_view name, std::string_view field);

// Ok for a name a new joint may have, by the rules of check_body_name with
// kMaxJointNameBytes.
Status check_joint_name(std::string_view name, std::string_view field);

}  // namespace tumble::sim
