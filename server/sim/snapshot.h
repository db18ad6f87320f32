// An immutable copy of the world's poses after one step (or, while paused,
// after an edit), shared by the publisher and every subscription that reads
// it.
#pragma once

#include <cstdint>
#include <vector>

#include "physics/body.h"

namespace tumble::sim {

// Body i of the snapshot is ids[i]; its values are at 3i (vectors) and 4i
// (orientations: w, x, y, z). All in the world frame, SI units.
struct Snapshot {
  std::uint64_t tick = 0;
  double sim_time = 0;  // s
  std::vector<physics::BodyId> ids;
  std::vector<double> positions;           // m, centre of mass
  std::vector<double> orientations;        // unit quaternions, w x y z
  std::vector<double> linear_velocities;   // m/s
  std::vector<double> angular_velocities;  // rad/s
  // The world was edited while paused (spawn, remove, set, impulse, reset):
  // every subscription gets this frame although its tick is not new.
  bool out_of_band = false;

  std::size_t body_count() const { return ids.size(); }
};

}  // namespace tumble::sim
