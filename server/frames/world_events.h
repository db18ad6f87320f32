// A sim WorldEvent as the protocol's WorldEvent, whatever carries it (a TCP
// subscription, NATS's events subject).
#pragma once

#include <cstdint>

#include "sim/world_event.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::frames {

tumble::v1::WorldEventKind wire_kind(sim::WorldEventKind kind);

// Fills `out` with `event`, for the stream `subscription_id` (0 over NATS).
void fill_world_event(const sim::WorldEvent& event, std::uint32_t subscription_id, tumble::v1::WorldEvent* out);

}  // namespace tumble::frames
