// Naming a body or a joint the way a person types it.
#pragma once

#include <string_view>

#include "tumble/v1/protocol.pb.h"
#include "tumble_client/result.h"

namespace tumble::client {

// Parses a body reference: text made only of decimal digits is a body id
// (BodyRef.id, at most 4294967295), anything else a body name (BodyRef.name)
// taken verbatim. Fails with kind invalid_argument on empty text or an id
// out of range.
Result<tumble::v1::BodyRef> parse_body_ref(std::string_view text);

// Parses a joint reference by the same rule: digits are a JointRef.id,
// anything else a JointRef.name.
Result<tumble::v1::JointRef> parse_joint_ref(std::string_view text);

}  // namespace tumble::client
