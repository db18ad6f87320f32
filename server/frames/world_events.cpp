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
    case sim::WorldEventKind::joint_added:
      return tumble::v1::WORLD_EVENT_JOINT_ADDED;
    case sim::WorldEventKind::joint_removed:
      return tumble::v1::WORLD_EVENT_JOINT_REMOVED;
    case sim::WorldEventKind::joint_broken:
      return tumble::v1::WORLD_EVENT_JOINT_BROKEN;
  }
  return tumble::v1::WORLD_EVENT_KIND_UNSPECIFIED;
}

void fill_world_event(const sim::WorldEvent& event, std::uint32_t subscription_id, tumble::v1::WorldEvent* out) {
  out->set_subscription_id(subscription_id);
  out->set_tick(event.tick);
  out->set_kind(wire_kind(event.kind));
  if (event.body != physics::kInvalidBodyId) out->set_body_id(event.body);
  if (event.joint == physics::kInvalidJointId) {
    out->set_body_name(event.name);
    return;
  }
  // A joint's event names the joint; its bodies go by id.
  out->set_joint_id(event.joint);
  out->set_joint_name(event.name);
  out->set_joint_body_a(event.body_a);
}

}  // namespace tumble::frames
