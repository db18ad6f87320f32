#include "net/outbound_queue.h"

#include <algorithm>

namespace tumble::net {

void OutboundQueue::push_message(std::string bytes) {
  message_bytes_ += bytes.size();
  messages_.push_back(std::move(bytes));
}

void OutboundQueue::offer_frame(std::uint32_t stream, std::shared_ptr<const std::string> bytes) {
  for (FrameSlot& slot : frames_) {
    if (slot.stream == stream) {
      slot.bytes = std::move(bytes);
      ++frames_replaced_;
      return;
    }
  }
  frames_.push_back({stream, std::move(bytes)});
}

void OutboundQueue::drop_stream(std::uint32_t stream) {
  std::erase_if(frames_, [stream](const FrameSlot& slot) { return slot.stream == stream; });
}

void OutboundQueue::take_batch(Batch& batch) {
  batch.messages.clear();
  batch.frames.clear();
  batch.pieces.clear();
  batch.bytes = 0;
  batch.messages.swap(messages_);
  message_bytes_ = 0;
  for (FrameSlot& slot : frames_) batch.frames.push_back(std::move(slot.bytes));
  frames_.clear();
  for (const std::string& message : batch.messages) batch.pieces.emplace_back(message);
  for (const auto& frame : batch.frames) batch.pieces.emplace_back(*frame);
  for (std::string_view piece : batch.pieces) batch.bytes += piece.size();
}

}  // namespace tumble::net
