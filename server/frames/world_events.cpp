#include "frames/world_events.h"

namespace tumble::frames {

tumble::v1::WorldEventKind wire_kind(sim::WorldEventKind kind) {
  switch (kind) {
    case sim::WorldEventKind::body_spawned:
      return tumble::v1::WORLD_EVENT_BODY_SPAWNED;
    case sim::WorldEventKind::body_removed:
      return tumble::v1::WORLD_EVENT_BODY_REMOVED;
    case sim::WorldEventKind::body_asleep:
      return tumble::v1::WORLD_EVENT_BODY_ASLEEP;
    case sim::WorldEventKind::body_awake:
      return tumble::v1::WORLD_EVENT_BODY_AWAKE;
    case sim::WorldEventKind::world_reset:
      return tumble::v1::WORLD_EVENT_WORLD_RESET;
    case sim::WorldEventKind::body_diverged:
      return tumble::v1::WORLD_EVENT_BODY_DIVERGED;
  }
  return tumble::v1::WORLD_EVENT_KIND_UNSPECIFIED;
}

void fill_world_event(const sim::WorldEvent& event, std::uint32_t subscription_id, tumble::v1::WorldEvent* out) {
  out->set_subscription_id(subscription_id);
  out->set_tick(event.tick);
  out->set_kind(wire_kind(event.kind));
  if (event.body != physics::kInvalidBodyId) out->set_body_id(event.body);
  out->set_body_name(event.name);
}

}  // namespace tumble::frames
