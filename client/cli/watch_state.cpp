#include "watch_state.h"

namespace tumble::cli {

void WatchState::load(const tumble::v1::BodyList& list) {
  bodies_.clear();
  for (const tumble::v1::BodyInfo& body : list.bodies()) bodies_[body.id()] = Body{body.name(), body.asleep()};
}

void WatchState::apply(const tumble::v1::WorldEvent& event) {
  switch (event.kind()) {
    case tumble::v1::WORLD_EVENT_BODY_SPAWNED:
      bodies_[event.body_id()] = Body{event.body_name(), false};
      break;
    case tumble::v1::WORLD_EVENT_BODY_REMOVED:
      bodies_.erase(event.body_id());
      break;
    case tumble::v1::WORLD_EVENT_BODY_ASLEEP:
      bodies_[event.body_id()].asleep = true;
      break;
    case tumble::v1::WORLD_EVENT_BODY_AWAKE:
      bodies_[event.body_id()].asleep = false;
      break;
    default:
      break;
  }
}

const std::string& WatchState::name(std::uint32_t id) const {
  static const std::string kNoName;
  const auto found = bodies_.find(id);
  return found == bodies_.end() ? kNoName : found->second.name;
}

bool WatchState::asleep(std::uint32_t id) const {
  const auto found = bodies_.find(id);
  return found != bodies_.end() && found->second.asleep;
}

}  // namespace tumble::cli
