#include "frame_client.h"

namespace tumble::test {

std::optional<tumble::v1::ServerMessage> FrameClient::read(std::chrono::milliseconds timeout) {
  const Clock::time_point deadline = Clock::now() + timeout;
  for (;;) {
    std::string_view body;
    const wire::FrameStatus status = reader_.next(body);
    if (status == wire::FrameStatus::frame) {
      tumble::v1::ServerMessage message;
      if (!message.ParseFromArray(body.data(), static_cast<int>(body.size()))) return std::nullopt;
      return message;
    }
    if (status != wire::FrameStatus::need_more || Clock::now() >= deadline || !fill(deadline)) return std::nullopt;
  }
}

}  // namespace tumble::test
