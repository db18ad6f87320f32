#include "sim/sleep_watch.h"

namespace tumble::sim {

void SleepWatch::start(const physics::World& world) {
  watching_ = true;
  awake_.clear();
  for (std::size_t i = 0; i < world.body_count(); ++i) {
    const physics::BodyId id = world.body_id_at(i);
    if (id >= awake_.size()) awake_.resize(static_cast<std::size_t>(id) + 1, 1);
    awake_[id] = world.is_awake(id) ? 1 : 0;
  }
}

void SleepWatch::scan(const physics::World& world, const BodyDirectory& directory, std::uint64_t tick,
                      WorldEvents* events) {
  for (std::size_t i = 0; i < world.body_count(); ++i) {
    const physics::BodyId id = world.body_id_at(i);
    if (!sleeps(world, id)) continue;
    if (id >= awake_.size()) awake_.resize(static_cast<std::size_t>(id) + 1, 1);
    const std::uint8_t awake = world.is_awake(id) ? 1 : 0;
    if (awake == awake_[id]) continue;
    awake_[id] = awake;
    events->push_back(
        {tick, awake ? WorldEventKind::body_awake : WorldEventKind::body_asleep, id, directory.name_of(id)});
  }
}

void SleepWatch::add(const physics::World& world, physics::BodyId id) {
  if (!watching_ || !sleeps(world, id)) return;
  if (id >= awake_.size()) awake_.resize(static_cast<std::size_t>(id) + 1, 1);
  awake_[id] = world.is_awake(id) ? 1 : 0;
}

}  // namespace tumble::sim
