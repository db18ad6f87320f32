// QuantizeMemo: a stream's bodies on the quantization grids as it last made
// them, with the snapshot values they came from, so that its next frame
// takes the record of every body whose values have not changed since (a
// resting body's are bit-identical from tick to tick) instead of
// quantizing it again. In a world of 10,000 bodies of which a tenth move,
// quantizing every body was most of the I/O thread's work per frame
// besides the writes.
//
// The records are kept in the snapshot's order and matched by walking both
// lists at once: a body left out since (removed, or its last body moved
// into its place) costs a fresh quantization of the bodies that moved,
// never a wrong record; a reused record equals what quantize_body() would
// make, since the values are the same to the bit.
//
// Thread: owned by one stream, used on the thread that publishes it (net's
// I/O thread, or the NATS publisher's).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/snapshot.h"
#include "tumble/physics/body.h"
#include "wire/quantized_poses.h"

namespace tumble::frames {

class QuantizeMemo {
 public:
  // The bodies of `snapshot` a stream reads (every one, or those in the
  // sorted `filter`) on the grids, with velocities or without, sorted by
  // id. A memo serves one stream: `velocities` must not change between
  // calls.
  std::vector<wire::QuantizedBody> quantize(const sim::Snapshot& snapshot, bool all_bodies,
                                            const std::vector<physics::BodyId>& filter, bool velocities);

  // Bodies the last quantize() put on the grids afresh (the rest were reused).
  std::size_t quantized_last() const { return quantized_last_; }

 private:
  // Values a body's record is made from: position 3, orientation 4, and
  // with velocities linear 3 and angular 3.
  static std::size_t values_per_body(bool velocities) { return velocities ? 13 : 7; }

  std::vector<physics::BodyId> ids_;          // in the last snapshot's order
  std::vector<double> values_;                // values_per_body() a body, in that order
  std::vector<wire::QuantizedBody> records_;  // in that order
  // The lists being made, swapped with the above at the end of a call.
  std::vector<physics::BodyId> next_ids_;
  std::vector<double> next_values_;
  std::vector<wire::QuantizedBody> next_records_;
  std::size_t quantized_last_ = 0;
};

}  // namespace tumble::frames
