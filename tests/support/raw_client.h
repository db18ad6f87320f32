// A plain TCP client for protocol tests: sends exact bytes, reads whole
// frames with a deadline, and tells whether the server closed the
// connection. Uses POSIX sockets so the tests share no code with the
// server's or the client library's networking.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::test {

class RawClient {
 public:
  // Connects to 127.0.0.1:port; check connected().
  explicit RawClient(std::uint16_t port);
  ~RawClient();
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;

  bool connected() const { return fd_ >= 0; }

  // Writes all of `bytes`; false if the connection is gone.
  bool send_bytes(const std::string& bytes);
  bool send(const tumble::v1::ClientMessage& message) { return send_bytes(wire::encode_frame(message)); }

  // Sends Hello and returns the server's reply (Welcome on success).
  std::optional<tumble::v1::ServerMessage> handshake(const std::string& name = "raw-test");

  // The next whole message, or nullopt on timeout, close or a bad frame.
  std::optional<tumble::v1::ServerMessage> read(std::chrono::milliseconds timeout = std::chrono::seconds(10));

  // Reads messages until one satisfies `wanted` (skipping others, such as
  // pose frames), or nullopt on timeout or close.
  template <class Predicate>
  std::optional<tumble::v1::ServerMessage> read_until(Predicate wanted,
                                                      std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      auto message = read(left);
      if (!message) return std::nullopt;
      if (wanted(*message)) return message;
    }
  }

  // True when the server closes the connection within `timeout`; messages
  // that arrive first are skipped.
  bool closed_by_server(std::chrono::milliseconds timeout = std::chrono::seconds(10));

  // True once the peer's end-of-stream has been read.
  bool saw_eof() const { return eof_; }

 private:
  // Reads what is available within `timeout` into the reader; false on close or timeout.
  bool fill(std::chrono::milliseconds timeout);

  int fd_ = -1;
  bool eof_ = false;
  wire::FrameReader reader_{std::size_t{64} << 20};
};

}  // namespace tumble::test
