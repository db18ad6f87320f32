// PoseStream: the frames of one subscription, decoded whatever their
// encoding. FULL and QUANTIZED frames stand alone; a DELTA frame holds only
// what changed, so the stream keeps the bodies it has seen and completes
// each frame from them, giving every body of the subscription each time.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "tumble_client/pose_sample.h"
#include "wire/quantized_poses.h"

namespace tumble::client {

class PoseStream {
 public:
  // The whole state the frame shows: for a DELTA frame, the bodies of the
  // last key frame updated by every frame since, in id order. Fails with
  // kind protocol on malformed bytes or a DELTA change before any key frame.
  Result<PoseSample> decode(const tumble::v1::PoseFrame& frame);

  // What decode() does without building the sample, for clients that only
  // count: checks the frame (and for DELTA, brings the stream's bodies up to
  // date) and returns how many bodies it stands for. Same failures.
  Result<std::size_t> apply(const tumble::v1::PoseFrame& frame);

 private:
  // Applies a DELTA frame to bodies_; the failure when it cannot.
  std::optional<Failure> merge(const tumble::v1::PoseFrame& frame);

  bool has_key_frame_ = false;
  wire::QuantizedPoses bodies_;  // a DELTA stream's bodies so far, sorted by id
};

}  // namespace tumble::client
