// The worlds net_load spawns into a running tumbled, and the probe body its
// latency measurement moves.
//
//  - field: a static ground plane y = 0 and B spheres (radius 0.2 m, 1 kg)
//    resting on it on a 0.5 m grid centred on the origin (100 x 100, 50 m
//    across, for B = 10000); every 1/F-th one spins in place about the
//    vertical at 1 rad/s (on its one contact point nothing slows it), the
//    rest lie still and fall asleep. A large world of which a fraction
//    moves. With kinematic movers the spinning ones are kinematic bodies
//    (moved by the world's owner, like a game's animated objects): the same
//    streams at a fraction of the physics (a dynamic sphere on the ground
//    costs a contact every step).
//  - cubes: the ground plane, B - 1 cubes of 0.3 m on a square
//    grid 0.4 m apart centred on the origin, dropped from 0.4, 0.95 or 1.5 m
//    (alternating, so that neighbours never overlap) in tilted orientations,
//    and one level 1 m cube of 10 kg dropped from 2.3 m onto the middle:
//    they land, tumble and come to rest.
//
// Both are for a world with gravity (tumbled without --scene), and both
// add the probe: a kinematic sphere at (-100, 5, 0), far from the rest,
// which gravity and contacts leave alone.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "load_connection.h"

namespace tumble::bench {

enum class WorldLayout { field, cubes };

struct WorldOptions {
  WorldLayout layout = WorldLayout::field;
  unsigned bodies = 1000;         // B: the bodies the subscribers follow (the plane and the probe are extra)
  double moving = 0.1;            // field: F, the fraction that spins
  bool kinematic_movers = false;  // field: the spinning ones are kinematic, not dynamic
};

struct LoadWorld {
  std::vector<std::uint32_t> bodies;  // ids of the B bodies, ascending
  std::uint32_t probe = 0;            // id of the probe
  unsigned resting = 0;               // how many of the bodies come to rest (and fall asleep)
};

// Spawns the world through `parallel` connections at once (a spawn takes
// effect at the next tick, so one connection spawns at most one body a
// tick), retrying spawns the server's request rate refuses; exits on any
// other failure.
LoadWorld spawn_world(const LoadTarget& target, const WorldOptions& options, unsigned parallel);

// "field" or "cubes".
const char* layout_name(WorldLayout layout);

}  // namespace tumble::bench
