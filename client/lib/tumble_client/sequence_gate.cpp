#include "tumble_client/sequence_gate.h"

namespace tumble::client {
namespace {

// A frame that stands alone: every body of the stream.
bool is_whole(const tumble::v1::PoseFrame& frame) {
  return frame.encoding() != tumble::v1::POSE_ENCODING_DELTA || frame.key_frame();
}

}  // namespace

SequenceGate::Verdict SequenceGate::take_whole(std::uint64_t sequence) {
  held_ = sequence;
  key_requested_ = false;
  return Verdict{.show = true, .request_key = false};
}

SequenceGate::Verdict SequenceGate::published(const tumble::v1::PoseFrame& frame) {
  const std::uint64_t sequence = frame.sequence();
  if (key_shown_ != 0) {
    // Frames published before the key reply that was shown may still come:
    // they are older than what is on screen. A restarted server begins again
    // at 1, which ends the wait as a newer frame does.
    if (sequence <= key_shown_ && sequence != 1) return Verdict{};
    key_shown_ = 0;
  }
  if (is_whole(frame)) return take_whole(sequence);
  if (held_ != 0 && sequence == held_ + 1) {
    held_ = sequence;
    return Verdict{.show = true, .request_key = false};
  }
  // A change already contained in what is shown: nothing new, still in step.
  if (held_ != 0 && sequence <= held_) return Verdict{};
  // A change on top of a frame this reader never had.
  held_ = 0;
  if (key_requested_) return Verdict{};
  key_requested_ = true;
  return Verdict{.show = false, .request_key = true};
}

SequenceGate::Verdict SequenceGate::key_reply(const tumble::v1::PoseFrame& frame) {
  const std::uint64_t sequence = frame.sequence();
  key_requested_ = false;
  if (!is_whole(frame)) return Verdict{};  // a change cannot restore anything
  // Out of step, any whole frame restores; in step, only a newer one is news.
  if (held_ != 0 && sequence <= held_) return Verdict{};
  key_shown_ = sequence;
  return take_whole(sequence);
}

}  // namespace tumble::client
