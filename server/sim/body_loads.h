// Forces and torques that act on bodies over ticks: for a number of ticks,
// or at every tick until cleared (persistent). A force keeps its point of
// application in the body frame, so a push at a corner stays at that corner
// while the body turns; its direction stays fixed in the world.
//
// The loads are plain data in the order they were added: that order fixes
// the order of the floating-point sums, so the same commands give the same
// trajectory, and the list can be saved and put back as it is.
//
// Thread: owned by the sim thread.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "tumble/physics/world.h"

namespace tumble::sim {

// One force (at a body point) and one torque on one body; a plain force has
// zero torque and vice versa.
struct BodyLoad {
  // ticks_left of a load that acts until it is cleared.
  static constexpr std::uint32_t kPersistent = std::numeric_limits<std::uint32_t>::max();

  physics::BodyId body = physics::kInvalidBodyId;
  physics::Vec3 force = physics::Vec3::Zero();        // N, world frame
  physics::Vec3 local_point = physics::Vec3::Zero();  // m, body frame, relative to the centre of mass
  physics::Vec3 torque = physics::Vec3::Zero();       // N m, world frame
  std::uint32_t ticks_left = 1;                       // ticks still to act, or kPersistent

  bool persistent() const { return ticks_left == kPersistent; }
};

class BodyLoads {
 public:
  // `local_point`: m, body frame, relative to the centre of mass. `ticks`:
  // at least 1, or BodyLoad::kPersistent.
  void add_force(physics::BodyId body, const physics::Vec3& force, const physics::Vec3& local_point,
                 std::uint32_t ticks);
  void add_torque(physics::BodyId body, const physics::Vec3& torque, std::uint32_t ticks);

  // Adds every active load to the world's accumulators for the coming step
  // and counts one tick off each timed load; timed loads that are used up
  // are dropped.
  void apply(physics::World& world);

  // Drops every load on `body`, timed and persistent (ClearForces, or the
  // body is gone).
  void remove_body(physics::BodyId body);

  // Appends a load as it is, e.g. one read back from a saved state.
  void add(const BodyLoad& load) { loads_.push_back(load); }

  // Drops every load.
  void clear() { loads_.clear(); }

  std::size_t size() const { return loads_.size(); }

  // The active loads, in the order they were added.
  const std::vector<BodyLoad>& loads() const { return loads_; }

 private:
  std::vector<BodyLoad> loads_;
};

}  // namespace tumble::sim
