// A plain TCP client for protocol tests: sends exact bytes, reads whole
// frames with a deadline, and tells whether the server closed the
// connection. Uses POSIX sockets so the tests share no code with the
// server's or the client library's networking.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "frame_client.h"
#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::test {

class RawClient : public FrameClient {
 public:
  // Connects to 127.0.0.1:port; check connected().
  explicit RawClient(std::uint16_t port);
  ~RawClient();
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;

  bool connected() const { return fd_ >= 0; }

  // Writes all of `bytes`; false if the connection is gone.
  bool send_bytes(const std::string& bytes) override;
  using FrameClient::send;

  // Sends Hello and returns the server's reply (Welcome on success).
  std::optional<tumble::v1::ServerMessage> handshake(const std::string& name = "raw-test");

  // True when the server closes the connection within `timeout`; messages
  // that arrive first are skipped.
  bool closed_by_server(std::chrono::milliseconds timeout = std::chrono::seconds(10));

  // True once the peer's end-of-stream has been read.
  bool saw_eof() const { return eof_; }

 private:
  // Reads what is available before `deadline` into the reader; false on close or timeout.
  bool fill(Clock::time_point deadline) override;

  int fd_ = -1;
  bool eof_ = false;
};

}  // namespace tumble::test
