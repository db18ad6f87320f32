// What the pose streams need from the sim's snapshots: at every multiple of
// period_ticks, the poses of some bodies. The publisher states it whenever
// its streams change (Simulation::set_publish_interest); the sim copies
// into a snapshot only the bodies the streams due at that tick read, so a
// small stream at the tick rate beside a large one at a lower rate does not
// cost a copy of the whole world every tick. When a large one is due beside
// small ones, the small ones' bodies go first, in a snapshot of their own
// (Snapshot::more_follows), so their frames do not wait for the large copy.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tumble/physics/body.h"

namespace tumble::sim {

// Interests of at most this many bodies are published in a snapshot of
// their own ahead of larger ones due at the same tick.
inline constexpr std::size_t kEarlySnapshotBodies = 64;

struct PublishInterest {
  std::uint32_t period_ticks = 1;       // > 0
  bool all_bodies = true;               // every body, whatever `bodies` holds
  std::vector<physics::BodyId> bodies;  // sorted, unique; read when !all_bodies
};

// Whether an interest (or a stream) of these bodies is one that goes early.
// The publisher groups streams by it and the sim splits snapshots by it:
// both must draw the line in the same place.
inline bool publishes_early(bool all_bodies, const std::vector<physics::BodyId>& bodies) {
  return !all_bodies && bodies.size() <= kEarlySnapshotBodies;
}

}  // namespace tumble::sim
