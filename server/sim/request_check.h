// Checks a client request for what can be judged without the world:
// required fields present, numbers finite and within limits, durations
// positive. Runs on the I/O thread before a request reaches the sim; whether
// the named body exists is decided by the sim when it applies the request.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "tumble/v1/protocol.pb.h"

namespace tumble::sim {

// The tick rates a server may run at (--tick-rate, SetTickRate), in Hz.
inline constexpr double kMinTickRateHz = 1;
inline constexpr double kMaxTickRateHz = 10000;

// The most ticks one Step may ask for.
inline constexpr std::uint32_t kMaxStepTicks = 1000000;

// Why a request was refused.
struct RequestError {
  tumble::v1::ErrorCode code = tumble::v1::INVALID_ARGUMENT;
  std::string message;
};

// nullopt when a Hello's strings are within the limits of string_limits.h;
// else UNAUTHENTICATED for a token, INVALID_ARGUMENT for a client_name.
std::optional<RequestError> check_hello(const tumble::v1::Hello& hello);

// nullopt when `message` may be applied.
std::optional<RequestError> check_request(const tumble::v1::ClientMessage& message);

}  // namespace tumble::sim
