// Things that happen to the world that a client may want to hear about
// without watching every frame: bodies spawned and removed, falling asleep
// and waking, diverging, and resets. The sim thread collects them while it applies
// commands and steps, and hands each tick's events over in order.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tumble/physics/body.h"

namespace tumble::sim {

enum class WorldEventKind : std::uint8_t {
  body_spawned,  // SpawnBody, or Reset bringing back a body of the scene
  body_removed,  // RemoveBody, or Reset dropping a spawned body
  body_asleep,   // a dynamic body fell asleep in the step of `tick`
  body_awake,    // a sleeping dynamic body woke up
  world_reset,   // the world was put back to its scene; no body
  // The step of `tick` left the body's state not finite or out of range
  // (physics::World::diverged_bodies); a body_removed follows at once.
  body_diverged,
};

struct WorldEvent {
  std::uint64_t tick = 0;  // the first tick whose state shows the event
  WorldEventKind kind = WorldEventKind::body_spawned;
  physics::BodyId body = physics::kInvalidBodyId;  // kInvalidBodyId for world_reset
  std::string name;                                // the body's name; may be empty
};

// The events of one tick, oldest first. Shared read-only once handed over.
using WorldEvents = std::vector<WorldEvent>;

// Receives each tick's events on the sim thread; must not block.
using WorldEventListener = std::function<void(std::shared_ptr<const WorldEvents>)>;

}  // namespace tumble::sim
