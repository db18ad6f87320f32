#include "tumble_client/body_ref.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

namespace tumble::client {

namespace {

// A BodyRef or JointRef from `text`; `what` is "body" or "joint".
template <typename Ref>
Result<Ref> parse_ref(std::string_view text, const std::string& what) {
  if (text.empty()) return Failure{FailureKind::invalid_argument, "a " + what + " name or id cannot be empty"};
  Ref ref;
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
                     what + " id " + std::string(text) + " is out of range (at most " + std::to_string(kMaxId) + ")"};
    }
  }
  ref.set_id(static_cast<std::uint32_t>(id));
  return ref;
}

}  // namespace

Result<tumble::v1::BodyRef> parse_body_ref(std::string_view text) {
  return parse_ref<tumble::v1::BodyRef>(text, "body");
}

Result<tumble::v1::JointRef> parse_joint_ref(std::string_view text) {
  return parse_ref<tumble::v1::JointRef>(text, "joint");
}

}  // namespace tumble::client
