// Watches a world's dynamic bodies fall asleep and wake, for the
// body_asleep and body_awake events: a scan compares every dynamic body's
// sleep with what the last scan saw. Started when a subscriber wants those
// events, so only changes from then on are events.
//
// Thread: owned by the sim thread.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/body_directory.h"
#include "sim/world_event.h"
#include "tumble/physics/world.h"

namespace tumble::sim {

// True when body `id` sleeps and wakes: a dynamic body. Static and
// kinematic bodies never sleep.
inline bool sleeps(const physics::World& world, physics::BodyId id) {
  return world.motion_type(id) == physics::MotionType::dynamic_body;
}

class SleepWatch {
 public:
  bool watching() const { return watching_; }
  // Records every body's sleep as it is now, without events, and watches
  // from now on.
  void start(const physics::World& world);
  void stop() { watching_ = false; }

  // Appends to `events`, as events of `tick`, the dynamic bodies whose
  // sleep changed since the last scan, named from `directory`.
  void scan(const physics::World& world, const BodyDirectory& directory, std::uint64_t tick, WorldEvents* events);

  // Records the sleep of body `id`, new in the world, without an event;
  // nothing when not watching or when it is not dynamic.
  void add(const physics::World& world, physics::BodyId id);

 private:
  bool watching_ = false;
  std::vector<std::uint8_t> awake_;  // by body id, while watching: 1 when awake at the last scan
};

}  // namespace tumble::sim
