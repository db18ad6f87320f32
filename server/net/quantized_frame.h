// One snapshot of a DELTA stream's bodies on the quantization grids, made
// once per stream and shared by its sessions, each of which turns it into
// a delta against what that session's client last received
// (net/delta_encoder.h).
//
// Most clients keep up, so most hold the stream's previous frame and get
// the same bytes: the frame keeps the first encoding of itself as a key
// frame and as a change from the previous frame, and the sessions that
// need the same one share it.
//
// Thread: made and used on the I/O thread only (the caches are filled
// through a const frame).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tumble/v1/protocol.pb.h"
#include "wire/quantized_poses.h"

namespace tumble::net {

struct QuantizedFrame {
  std::uint32_t subscription_id = 0;
  std::uint64_t tick = 0;
  double sim_time = 0;  // s
  bool velocities = false;
  std::vector<wire::QuantizedBody> bodies;  // sorted by id
  std::uint64_t sequence = 0;               // 1, 2, 3, ... for the frames of one stream, in the order they were made
  // Subscribe.joints: a PoseFrame holding only the joints' states
  // (frames::fill_joints), merged into every encoding of this frame, key
  // or change alike.
  tumble::v1::PoseFrame joints;

  // Framed ServerMessages, filled by the first session that needs each.
  mutable std::shared_ptr<const std::string> key_bytes;     // this frame as a key frame
  mutable std::shared_ptr<const std::string> change_bytes;  // the change from frame sequence - 1
};

}  // namespace tumble::net
