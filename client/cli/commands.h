// The `tumble` subcommands: each connects (over TCP, or through NATS with
// --nats, the same code either way: see client::Transport), does one thing and writes what
// the server said to `out`, as text or, with --json, as JSON lines. Each
// returns the failure that stopped it, or nothing on success. Nothing is
// written to `out` on failure; reporting it is the caller's job.
#pragma once

#include <optional>
#include <ostream>

#include "command_line.h"
#include "tumble_client/failure.h"

namespace tumble::cli {

// The name this client gives in Hello.
inline constexpr const char* kClientName = "tumble-cli";

// Runs whichever command `invocation` holds. `out_is_terminal`: `out` is a
// terminal, where `watch` redraws its table in place.
std::optional<client::Failure> run(const Invocation& invocation, std::ostream& out, bool out_is_terminal = false);

// tumble bodies: lists every body.
std::optional<client::Failure> run_bodies(const GlobalOptions& global, std::ostream& out);

// tumble force: one ApplyForce, prints the tick it takes effect.
std::optional<client::Failure> run_force(const GlobalOptions& global, const ForceCommand& command, std::ostream& out);

// tumble torque: one ApplyTorque, prints the tick it takes effect.
std::optional<client::Failure> run_torque(const GlobalOptions& global, const TorqueCommand& command, std::ostream& out);

// tumble impulse: one ApplyImpulse, prints the tick it takes effect.
std::optional<client::Failure> run_impulse(const GlobalOptions& global, const ImpulseCommand& command,
                                           std::ostream& out);

// tumble subscribe: lists the bodies once (for their names), subscribes,
// then prints each frame (and, with --events, each event) of its
// subscription as it arrives, flushed. Ends with success after `count`
// frames or on SIGINT/SIGTERM (caught from the moment the subscription
// stands); fails when the server sends an Error or closes the connection.
// With `reconnect`, SIGINT/SIGTERM are caught from the start, and a failure
// that worth_reconnecting() accepts, the first connection's included, is a
// line on `notes` (the reason and the wait) followed by a new connection,
// body list and the same Subscribe after a ReconnectBackoff wait, for as
// long as it takes; `count` counts frames across connections, and `notes`
// gets a line when a new subscription stands. Only frames and events go to
// `out`.
std::optional<client::Failure> run_subscribe(const GlobalOptions& global, const SubscribeCommand& command,
                                             std::ostream& out, std::ostream& notes);

// tumble spawn: one SpawnBody, prints the new body's id and the tick.
std::optional<client::Failure> run_spawn(const GlobalOptions& global, const SpawnCommand& command, std::ostream& out);

// tumble remove, set, clear, resume, reset, tick-rate: one request each,
// printing the tick it takes effect.
std::optional<client::Failure> run_remove(const GlobalOptions& global, const RemoveCommand& command, std::ostream& out);
std::optional<client::Failure> run_set(const GlobalOptions& global, const SetCommand& command, std::ostream& out);
std::optional<client::Failure> run_clear(const GlobalOptions& global, const ClearCommand& command, std::ostream& out);
std::optional<client::Failure> run_resume(const GlobalOptions& global, std::ostream& out);
std::optional<client::Failure> run_reset(const GlobalOptions& global, std::ostream& out);
std::optional<client::Failure> run_tick_rate(const GlobalOptions& global, const TickRateCommand& command,
                                             std::ostream& out);

// tumble pause: prints the tick the world stays at.
std::optional<client::Failure> run_pause(const GlobalOptions& global, std::ostream& out);

// tumble step: prints the last tick stepped once all are done.
std::optional<client::Failure> run_step(const GlobalOptions& global, const StepCommand& command, std::ostream& out);

// tumble stats: the server's counters, as labelled lines or one JSON object.
std::optional<client::Failure> run_stats(const GlobalOptions& global, std::ostream& out);

// tumble watch: subscribes to the bodies' poses and to the events that
// change their names and sleep, lists the bodies, then draws a table per
// frame: on a terminal in place (ANSI clear and home), otherwise tables
// separated by blank lines; with --json one object per frame. Ends as
// subscribe does, after `count` tables or on SIGINT/SIGTERM.
std::optional<client::Failure> run_watch(const GlobalOptions& global, const WatchCommand& command, std::ostream& out,
                                         bool out_is_terminal);

// tumble worlds: asks tumble.v1.worlds over NATS and prints every world
// that answered within the quiet period (kWorldsQuietPeriod): a table, or
// with --json one object per world per line.
std::optional<client::Failure> run_worlds(const GlobalOptions& global, std::ostream& out);

// tumble joints: lists every joint, as a table or one JSON object.
std::optional<client::Failure> run_joints(const GlobalOptions& global, std::ostream& out);

// tumble joint add: one AddJoint, prints the new joint's id and the tick.
std::optional<client::Failure> run_joint_add(const GlobalOptions& global, const JointAddCommand& command,
                                             std::ostream& out);

// tumble joint remove, motor: one request each, printing the tick it takes effect.
std::optional<client::Failure> run_joint_remove(const GlobalOptions& global, const JointRemoveCommand& command,
                                                std::ostream& out);
std::optional<client::Failure> run_motor(const GlobalOptions& global, const MotorCommand& command, std::ostream& out);

}  // namespace tumble::cli
