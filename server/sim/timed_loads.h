// Forces and torques that act for a number of ticks. A force keeps its point
// of application in the body frame, so a push at a corner stays at that
// corner while the body turns; its direction stays fixed in the world.
//
// Thread: owned by the sim thread.
#pragma once

#include <cstdint>
#include <vector>

#include "physics/world.h"

namespace tumble::sim {

class TimedLoads {
 public:
  // `local_point`: m, body frame, relative to the centre of mass.
  void add_force(physics::BodyId body, const physics::Vec3& force, const physics::Vec3& local_point,
                 std::uint32_t ticks);
  void add_torque(physics::BodyId body, const physics::Vec3& torque, std::uint32_t ticks);

  // Adds every active load to the world's accumulators for the coming step
  // and counts one tick off each; loads that are used up are dropped.
  void apply(physics::World& world);

  // Drops the loads on a body that is gone.
  void remove_body(physics::BodyId body);

  std::size_t size() const { return loads_.size(); }

 private:
  // One force (at a body point) and one torque; a plain force has zero
  // torque and vice versa.
  struct Load {
    physics::BodyId body;
    physics::Vec3 force;        // N, world frame
    physics::Vec3 local_point;  // m, body frame
    physics::Vec3 torque;       // N m, world frame
    std::uint32_t ticks_left;
  };
  std::vector<Load> loads_;
};

}  // namespace tumble::sim
