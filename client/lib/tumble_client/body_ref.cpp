#include "tumble_client/body_ref.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

namespace tumble::client {

Result<tumble::v1::BodyRef> parse_body_ref(std::string_view text) {
  if (text.empty()) return Failure{FailureKind::invalid_argument, "a body name or id cannot be empty"};
  tumble::v1::BodyRef ref;
  const bool numeric = std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (!numeric) {
    ref.set_name(std::string(text));
    return ref;
  }
  constexpr std::uint64_t kMaxId = std::numeric_limits<std::uint32_t>::max();
  std::uint64_t id = 0;
  for (char c : text) {
    id = id * 10 + static_cast<std::uint64_t>(c - '0');
    if (id > kMaxId) {
      return Failure{FailureKind::invalid_argument,
                     "body id " + std::string(text) + " is out of range (at most " + std::to_string(kMaxId) + ")"};
    }
  }
  ref.set_id(static_cast<std::uint32_t>(id));
  return ref;
}

}  // namespace tumble::client
