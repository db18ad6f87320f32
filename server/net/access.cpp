#include "net/access.h"

namespace tumble::net {
namespace {

using tumble::v1::ClientMessage;

// True when `given` equals `expected` (which is not empty), in a time that
// depends only on given.size(): every byte of `given` is compared with a
// byte of `expected` (cycling through it), with no early exit, and the
// lengths are folded into the same difference.
bool constant_time_equal(std::string_view expected, std::string_view given) {
  std::size_t difference = expected.size() ^ given.size();
  for (std::size_t i = 0; i < given.size(); ++i) {
    const auto expected_byte = static_cast<unsigned char>(expected[i % expected.size()]);
    difference |= static_cast<std::size_t>(expected_byte ^ static_cast<unsigned char>(given[i]));
  }
  return difference == 0;
}

// Whether `token` is `expected`, for a token that may not be set.
bool matches(const std::string& expected, std::string_view token) {
  return !expected.empty() && constant_time_equal(expected, token);
}

}  // namespace

std::optional<tumble::v1::Role> authenticate(const AccessTokens& tokens, std::string_view token) {
  if (!tokens.required()) return tumble::v1::ROLE_CONTROLLER;
  // Both comparisons run whichever matches, so the time does not tell which token is close.
  const bool controller = matches(tokens.controller, token);
  const bool observer = matches(tokens.observer, token);
  if (controller) return tumble::v1::ROLE_CONTROLLER;
  if (observer) return tumble::v1::ROLE_OBSERVER;
  return std::nullopt;
}

bool observer_may(ClientMessage::KindCase kind) {
  switch (kind) {
    case ClientMessage::kHello:
    case ClientMessage::kListBodies:
    case ClientMessage::kListJoints:
    case ClientMessage::kSubscribe:
    case ClientMessage::kUnsubscribe:
    case ClientMessage::kKeyFrameRequest:
    case ClientMessage::kGetStats:
    case ClientMessage::KIND_NOT_SET:
      return true;
    default:
      return false;
  }
}

bool role_may(tumble::v1::Role role, ClientMessage::KindCase kind) {
  switch (role) {
    case tumble::v1::ROLE_CONTROLLER:
      return true;
    case tumble::v1::ROLE_OBSERVER:
      return observer_may(kind);
    default:
      return false;
  }
}

std::string observer_denial(ClientMessage::KindCase kind) {
  // A oneof case's value is its field number, which names the request.
  const auto* field = ClientMessage::descriptor()->FindFieldByNumber(static_cast<int>(kind));
  const std::string name =
      field != nullptr && field->message_type() != nullptr ? field->message_type()->name() : "this request";
  return name +
         " needs the controller token; an observer may only list bodies and joints, subscribe, "
         "unsubscribe and read stats";
}

}  // namespace tumble::net
