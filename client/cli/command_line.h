// The `tumble` command line, parsed into plain values.
//
//   tumble [--server HOST:PORT | --nats URL[,URL...] [--world NAME] [--nats-creds FILE]]
//          [--json] [--token TOKEN] [--timeout SECONDS] COMMAND ...
//     bodies
//     force BODY --force FX FY FZ [--at PX PY PZ [--local]] [--duration S | --ticks N | --persistent]
//     torque BODY --torque TX TY TZ [--duration S | --ticks N | --persistent]
//     impulse BODY --impulse JX JY JZ [--at PX PY PZ [--local]]
//     subscribe [--bodies A,B,...] [--rate HZ] [--count N] [--fields pose|all]
//               [--encoding full|quantized|delta] [--events] [--reconnect [--reconnect-max-wait S]]
//     spawn NAME (--box HX HY HZ | --sphere R | --capsule R HH) [--mass M] [--at X Y Z]
//           [--orientation W X Y Z] [--velocity VX VY VZ] [--angular-velocity WX WY WZ]
//           [--static | --kinematic] [--friction F] [--restitution E]
//     remove BODY
//     set BODY [--position X Y Z] [--orientation W X Y Z] [--velocity VX VY VZ] [--angular-velocity WX WY WZ]
//     clear [BODY]
//     pause | resume | reset | stats
//     step [N]
//     tick-rate HZ
//     watch [--bodies A,B,...] [--rate HZ] [--count N] [--encoding full|quantized|delta]
//     joints
//     joint add NAME (--hinge | --ball | --slider | --fixed | --distance) BODY_A BODY_B [--anchor X Y Z]
//           [--anchor-b X Y Z] [--axis X Y Z] [--limits LO HI] [--cone C] [--min-length L] [--max-length L]
//           [--length L] [--break-force F] [--break-torque T] [--collide-connected]
//     joint remove JOINT
//     motor JOINT ((--speed S | --position P [--hertz F] [--damping-ratio Z]) (--max-torque T | --max-force F)
//                  | --off)
//     worlds                                     (NATS only)
//
// Over NATS (--nats), subscribe and watch read a stream the server
// publishes (--stream NAME, default the world's first): its rate, encoding
// and fields apply, so --rate, --encoding, --fields and --bodies are
// refused there.
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

#include "reconnect_policy.h"
#include "tumble/endpoint.h"
#include "tumble/v1/protocol.pb.h"
#include "tumble_client/connection.h"

namespace tumble::cli {

// Options written before the subcommand.
struct GlobalOptions {
  Endpoint server;                                           // --server, else $TUMBLE_SERVER, else 127.0.0.1:7400
  std::vector<std::string> nats;                             // --nats, else $TUMBLE_NATS; empty: TCP to `server`
  std::string world;                                         // --world, else $TUMBLE_WORLD; with `nats` only
  std::string nats_credentials;                              // --nats-creds FILE; with `nats` only
  std::string token;                                         // --token, else $TUMBLE_TOKEN
  client::Timeout timeout = client::kDefaultRequestTimeout;  // --timeout: connecting, and each request
  bool json = false;                                         // --json: one JSON object per line
};

// x, y, z as typed.
using Vector3 = std::array<double, 3>;

// w, x, y, z as typed.
using Quaternion = std::array<double, 4>;

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
  Vector3 force{};            // N, world frame
  std::optional<Vector3> at;  // m; world frame, or body frame when `local`
  bool local = false;         // only with `at`
  Duration duration;
  bool persistent = false;  // every tick until cleared; never with a duration
};

// tumble torque
struct TorqueCommand {
  tumble::v1::BodyRef body;
  Vector3 torque{};  // N m, world frame
  Duration duration;
  bool persistent = false;  // every tick until cleared; never with a duration
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
  bool poses_only = false;                  // --fields pose: no velocities
  bool joints = false;                      // --fields ...,joints: every joint's state too
  tumble::v1::PoseEncoding encoding = tumble::v1::POSE_ENCODING_FULL;       // --encoding
  bool events = false;                                                      // --events: every kind of WorldEvent too
  std::string stream;                                                       // --stream: over NATS; "" for the first
  bool reconnect = false;                                                   // --reconnect: ride out lost connections
  std::chrono::milliseconds reconnect_max_wait = kReconnectDefaultMaxWait;  // --reconnect-max-wait
};

