// Turns a DELTA stream's quantized frames into the PoseFrames one client
// gets: the bodies whose quantized state differs from the last frame this
// encoder produced, and the ids that have left the stream since. The first
// frame after construction or restart() is a key frame with every body.
//
// Correctness under latest-wins: the session encodes a frame only when it
// hands the frame to the socket (OutboundQueue::take_batch), never when it
// is queued, so a frame replaced before it was written never becomes a
// baseline. TCP delivers what was written in order, so the baseline is
// exactly the state the client holds.
//
// Thread: owned by one session's outbound queue on the I/O thread.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "net/quantized_frame.h"

namespace tumble::net {

class DeltaEncoder {
 public:
  // The framed ServerMessage carrying `frame` as a change from the last
  // frame encoded (or as a key frame); `frame` becomes the baseline. The
  // frame is immutable and shared with the stream's other sessions, so
  // keeping it as the baseline copies nothing; when the baseline is the
  // stream's previous frame the bytes are the frame's shared ones.
  std::shared_ptr<const std::string> encode(std::shared_ptr<const QuantizedFrame> frame);

  // Makes the next frame a key frame.
  void restart() { baseline_.reset(); }

 private:
  // The bytes of `frame` as a change from baseline_.
  std::string encode_change(const QuantizedFrame& frame);

  std::shared_ptr<const QuantizedFrame> baseline_;  // the last frame encoded; null: none, or restarted
  std::vector<wire::QuantizedBody> changed_;        // reused between frames
};

}  // namespace tumble::net
