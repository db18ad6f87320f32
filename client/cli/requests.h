// Protocol requests built from parsed subcommands. Pure: no I/O.
#pragma once

#include "command_line.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::cli {

// The ApplyForce for `tumble force`: the point is in FRAME_BODY when
// --local, FRAME_WORLD otherwise, and absent without --at; the duration is
// seconds, ticks, or absent (one tick).
tumble::v1::ApplyForce make_apply_force(const ForceCommand& command);

// The ApplyTorque for `tumble torque`.
tumble::v1::ApplyTorque make_apply_torque(const TorqueCommand& command);

// The ApplyImpulse for `tumble impulse`; the point as for make_apply_force.
tumble::v1::ApplyImpulse make_apply_impulse(const ImpulseCommand& command);

// The Subscribe for `tumble subscribe`.
tumble::v1::Subscribe make_subscribe(const SubscribeCommand& command);

}  // namespace tumble::cli
