// Failure: why a client call did not succeed, as a value.
#pragma once

#include <string>

#include "tumble/v1/protocol.pb.h"

namespace tumble::client {

// What kind of thing went wrong. Callers that only report the failure need
// no more than the message; the kind lets a caller retry a timeout or tell
// its own mistakes from the server's.
enum class FailureKind {
  invalid_argument,  // the caller's input cannot be used (a bad "host:port", an empty body name)
  connect,           // the server could not be resolved or reached
  timeout,           // the deadline passed; see the call for whether the connection is still usable
  closed,            // the server closed the connection or it broke
  protocol,          // the server sent something this client cannot accept; the connection is unusable
  server,            // the server answered with an Error; `code` says which
};

// One failure: its kind and one sentence for a person, without a trailing
// period, e.g. "cannot connect to 127.0.0.1:7400: Connection refused".
struct Failure {
  FailureKind kind = FailureKind::protocol;
  std::string message;
  // The server's code when kind is server; ERROR_CODE_UNSPECIFIED otherwise.
  tumble::v1::ErrorCode code = tumble::v1::ERROR_CODE_UNSPECIFIED;
};

// The failure an Error from the server stands for:
// "server error UNKNOWN_BODY: no body named 'foo'".
Failure server_failure(const tumble::v1::Error& error);

}  // namespace tumble::client
