// What the pose streams need from the sim's snapshots: at every multiple of
// period_ticks, the poses of some bodies. The publisher states it whenever
// its streams change (Simulation::set_publish_interest); the sim copies
// into a snapshot only the bodies the streams due at that tick read, so a
// small stream at the tick rate beside a large one at a lower rate does not
// cost a copy of the whole world every tick. When a large one is due beside
// small ones, the small ones' bodies go first, in a snapshot of their own
// (Snapshot::more_follows), so their frames do not wait for the large copy.
// Where small ends is the publisher's to say: it hands the line over with
// the interests (early_bodies).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tumble/physics/body.h"

namespace tumble::sim {

struct PublishInterest {
  std::uint32_t period_ticks = 1;       // > 0
  bool all_bodies = true;               // every body, whatever `bodies` holds
  std::vector<physics::BodyId> bodies;  // sorted, unique; read when !all_bodies
  bool joints = false;                  // the state of every joint as well
};

// Whether an interest (or a stream) of `body_count` bodies, or of every body
// when all_bodies, goes early when the line is drawn at `early_bodies`. The
// publisher groups its streams by it and the sim splits snapshots by it,
// with the same early_bodies: both draw the line in the same place.
inline bool goes_early(bool all_bodies, std::size_t body_count, std::size_t early_bodies) {
  return !all_bodies && body_count <= early_bodies;
}

}  // namespace tumble::sim
