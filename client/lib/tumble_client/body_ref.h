// Naming a body the way a person types it.
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

}  // namespace tumble::client
