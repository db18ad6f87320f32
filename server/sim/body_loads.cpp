#include "sim/body_loads.h"

#include <algorithm>

namespace tumble::sim {

void BodyLoads::add_force(physics::BodyId body, const physics::Vec3& force, const physics::Vec3& local_point,
                          std::uint32_t ticks) {
  loads_.push_back({body, force, local_point, physics::Vec3::Zero(), ticks});
}

void BodyLoads::add_torque(physics::BodyId body, const physics::Vec3& torque, std::uint32_t ticks) {
  loads_.push_back({body, physics::Vec3::Zero(), physics::Vec3::Zero(), torque, ticks});
}

void BodyLoads::apply(physics::World& world) {
  for (BodyLoad& load : loads_) {
    if (!load.force.isZero(0.0)) {
      // The attachment point follows the body: r = x + R p_body.
      const physics::Vec3 point = world.position(load.body) + world.orientation(load.body) * load.local_point;
      world.add_force_at_point(load.body, load.force, point);
    }
    if (!load.torque.isZero(0.0)) world.add_torque(load.body, load.torque);
    if (!load.persistent()) --load.ticks_left;
  }
  // Stable removal keeps the order of accumulation, and with it the
  // floating-point sums, a function of the command stream alone.
  std::erase_if(loads_, [](const BodyLoad& load) { return load.ticks_left == 0; });
}

void BodyLoads::remove_body(physics::BodyId body) {
  std::erase_if(loads_, [body](const BodyLoad& load) { return load.body == body; });
}

}  // namespace tumble::sim
