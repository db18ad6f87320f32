// One snapshot of a DELTA stream's bodies on the quantization grids, made
// once per stream and shared by its sessions, each of which turns it into
// a delta against what that session's client last received
// (net/delta_encoder.h).
#pragma once

#include <cstdint>
#include <vector>

#include "wire/quantized_poses.h"

namespace tumble::net {

struct QuantizedFrame {
  std::uint32_t subscription_id = 0;
  std::uint64_t tick = 0;
  double sim_time = 0;  // s
  bool velocities = false;
  std::vector<wire::QuantizedBody> bodies;  // sorted by id
};

}  // namespace tumble::net
