#include "net/outbound_queue.h"

#include <algorithm>

namespace tumble::net {

void OutboundQueue::push_message(std::string bytes) {
  message_bytes_ += bytes.size();
  messages_.push_back(std::move(bytes));
}

void OutboundQueue::offer_frame(std::uint32_t stream, std::shared_ptr<const std::string> bytes) {
  offer_slot({stream, std::move(bytes), nullptr});
}

void OutboundQueue::offer_delta_frame(std::uint32_t stream, std::shared_ptr<const QuantizedFrame> frame) {
  offer_slot({stream, nullptr, std::move(frame)});
}

void OutboundQueue::offer_slot(FrameSlot offered) {
  for (FrameSlot& slot : frames_) {
    if (slot.stream == offered.stream) {
      slot = std::move(offered);
      ++frames_replaced_;
      return;
    }
  }
  frames_.push_back(std::move(offered));
}

DeltaEncoder& OutboundQueue::encoder_of(std::uint32_t stream) {
  for (DeltaStream& delta : delta_streams_) {
    if (delta.stream == stream) return delta.encoder;
  }
  return delta_streams_.emplace_back(DeltaStream{stream, {}}).encoder;
}

void OutboundQueue::restart_delta(std::uint32_t stream) {
  // A stream without an encoder yet starts with a key frame anyway.
  for (DeltaStream& delta : delta_streams_) {
    if (delta.stream == stream) delta.encoder.restart();
  }
}

void OutboundQueue::drop_stream(std::uint32_t stream) {
  std::erase_if(frames_, [stream](const FrameSlot& slot) { return slot.stream == stream; });
  std::erase_if(delta_streams_, [stream](const DeltaStream& delta) { return delta.stream == stream; });
}

void OutboundQueue::take_batch(Batch& batch) {
  batch.messages.clear();
  batch.frames.clear();
  batch.pieces.clear();
  batch.bytes = 0;
  batch.messages.swap(messages_);
  message_bytes_ = 0;
  for (FrameSlot& slot : frames_) {
    if (slot.delta) {
      batch.frames.push_back(encoder_of(slot.stream).encode(std::move(slot.delta)));
    } else {
      batch.frames.push_back(std::move(slot.bytes));
    }
  }
  frames_.clear();
  for (const std::string& message : batch.messages) batch.pieces.emplace_back(message);
  for (const auto& frame : batch.frames) batch.pieces.emplace_back(*frame);
  for (std::string_view piece : batch.pieces) batch.bytes += piece.size();
}

}  // namespace tumble::net
