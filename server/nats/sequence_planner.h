// The numbering of one NATS pose stream's frames: sequence 1, 2, 3, ...
// from when tumbled starts publishing, and which of them are key frames.
// The first frame is one; then a frame is one when key_interval seconds
// of sim time have passed since the last key frame, or when the last frame
// was not published (over the max payload, or the link down), so that no
// change is ever published against a frame nobody received. While nothing
// has changed since the last key frame (a world at rest), the next one
// waits rest_key_interval instead: a reader that joins then asks for a key
// frame on .key rather than waiting, and a resting world's stream stays
// small. A FULL or QUANTIZED stream's frames are all whole; they are
// numbered the same way.
//
// Thread: owned by the stream, on the NATS publisher's thread.
#pragma once

#include <cstdint>

namespace tumble::nats {

class SequencePlanner {
 public:
  // Sim seconds between key frames: `key_interval_s` > 0 after a change,
  // `rest_key_interval_s` >= key_interval_s while nothing changed.
  SequencePlanner(double key_interval_s, double rest_key_interval_s)
      : key_interval_s_(key_interval_s), rest_key_interval_s_(rest_key_interval_s) {}

  struct Frame {
    std::uint64_t sequence = 0;
    bool key = false;
  };

  // The number of the next frame, of sim time `sim_time_s`, and whether it
  // is a key frame.
  Frame next(double sim_time_s);

  // The frame next() numbered last, a change frame, changed something: a
  // body moved, came or went.
  void changed() { changed_since_key_ = true; }

  // The frame next() numbered last was not published: the one after it must
  // be a key frame.
  void lost() { key_due_ = true; }

  std::uint64_t last_sequence() const { return sequence_; }

 private:
  double key_interval_s_;
  double rest_key_interval_s_;
  std::uint64_t sequence_ = 0;
  bool key_due_ = true;
  bool changed_since_key_ = false;
  double last_key_time_ = 0;
};

}  // namespace tumble::nats
