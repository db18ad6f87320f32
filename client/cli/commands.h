// The `tumble` subcommands: each connects, does one thing and writes what
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

// Runs whichever command `invocation` holds.
std::optional<client::Failure> run(const Invocation& invocation, std::ostream& out);

// tumble bodies: lists every body.
std::optional<client::Failure> run_bodies(const GlobalOptions& global, std::ostream& out);

// tumble force: one ApplyForce, prints the tick it takes effect.
std::optional<client::Failure> run_force(const GlobalOptions& global, const ForceCommand& command, std::ostream& out);

// tumble torque: one ApplyTorque, prints the tick it takes effect.
std::optional<client::Failure> run_torque(const GlobalOptions& global, const TorqueCommand& command,
                                          std::ostream& out);

// tumble impulse: one ApplyImpulse, prints the tick it takes effect.
std::optional<client::Failure> run_impulse(const GlobalOptions& global, const ImpulseCommand& command,
                                           std::ostream& out);

// tumble subscribe: lists the bodies once (for their names), subscribes,
// then prints each frame of its subscription as it arrives, flushed. Ends
// with success after `count` frames or on SIGINT/SIGTERM (caught from the
// moment the subscription stands); fails when the server sends an Error or
// closes the connection.
std::optional<client::Failure> run_subscribe(const GlobalOptions& global, const SubscribeCommand& command,
                                             std::ostream& out);

}  // namespace tumble::cli
