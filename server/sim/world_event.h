// Things that happen to the world that a client may want to hear about
// without watching every frame: bodies spawned and removed, falling asleep
// and waking, diverging, joints added, removed and broken, and resets. The sim thread collects them while it applies
// commands and steps, and hands each tick's events over in order.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tumble/physics/body.h"
#include "tumble/physics/joint.h"

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
  joint_added,    // AddJoint, or Reset bringing back a joint of the scene
  joint_removed,  // RemoveJoint, a removal of one of its bodies, Reset, or after joint_broken
  // The step of `tick` broke the joint (physics::World::broken_joints); a
  // joint_removed follows at once.
  joint_broken,
};

struct WorldEvent {
  std::uint64_t tick = 0;  // the first tick whose state shows the event
  WorldEventKind kind = WorldEventKind::body_spawned;
  // kInvalidBodyId for world_reset; body B for the joint events.
  physics::BodyId body = physics::kInvalidBodyId;
  std::string name;  // the body's name, or the joint's for joint events; may be empty
  // Joint events: the joint and its body A (kWorldBodyId for the world).
  physics::JointId joint = physics::kInvalidJointId;
  physics::BodyId body_a = physics::kInvalidBodyId;
};

// The events of one tick, oldest first. Shared read-only once handed over.
using WorldEvents = std::vector<WorldEvent>;

// Receives each tick's events on the sim thread; must not block.
using WorldEventListener = std::function<void(std::shared_ptr<const WorldEvents>)>;

}  // namespace tumble::sim
