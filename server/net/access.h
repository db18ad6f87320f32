// Who may do what: the tokens a server accepts, the role each one grants,
// and what each role may ask for.
//
// A controller may send every request. An observer may only read: the
// requests in observer_may()'s allowlist; anything else, including every
// request added to the protocol later, is denied until it is listed there.
//
// Thread: pure functions and plain values; safe from any thread.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "tumble/v1/protocol.pb.h"

namespace tumble::net {

// The tokens a server accepts. An empty string means that token is not set.
// With neither set, every client is a controller and no token is checked.
struct AccessTokens {
  std::string controller;  // grants ROLE_CONTROLLER
  std::string observer;    // grants ROLE_OBSERVER

  bool required() const { return !controller.empty() || !observer.empty(); }
};

// The role a Hello carrying `token` gets, or nullopt when the server
// requires a token and `token` is none of its tokens. The comparison takes
// a time that depends only on the length of `token`, not on how much of it
// matches.
std::optional<tumble::v1::Role> authenticate(const AccessTokens& tokens, std::string_view token);

// True for the requests an observer may send: Hello (answered as a repeat),
// ListBodies, ListJoints, Subscribe, Unsubscribe, KeyFrameRequest, GetStats, and an envelope with no
// request at all (answered UNKNOWN_MESSAGE). False for everything else.
bool observer_may(tumble::v1::ClientMessage::KindCase kind);

// True when a connection of `role` may send a request of `kind`.
bool role_may(tumble::v1::Role role, tumble::v1::ClientMessage::KindCase kind);

// The sentence of the PERMISSION_DENIED error for a request of `kind` an
// observer may not send, naming the request.
std::string observer_denial(tumble::v1::ClientMessage::KindCase kind);

}  // namespace tumble::net