// tumble spawn
struct SpawnCommand {
  std::string name;                       // may be empty; never digits only (it would read as an id)
  tumble::v1::Shape shape;                // box, sphere or capsule
  double mass = 1;                        // kg; ignored by the server unless dynamic
  Vector3 position{};                     // m, centre of mass, world frame (--at)
  std::optional<Quaternion> orientation;  // identity when absent
  Vector3 linear_velocity{};              // m/s, world frame
  Vector3 angular_velocity{};             // rad/s, world frame
  tumble::v1::Motion motion = tumble::v1::MOTION_DYNAMIC;
  std::optional<double> friction;     // the server's default when absent
  std::optional<double> restitution;  // the server's default when absent
};

// tumble remove
struct RemoveCommand {
  tumble::v1::BodyRef body;
};

// tumble set: the parts given replace the body's; the others stay.
struct SetCommand {
  tumble::v1::BodyRef body;
  std::optional<Vector3> position;  // m
  std::optional<Quaternion> orientation;
  std::optional<Vector3> linear_velocity;   // m/s
  std::optional<Vector3> angular_velocity;  // rad/s
};

// tumble clear
struct ClearCommand {
  std::optional<tumble::v1::BodyRef> body;  // none: every body
};

// tumble pause
struct PauseCommand {};

// tumble resume
struct ResumeCommand {};

// tumble step
struct StepCommand {
  std::uint32_t ticks = 1;
};

// tumble reset
struct ResetCommand {};

// tumble tick-rate
struct TickRateCommand {
  double rate_hz = 0;
};

// tumble stats
struct StatsCommand {};

// tumble watch
struct WatchCommand {
  std::vector<tumble::v1::BodyRef> bodies;  // empty: every body
  double rate_hz = 10;                      // tables per second; 0: every tick
  std::optional<std::uint64_t> count;       // stop after this many tables; none: until interrupted
  tumble::v1::PoseEncoding encoding = tumble::v1::POSE_ENCODING_FULL;  // --encoding
  std::string stream;                                                  // --stream: over NATS; "" for the first
};

// tumble worlds: every world answering over NATS.
struct WorldsCommand {};

// tumble joints
struct JointsCommand {};

// tumble joint add: the fields of a JointSpec (scene.proto), as typed.
struct JointAddCommand {
  std::string name;  // may be empty; never digits only (it would read as an id)
  tumble::v1::JointType type = tumble::v1::JOINT_TYPE_UNSPECIFIED;
  std::string body_a;                           // a name, an id, or "world"
  std::string body_b;                           // a name or an id
  std::optional<Vector3> anchor;                // m, world frame; a distance joint's point on body A
  std::optional<Vector3> anchor_b;              // m, a distance joint's point on body B
  std::optional<Vector3> axis;                  // world direction
  std::optional<std::array<double, 2>> limits;  // rad or m: lower, upper
  std::optional<double> cone_limit;             // rad
  std::optional<double> min_length;             // m
  std::optional<double> max_length;             // m
  std::optional<double> length;                 // m
  std::optional<double> break_force;            // N
  std::optional<double> break_torque;           // N m
  std::optional<double> friction;               // N m (ball, hinge) or N (slider)
  bool collide_connected = false;
};

// tumble joint remove
struct JointRemoveCommand {
  tumble::v1::JointRef joint;
};

// tumble motor: a motor to drive the joint with, or none to turn it off (--off).
struct MotorCommand {
  tumble::v1::JointRef joint;
  std::optional<tumble::v1::JointMotorSpec> motor;
};

using Command = std::variant<BodiesCommand, ForceCommand, TorqueCommand, ImpulseCommand, SubscribeCommand, SpawnCommand,
                             RemoveCommand, SetCommand, ClearCommand, PauseCommand, ResumeCommand, StepCommand,
                             ResetCommand, TickRateCommand, StatsCommand, WatchCommand, WorldsCommand, JointsCommand,
                             JointAddCommand, JointRemoveCommand, MotorCommand>;

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

// Parses argv (argv[0] is the program). Reads $TUMBLE_SERVER,
// $TUMBLE_TOKEN, $TUMBLE_NATS and $TUMBLE_WORLD for options not given.
// Never prints and never exits.
ParsedCommandLine parse_command_line(int argc, const char* const* argv);

}  // namespace tumble::cli
