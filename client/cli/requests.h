// Protocol requests built from parsed subcommands. Pure: no I/O.
#pragma once

#include "command_line.h"
#include "tumble/v1/protocol.pb.h"

namespace tumble::cli {

// The ApplyForce for `tumble force`: the point is in FRAME_BODY when
// --local, FRAME_WORLD otherwise, and absent without --at; the duration is
// seconds, ticks, or absent (one tick, or until cleared when persistent).
tumble::v1::ApplyForce make_apply_force(const ForceCommand& command);

// The ApplyTorque for `tumble torque`.
tumble::v1::ApplyTorque make_apply_torque(const TorqueCommand& command);

// The ApplyImpulse for `tumble impulse`; the point as for make_apply_force.
tumble::v1::ApplyImpulse make_apply_impulse(const ImpulseCommand& command);

// The Subscribe for `tumble subscribe`: with --events, every kind of
// WorldEvent.
tumble::v1::Subscribe make_subscribe(const SubscribeCommand& command);

// The BodySpec for `tumble spawn`: orientation, friction and restitution
// only when given.
tumble::v1::BodySpec make_body_spec(const SpawnCommand& command);

// The SetBodyState for `tumble set`, with only the parts given.
tumble::v1::SetBodyState make_set_body_state(const SetCommand& command);

// The ClearForces for `tumble clear`; no body means every body.
tumble::v1::ClearForces make_clear_forces(const ClearCommand& command);

// The Subscribe for `tumble watch`: poses and velocities (for the speed),
// and the events that change its table (spawned, removed, asleep, awake).
tumble::v1::Subscribe make_watch_subscribe(const WatchCommand& command);

// The JointSpec for `tumble joint add`: only the fields given. --anchor is
// a distance joint's anchor_a.
tumble::v1::JointSpec make_joint_spec(const JointAddCommand& command);

// The SetJointMotor for `tumble motor`; without a motor it turns it off.
tumble::v1::SetJointMotor make_set_joint_motor(const MotorCommand& command);

}  // namespace tumble::cli
