#include "sim/string_limits.h"

#include <string>

#include "sim/log_text.h"

namespace tumble::sim {

Status check_text_length(std::string_view text, std::string_view field, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return {};
  return Status::error(std::string(field) + ": " + std::to_string(text.size()) + " bytes, over the limit of " +
                       std::to_string(max_bytes) + " bytes");
}

namespace {

// A name of at most max_bytes that is not digits only; `what` is "body" or "joint".
Status check_name(std::string_view name, std::string_view field, std::size_t max_bytes, std::string_view what) {
  if (Status status = check_text_length(name, field, max_bytes); !status.ok()) return status;
  const bool digits_only = !name.empty() && name.find_first_not_of("0123456789") == std::string_view::npos;
  if (digits_only) {
    return Status::error(std::string(field) + ": '" + log_text(name) + "' is digits only, which clients read as a " +
                         std::string(what) + " id; a name needs another character");
  }
  return {};
}

}  // namespace

Status check_body_name(std::string_view name, std::string_view field) {
  return check_name(name, field, kMaxBodyNameBytes, "body");
}

Status check_joint_name(std::string_view name, std::string_view field) {
  return check_name(name, field, kMaxJointNameBytes, "joint");
}

}  // namespace tumble::sim
