// World: islands and sleeping.
//
// An island is a set of dynamic bodies connected by contacts with manifold
// points; static and kinematic bodies do not connect islands (a floor
// under two separate piles keeps them separate). Each step every awake
// dynamic body accumulates the time it has been slow; an island whose
// bodies have all been slow for time_to_sleep, and that touches something,
// falls asleep as a whole: its bodies stop being integrated and their
// contacts are neither updated nor solved. Anything that disturbs one of its
// bodies wakes the whole island (Catto, "Box2D" b2Island; Baraff's notes
// leave sleeping out).
#include <algorithm>

#include "world_impl.h"

namespace tumble::physics {

void World::Impl::update_sleep(double dt) {
  if (!settings_.sleep_enabled) return;
  const double time_to_sleep = settings_.time_to_sleep;
  bool any_ready = false;
  for (std::size_t i = 0; i < records_.size(); ++i) {
    // Only awake bodies are visited below, so only theirs need clearing.
    if (!awake_[i]) continue;
    BodyRecord& record = records_[i];
    record.visited = false;
    if (record.motion_type != MotionType::dynamic_body) continue;
    const SolverVelocity& v = velocities_[i];
    const double speed = std::max(v.linear.norm(), v.angular.norm() * record.bounding_radius);
    if (speed < settings_.sleep_speed) {
      record.sleep_time += dt;
      any_ready = any_ready || record.sleep_time >= time_to_sleep;
    } else {
      record.sleep_time = 0;
    }
  }
  if (!any_ready) return;

  // Depth-first search over touching contacts from each body ready to
  // sleep; bodies not ready keep their island awake.
  for (std::uint32_t seed = 0; seed < records_.size(); ++seed) {
    if (!awake_[seed]) continue;
    const BodyRecord& seed_record = records_[seed];
    if (seed_record.visited || seed_record.motion_type != MotionType::dynamic_body ||
        seed_record.sleep_time < time_to_sleep) {
      continue;
    }
    island_stack_.clear();
    island_members_.clear();
    island_stack_.push_back(seed);
    records_[seed].visited = true;
    bool can_sleep = true;
    bool touches = false;
    while (!island_stack_.empty()) {
      const std::uint32_t body = island_stack_.back();
      island_stack_.pop_back();
      island_members_.push_back(body);
      if (records_[body].sleep_time < time_to_sleep) can_sleep = false;
      for (ContactKey key = records_[body].contact_head; key != kNullContactKey;) {
        const ContactLink& link = links_[key >> 1];
        const std::uint32_t side = key & 1;
        key = link.next[side];
        if (!link.touching) continue;
        touches = true;
        const std::uint32_t other = side == 0 ? link.body_b : link.body_a;
        BodyRecord& other_record = records_[other];
        if (other_record.motion_type == MotionType::kinematic_body) {
          if (awake_[other]) can_sleep = false;  // carried by a moving body
          continue;
        }
        if (other_record.motion_type != MotionType::dynamic_body || other_record.visited || !awake_[other]) {
          continue;
        }
        other_record.visited = true;
        island_stack_.push_back(other);
      }
    }
    if (!can_sleep || !touches) continue;
    for (std::uint32_t body : island_members_) put_to_sleep(body);
  }
}

void World::Impl::put_to_sleep(std::uint32_t body) {
  BodyRecord& record = records_[body];
  awake_[body] = 0;
  record.reach = 0;
  states_[body].linear_momentum.setZero();
  states_[body].angular_momentum.setZero();
  velocities_[body] = SolverVelocity{};
}

void World::Impl::wake_island(std::uint32_t body) {
  if (records_[body].motion_type != MotionType::dynamic_body || awake_[body]) return;
  // Flood over touching contacts to the sleeping dynamic bodies.
  island_stack_.clear();
  island_stack_.push_back(body);
  awake_[body] = 1;
  if (collecting_woken_) woken_.push_back(body);
  while (!island_stack_.empty()) {
    const std::uint32_t i = island_stack_.back();
    island_stack_.pop_back();
    BodyRecord& record = records_[i];
    record.sleep_time = 0;
    record.reach = 0;
    external_[i] = SolverVelocity{};
    refresh_solver_data(i);
    for (ContactKey key = record.contact_head; key != kNullContactKey;) {
      const ContactLink& link = links_[key >> 1];
      const std::uint32_t side = key & 1;
      key = link.next[side];
      if (!link.touching) continue;
      const std::uint32_t other = side == 0 ? link.body_b : link.body_a;
      BodyRecord& other_record = records_[other];
      if (other_record.motion_type != MotionType::dynamic_body || awake_[other]) continue;
      awake_[other] = 1;
      island_stack_.push_back(other);
      if (collecting_woken_) woken_.push_back(other);
    }
  }
}

}  // namespace tumble::physics
