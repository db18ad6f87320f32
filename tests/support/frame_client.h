// What the protocol tests' clients share, whatever carries their bytes (a
// TCP socket in RawClient, WebSocket messages in WsClient): the server's
// byte stream cut into whole ServerMessages, read with a deadline.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>

#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::test {

class FrameClient {
 public:
  using Clock = std::chrono::steady_clock;

  virtual ~FrameClient() = default;

  // Sends exact bytes; false when the connection is gone.
  virtual bool send_bytes(const std::string& bytes) = 0;
  bool send(const tumble::v1::ClientMessage& message) { return send_bytes(wire::encode_frame(message)); }

  // The next whole message, or nullopt on timeout, close or a bad frame.
  std::optional<tumble::v1::ServerMessage> read(std::chrono::milliseconds timeout = std::chrono::seconds(10));

  // Reads messages until one satisfies `wanted` (skipping others, such as
  // pose frames), or nullopt on timeout or close.
  template <class Predicate>
  std::optional<tumble::v1::ServerMessage> read_until(Predicate wanted,
                                                      std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    const Clock::time_point deadline = Clock::now() + timeout;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      if (left.count() <= 0) return std::nullopt;
      auto message = read(left);
      if (!message) return std::nullopt;
      if (wanted(*message)) return message;
    }
  }

 protected:
  // Appends more of the server's bytes to reader_, waiting at most until
  // `deadline`; false on timeout or when the connection is over.
  virtual bool fill(Clock::time_point deadline) = 0;

  wire::FrameReader reader_{std::size_t{64} << 20};
};

}  // namespace tumble::test
