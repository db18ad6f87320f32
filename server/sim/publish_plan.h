// Publish planning: what the snapshots after a tick hold, from the interests
// of the pose streams (sim/publish_interest.h). A snapshot is due after a
// tick that one of the interests' periods divides. It holds every body when
// one was requested, when a due interest wants all, or when a large due
// interest alone names most of the world (copies_every_body); else the
// sorted union of the due interests' bodies. When small interests (those
// that go early) are due beside a large one or every body, their bodies go
// first, in a snapshot of their own, so their frames do not wait for the
// large copy.
//
// Pure: no World and no threads. Thread: owned by the sim thread. Once its
// vectors have grown to the interests' sizes, planning does not allocate.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/publish_interest.h"
#include "tumble/physics/body.h"

namespace tumble::sim {

class PublishPlan {
 public:
  enum class Due { nothing, wanted_bodies, every_body };

  // Replaces the interests; those of at most early_bodies bodies go early
  // (goes_early).
  void set_interests(std::vector<PublishInterest> interests, std::size_t early_bodies);

  // What is due after `tick` in a world of `world_bodies` bodies;
  // snapshot_requested: a snapshot of every body was asked for. Fills early().
  Due plan(std::uint64_t tick, std::size_t world_bodies, bool snapshot_requested);

  // The bodies (sorted, unique) of the small interests due at the planned
  // tick, to publish ahead of the rest; empty unless something larger is
  // due beside them.
  const std::vector<physics::BodyId>& early() const { return early_; }

  // The union of the bodies of the interests due at the planned tick, sorted
  // and unique. Gathered on call, so that the early snapshot can go out
  // before the large set is even gathered.
  const std::vector<physics::BodyId>& collect_wanted();

  // Whether a snapshot of `wanted` bodies by id is taken as a copy of every
  // body of a world of `world_bodies` instead: most of the world costs less
  // in one pass over the dense arrays than a lookup a body, and covers the
  // same. A set small enough to go early never is (a tiny world keeps its
  // filter).
  bool copies_every_body(std::size_t wanted, std::size_t world_bodies) const;

 private:
  std::vector<PublishInterest> interests_;
  std::size_t early_bodies_ = 0;         // the line between small and large interests
  std::vector<std::size_t> due_;         // indices in interests_ of those due at the planned tick
  std::vector<physics::BodyId> early_;   // the small due interests' bodies, when a larger one is due too
  std::vector<physics::BodyId> wanted_;  // every due interest's bodies (collect_wanted)
  std::vector<physics::BodyId> merge_scratch_;
};

}  // namespace tumble::sim
