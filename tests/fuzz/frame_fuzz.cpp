// Fuzz target: bytes as a client sends them, through the server's path for
// one connection. The bytes are fed to a FrameReader in chunks whose size
// the first byte chooses (so prefixes split across reads are exercised),
// each frame is parsed as a ClientMessage as Session::handle_frame does,
// and every message that parses goes through check_request, then is encoded
// again and must come back as exactly one frame.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "quiet_logs.h"
#include "sim/request_check.h"
#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace {

// Small enough that libFuzzer's inputs reach the too_large refusal.
constexpr std::size_t kMaxFrameBytes = 1024;

// Re-encoding a parsed message yields one frame the reader gives back whole.
void check_round_trip(const tumble::v1::ClientMessage& message) {
  tumble::wire::FrameReader reader(std::size_t{1} << 30);
  const std::string frame = tumble::wire::encode_frame(message);
  reader.append(frame.data(), frame.size());
  std::string_view body;
  if (reader.next(body) != tumble::wire::FrameStatus::frame || reader.buffered_bytes() != 0) std::abort();
  tumble::v1::ClientMessage again;
  if (!again.ParseFromArray(body.data(), static_cast<int>(body.size()))) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) { return tumble::fuzz::silence_logs(); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = std::size_t{data[0]} + 1;
  const char* bytes = reinterpret_cast<const char*>(data + 1);
  std::size_t left = size - 1;

  tumble::wire::FrameReader reader(kMaxFrameBytes);
  while (left > 0) {
    const std::size_t n = left < chunk ? left : chunk;
    reader.append(bytes, n);
    bytes += n;
    left -= n;
    std::string_view body;
    for (;;) {
      const tumble::wire::FrameStatus status = reader.next(body);
      if (status == tumble::wire::FrameStatus::need_more) break;
      // The server closes the connection on a refused prefix.
      if (status != tumble::wire::FrameStatus::frame) return 0;
      if (body.size() > kMaxFrameBytes) std::abort();
      tumble::v1::ClientMessage message;
      if (!message.ParseFromArray(body.data(), static_cast<int>(body.size()))) continue;
      (void)tumble::sim::check_request(message);
      check_round_trip(message);
    }
  }
  return 0;
}
