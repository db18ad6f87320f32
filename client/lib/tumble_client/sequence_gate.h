// SequenceGate: which frames of a pose stream read over NATS may be shown.
//
// A stream's frames carry a sequence number (1, 2, 3, ... from when the
// server started publishing). A DELTA change holds only what moved since
// frame `sequence - 1`, so it is right only on top of exactly that frame; a
// reader that missed one (it joined late, or NATS dropped messages of a
// slow consumer) must show nothing new until a whole frame: the next key
// frame published, or the reply to a request on the stream's `.key` subject,
// which is the stream's latest frame as a key frame with that frame's
// sequence. FULL, QUANTIZED and DELTA key frames are whole and always right.
//
// The gate sees every frame in the order it reaches the reader, published
// ones and key replies mixed (they travel on different subjects, so a key
// reply may overtake frames published before it). It lets a frame through
// when it is whole and not older than what was shown, or when it is the
// change that follows what was shown; it says when a key frame should be
// asked for. Frames it lets through, decoded in order by one PoseStream,
// give only states the server had. Not thread-safe.
#pragma once

#include <cstdint>

#include "tumble/v1/protocol.pb.h"

namespace tumble::client {

class SequenceGate {
 public:
  // What to do with one frame.
  struct Verdict {
    bool show = false;         // hand it on: it is right on top of what was shown
    bool request_key = false;  // ask for a key frame now: the reader is out of step and none was asked for
  };

  // A frame published on the stream's subject.
  Verdict published(const tumble::v1::PoseFrame& frame);

  // The reply to a request on the stream's `.key` subject.
  Verdict key_reply(const tumble::v1::PoseFrame& frame);

  // A key frame request could not be sent or went unanswered: the next
  // frame out of step may ask again.
  void key_request_failed() { key_requested_ = false; }

  // The sequence of the last frame shown; 0 while out of step (nothing
  // shown yet, or a change was missed).
  std::uint64_t held() const { return held_; }

 private:
  // Shows a whole frame of `sequence`.
  Verdict take_whole(std::uint64_t sequence);

  std::uint64_t held_ = 0;       // the sequence of the state shown; 0: none to build on
  std::uint64_t key_shown_ = 0;  // a key reply shown, until a published frame passes it
  bool key_requested_ = false;   // a key frame was asked for and has not come
};

}  // namespace tumble::client
