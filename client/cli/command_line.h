// The `tumble` command line, parsed into plain values.
//
//   tumble [--server HOST:PORT] [--json] [--token TOKEN] [--timeout SECONDS] COMMAND ...
//     bodies
//     force BODY --force FX FY FZ [--at PX PY PZ [--local]] [--duration S | --ticks N]
//     torque BODY --torque TX TY TZ [--duration S | --ticks N]
//     impulse BODY --impulse JX JY JZ [--at PX PY PZ [--local]]
//     subscribe [--bodies A,B,...] [--rate HZ] [--count N]
//
// Numbers that parse as floating point pass through unchecked, NaN and
// infinities included: judging them is the server's job.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "tumble/v1/protocol.pb.h"
#include "tumble_client/connection.h"
#include "tumble_client/endpoint.h"

namespace tumble::cli {

// Options written before the subcommand.
struct GlobalOptions {
  client::Endpoint server;                                   // --server, else $TUMBLE_SERVER, else 127.0.0.1:7400
  std::string token;                                         // --token, else $TUMBLE_TOKEN
  client::Timeout timeout = client::kDefaultRequestTimeout;  // --timeout: connecting, and each request
  bool json = false;                                         // --json: one JSON object per line
};

// x, y, z as typed.
using Vector3 = std::array<double, 3>;

// How long a force or torque lasts; with neither set, one tick.
struct Duration {
  std::optional<double> seconds;       // --duration
  std::optional<std::uint32_t> ticks;  // --ticks
};

// tumble bodies
struct BodiesCommand {};

// tumble force
struct ForceCommand {
  tumble::v1::BodyRef body;
  Vector3 force{};          // N, world frame
  std::optional<Vector3> at;  // m; world frame, or body frame when `local`
  bool local = false;       // only with `at`
  Duration duration;
};

// tumble torque
struct TorqueCommand {
  tumble::v1::BodyRef body;
  Vector3 torque{};  // N m, world frame
  Duration duration;
};

// tumble impulse
struct ImpulseCommand {
  tumble::v1::BodyRef body;
  Vector3 impulse{};          // N s, world frame
  std::optional<Vector3> at;  // m; world frame, or body frame when `local`
  bool local = false;         // only with `at`
};

// tumble subscribe
struct SubscribeCommand {
  std::vector<tumble::v1::BodyRef> bodies;  // empty: every body
  double rate_hz = 30;                      // 0: every tick
  std::optional<std::uint64_t> count;       // stop after this many frames; none: until interrupted
};

using Command = std::variant<BodiesCommand, ForceCommand, TorqueCommand, ImpulseCommand, SubscribeCommand>;

// A command to run and the options to run it with.
struct Invocation {
  GlobalOptions global;
  Command command;
};

// What the command line came to: either an invocation, or an exit.
struct ParsedCommandLine {
  std::optional<Invocation> invocation;
  // Without an invocation: kExitSuccess after --help or --version, with
  // `text` for standard output; kExitUsage for a usage error, with `text`
  // the one-line reason (no "tumble: " prefix, no newline).
  int exit_code = 0;
  std::string text;
};

// Parses argv (argv[0] is the program). Reads $TUMBLE_SERVER and
// $TUMBLE_TOKEN for options not given. Never prints and never exits.
ParsedCommandLine parse_command_line(int argc, const char* const* argv);

}  // namespace tumble::cli
