// What a session has yet to write to its client. Two kinds of bytes:
//  - messages (replies, errors, the handshake): kept in order and never
//    dropped; their total is bounded by the caller, who disconnects a client
//    that lets them pile up;
//  - pose frames: one slot per stream, latest-wins. A newer frame replaces
//    an unsent older one of the same stream, so a slow reader gets fewer,
//    newer frames and never a growing backlog. A DELTA stream's slot holds
//    its latest quantized frame instead, encoded against what this client
//    last received only when it is taken for writing (net/delta_encoder.h).
// Messages queued before a frame are written before it.
//
// Thread: owned by one session on the I/O thread.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "net/delta_encoder.h"
#include "net/quantized_frame.h"

namespace tumble::net {

class OutboundQueue {
 public:
  // Bytes handed out by take_batch(); they stay valid until the next call.
  struct Batch {
    std::vector<std::string> messages;
    std::vector<std::shared_ptr<const std::string>> frames;
    std::vector<std::string_view> pieces;  // in write order, viewing the two above
    std::size_t bytes = 0;
  };

  // Queues one framed message.
  void push_message(std::string bytes);

  // Queues a framed pose frame of `stream`, replacing an unsent one.
  void offer_frame(std::uint32_t stream, std::shared_ptr<const std::string> bytes);

  // Queues a DELTA stream's frame, replacing an unsent one.
  void offer_delta_frame(std::uint32_t stream, std::shared_ptr<const QuantizedFrame> frame);

  // Makes the next frame of DELTA `stream` written a key frame.
  void restart_delta(std::uint32_t stream);

  // Forgets the unsent frame (and the delta baseline) of a stream the client left.
  void drop_stream(std::uint32_t stream);

  bool empty() const { return messages_.empty() && frames_.empty(); }

  // Bytes of messages waiting, not counting frames.
  std::size_t pending_message_bytes() const { return message_bytes_; }

  // Frames replaced before they were written, since the queue was made.
  std::uint64_t frames_replaced() const { return frames_replaced_; }

  // Moves everything queued into `batch`, messages first; DELTA frames are
  // encoded here, and become their streams' baselines.
  void take_batch(Batch& batch);

 private:
  struct FrameSlot {
    std::uint32_t stream;
    std::shared_ptr<const std::string> bytes;     // null for a DELTA stream
    std::shared_ptr<const QuantizedFrame> delta;  // null but for a DELTA stream
  };
  struct DeltaStream {
    std::uint32_t stream;
    DeltaEncoder encoder;
  };
  void offer_slot(FrameSlot slot);
  DeltaEncoder& encoder_of(std::uint32_t stream);

  std::vector<std::string> messages_;
  std::vector<FrameSlot> frames_;           // at most one per stream, in arrival order
  std::vector<DeltaStream> delta_streams_;  // one per DELTA stream this client is on
  std::size_t message_bytes_ = 0;
  std::uint64_t frames_replaced_ = 0;
};

}  // namespace tumble::net
