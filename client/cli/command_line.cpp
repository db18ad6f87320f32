#include "command_line.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <variant>

#include <CLI/CLI.hpp>

#include "exit_code.h"
#include "tumble/version.h"
#include "tumble_client/body_ref.h"
#include "tumble_client/nats_subjects.h"

namespace tumble::cli {
namespace {

// The longest --timeout accepted, in seconds; well inside what a
// steady_clock duration holds.
constexpr double kMaxTimeoutSeconds = 1e6;

// A CLI11 check: the empty string when `text` is acceptable, else why not.
std::string check_endpoint(const std::string& text) { return parse_endpoint(text).error; }

std::string check_body(const std::string& text) {
  auto ref = client::parse_body_ref(text);
  return ref ? std::string() : ref.failure().message;
}

std::string check_joint(const std::string& text) {
  auto ref = client::parse_joint_ref(text);
  return ref ? std::string() : ref.failure().message;
}

std::string check_timeout(const std::string& text) {
  char* end = nullptr;
  const double seconds = std::strtod(text.c_str(), &end);
  const bool whole = !text.empty() && end == text.c_str() + text.size();
  if (whole && std::isfinite(seconds) && seconds > 0 && seconds <= kMaxTimeoutSeconds) return {};
  return "the timeout must be a number of seconds greater than 0 and at most 1e6, got '" + text + "'";
}

client::Timeout timeout_from_seconds(double seconds) {
  return std::chrono::duration_cast<client::Timeout>(std::chrono::duration<double>(seconds));
}

std::string check_world(const std::string& text) { return client::world_name_problem(text); }

std::string check_stream(const std::string& text) { return client::stream_name_problem(text); }

std::string check_nats_url(const std::string& text) {
  return text.empty() ? std::string("a NATS URL may not be empty (nats://HOST:PORT)") : std::string();
}

// The --stream of subscribe and watch, into `name`.
CLI::Option* add_stream_option(CLI::App& command, std::string& name) {
  return command
      .add_option("--stream", name,
                  "Over NATS: the stream to read, as `tumble worlds` lists them; default the world's first. "
                  "Its rate, encoding and fields apply")
      ->type_name("NAME")
      ->check(check_stream);
}

// Over NATS the stream fixes what these flags choose over TCP: the first
// one given, as a usage error; "" when none.
std::string stream_conflict(std::initializer_list<const CLI::Option*> options) {
  for (const CLI::Option* option : options) {
    if (option->count() > 0) {
      return option->get_name() +
             ": over NATS the stream decides the rate, encoding, fields and bodies; choose a stream with --stream "
             "(tumble worlds lists them)";
    }
  }
  return {};
}

// A name for a new body: anything but digits only, which every command
// would read as an id.
std::string check_new_name(const std::string& text) {
  const bool digits_only = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  return digits_only ? "a body name of digits only would read as an id, got '" + text + "'" : std::string();
}

// The --encoding of subscribe and watch, into `name`; pose_encoding() reads it.
CLI::Option* add_encoding_option(CLI::App& command, std::string& name) {
  return command
      .add_option("--encoding", name,
                  "full: float32; quantized: 1/1024 m grid, 32-bit orientations; delta: quantized, changes only")
      ->capture_default_str()
      ->check(CLI::IsMember({"full", "quantized", "delta"}));
}

tumble::v1::PoseEncoding pose_encoding(const std::string& name) {
  return name == "quantized" ? tumble::v1::POSE_ENCODING_QUANTIZED
         : name == "delta"   ? tumble::v1::POSE_ENCODING_DELTA
                             : tumble::v1::POSE_ENCODING_FULL;
}

// The value of an option that may be left out.
template <typename T>
std::optional<T> given(const CLI::Option* option, const T& value) {
  return option->count() > 0 ? std::optional<T>(value) : std::nullopt;
}

// A body reference that check_body accepted.
tumble::v1::BodyRef body_ref(const std::string& text) { return client::parse_body_ref(text).value(); }

// A joint reference that check_joint accepted.
tumble::v1::JointRef joint_ref(const std::string& text) { return client::parse_joint_ref(text).value(); }

// A name for a new joint: as for a body, digits only would read as an id.
std::string check_new_joint_name(const std::string& text) {
  const bool digits_only = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  return digits_only ? "a joint name of digits only would read as an id, got '" + text + "'" : std::string();
}

// The options of `joint add`, read into a JointAddCommand by command().
struct JointArguments {
  std::string name;
  std::string body_a;
  std::string body_b;
  Vector3 anchor{};
  Vector3 anchor_b{};
  Vector3 axis{};
  std::array<double, 2> limits{};
  double cone = 0;
  double min_length = 0;
  double max_length = 0;
  double length = 0;
  double break_force = 0;
  double break_torque = 0;
  double friction = 0;
  bool collide_connected = false;
  std::array<bool, 5> types{};        // --ball, --hinge, --slider, --fixed, --distance
  std::vector<CLI::Option*> options;  // by the order of the fields above, from anchor on

  void add(CLI::App& command) {
    command.add_option("NAME", name, "Name of the new joint; unique; \"\" for none")
        ->required()
        ->check(check_new_joint_name);
    auto* type = command.add_option_group("type", "What the joint leaves free");
    type->add_flag("--ball", types[0], "Anchors together, any rotation (optionally within --cone)");
    type->add_flag("--hinge", types[1], "Anchors together, rotation about --axis only");
    type->add_flag("--slider", types[2], "No rotation, translation along --axis only");
    type->add_flag("--fixed", types[3], "The bodies move as one");
    type->add_flag("--distance", types[4],
                   "The anchors' distance held (rigid, or within --min-length .. --max-length)");
    type->require_option(1);
    command.add_option("BODY_A", body_a, "Body name, id when all digits, or world")->required();
    command.add_option("BODY_B", body_b, "Body name, or id when all digits")->required()->check(check_body);
    options = {
        command
            .add_option("--anchor", anchor, "The point the bodies share (m), world frame; a distance joint's on BODY_A")
            ->type_name("X Y Z"),
        command.add_option("--anchor-b", anchor_b, "A distance joint's point on BODY_B (m), world frame")
            ->type_name("X Y Z"),
        command.add_option("--axis", axis, "The hinge's or slider's axis, the ball's cone axis; world frame")
            ->type_name("X Y Z"),
        command.add_option("--limits", limits, "Lower and upper angle (rad, hinge) or position (m, slider)")
            ->type_name("LO HI"),
        command.add_option("--cone", cone, "A ball joint's largest angle from its axis (rad)")->type_name("C"),
        command.add_option("--min-length", min_length, "A distance joint's shortest (m)")->type_name("L"),
        command.add_option("--max-length", max_length, "A distance joint's longest (m)")->type_name("L"),
        command.add_option("--length", length, "A distance joint's rest length (m)")->type_name("L"),
        command.add_option("--break-force", break_force, "Force (N) above which the joint breaks")->type_name("F"),
        command.add_option("--break-torque", break_torque, "Torque (N m) above which the joint breaks")->type_name("T"),
        command
            .add_option("--friction", friction,
                        "Torque (N m; ball, hinge) or force (N; slider) with which the joint resists moving")
            ->type_name("F"),
    };
    command.add_flag("--collide-connected", collide_connected, "The two bodies still collide with each other");
  }

  JointAddCommand command() const {
    JointAddCommand out;
    out.name = name;
    constexpr std::array kTypes = {tumble::v1::JOINT_TYPE_BALL, tumble::v1::JOINT_TYPE_HINGE,
                                   tumble::v1::JOINT_TYPE_SLIDER, tumble::v1::JOINT_TYPE_FIXED,
                                   tumble::v1::JOINT_TYPE_DISTANCE};
    for (std::size_t i = 0; i < types.size(); ++i) {
      if (types[i]) out.type = kTypes[i];
    }
    out.body_a = body_a;
    out.body_b = body_b;
    out.anchor = given(options[0], anchor);
    out.anchor_b = given(options[1], anchor_b);
    out.axis = given(options[2], axis);
    out.limits = given(options[3], limits);
    out.cone_limit = given(options[4], cone);
    out.min_length = given(options[5], min_length);
    out.max_length = given(options[6], max_length);
    out.length = given(options[7], length);
    out.break_force = given(options[8], break_force);
    out.break_torque = given(options[9], break_torque);
    out.friction = given(options[10], friction);
    out.collide_connected = collide_connected;
    return out;
  }
};

// The options of `motor`.
struct MotorArguments {
  std::string joint;
  double speed = 0;
  double position = 0;
  double hertz = 0;
  double damping_ratio = 0;
  double max_torque = 0;
  double max_force = 0;
  bool off = false;
  CLI::Option* speed_option = nullptr;
  CLI::Option* position_option = nullptr;
  CLI::Option* hertz_option = nullptr;
  CLI::Option* damping_option = nullptr;
  CLI::Option* max_torque_option = nullptr;
  CLI::Option* max_force_option = nullptr;

  void add(CLI::App& command) {
    command.add_option("JOINT", joint, "Joint name, or id when all digits")->required()->check(check_joint);
    speed_option = command.add_option("--speed", speed, "Drive the joint at this speed (rad/s or m/s)")->type_name("S");
    position_option = command.add_option("--position", position, "Drive the joint to this angle (rad) or position (m)")
                          ->type_name("P")
                          ->excludes(speed_option);
    hertz_option = command.add_option("--hertz", hertz, "With --position: the drive's stiffness (Hz), default 2")
                       ->type_name("F")
                       ->needs(position_option);
    damping_option =
        command.add_option("--damping-ratio", damping_ratio, "With --position: the drive's damping, default 1")
            ->type_name("Z")
            ->needs(position_option);
    max_torque_option =
        command.add_option("--max-torque", max_torque, "A hinge's motor: the most torque (N m)")->type_name("T");
    max_force_option = command.add_option("--max-force", max_force, "A slider's motor: the most force (N)")
                           ->type_name("F")
                           ->excludes(max_torque_option);
    command.add_flag("--off", off, "Turn the motor off")
        ->excludes(speed_option)
        ->excludes(position_option)
        ->excludes(max_torque_option)
        ->excludes(max_force_option);
  }

  // The command, or a usage error when neither a drive nor --off is given.
  std::variant<MotorCommand, std::string> command() const {
    MotorCommand out;
    out.joint = joint_ref(joint);
    if (off) return out;
    if (speed_option->count() == 0 && position_option->count() == 0) {
      return std::string("motor: give --speed S or --position P (with --max-torque or --max-force), or --off");
    }
    if (max_torque_option->count() == 0 && max_force_option->count() == 0) {
      return std::string("motor: give --max-torque T for a hinge or --max-force F for a slider");
    }
    tumble::v1::JointMotorSpec motor;
    if (speed_option->count() > 0) motor.set_speed(speed);
    if (position_option->count() > 0) motor.set_position(position);
    if (hertz_option->count() > 0) motor.set_hertz(hertz);
    if (damping_option->count() > 0) motor.set_damping_ratio(damping_ratio);
    if (max_torque_option->count() > 0) motor.set_max_torque(max_torque);
    if (max_force_option->count() > 0) motor.set_max_force(max_force);
    out.motor = std::move(motor);
    return out;
  }
};

// Options of `set` and `spawn` that give a body's state.
struct StateArguments {
  Vector3 position{};
  Quaternion orientation{};
  Vector3 linear_velocity{};
  Vector3 angular_velocity{};
  CLI::Option* position_option = nullptr;
  CLI::Option* orientation_option = nullptr;
  CLI::Option* linear_velocity_option = nullptr;
  CLI::Option* angular_velocity_option = nullptr;

  // `position_flag` is --position for `set`, --at for `spawn`.
  void add(CLI::App& command, const std::string& position_flag) {
    position_option = command.add_option(position_flag, position, "Position of the centre of mass (m), world frame")
                          ->type_name("X Y Z");
    orientation_option =
        command.add_option("--orientation", orientation, "Orientation, a unit quaternion body to world")
            ->type_name("W X Y Z");
    linear_velocity_option =
        command.add_option("--velocity", linear_velocity, "Linear velocity (m/s), world frame")->type_name("VX VY VZ");
    angular_velocity_option =
        command.add_option("--angular-velocity", angular_velocity, "Angular velocity (rad/s), world frame")
            ->type_name("WX WY WZ");
  }
};

// The options a force, torque or impulse subcommand shares. Each add_*
// declares some of them; point() and duration() need theirs declared.
struct BodyArguments {
  std::string body;
  Vector3 vector{};
  Vector3 at{};
  bool local = false;
  double seconds = 0;
  std::uint32_t ticks = 0;
  bool persistent = false;
  CLI::Option* at_option = nullptr;
  CLI::Option* seconds_option = nullptr;
  CLI::Option* ticks_option = nullptr;

  void add_body(CLI::App& command) {
    command.add_option("BODY", body, "Body name, or id when all digits")->required()->check(check_body);
  }
  void add_vector(CLI::App& command, const std::string& name, const std::string& components, const std::string& help) {
    command.add_option(name, vector, help)->required()->type_name(components);
  }
  void add_point(CLI::App& command) {
    at_option = command
                    .add_option("--at", at,
                                "Point of application (m), world frame unless --local; "
                                "centre of mass when absent")
                    ->type_name("PX PY PZ");
    command.add_flag("--local", local, "--at is in the body frame, relative to the centre of mass")->needs(at_option);
  }
  void add_duration(CLI::App& command) {
    seconds_option =
        command.add_option("--duration", seconds, "Seconds to apply for (rounded to whole ticks)")->type_name("S");
    ticks_option = command.add_option("--ticks", ticks, "Ticks to apply for")->type_name("N");
    seconds_option->excludes(ticks_option);
    command.add_flag("--persistent", persistent, "Apply at every tick until `tumble clear`")
        ->excludes(seconds_option)
        ->excludes(ticks_option);
  }

  std::optional<Vector3> point() const { return at_option->count() > 0 ? std::optional(at) : std::nullopt; }
  Duration duration() const {
    Duration out;
    if (seconds_option->count() > 0) out.seconds = seconds;
    if (ticks_option->count() > 0) out.ticks = ticks;
    return out;
  }
};

// CLI11's messages, folded onto one line.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

ParsedCommandLine parse_command_line(int argc, const char* const* argv) {
  CLI::App app{"tumble: command-line client of the tumble rigid-body simulation server"};
  app.name("tumble");
  app.require_subcommand(1);
  app.set_version_flag("--version", kVersion);
  app.footer(
      "Environment: TUMBLE_SERVER, TUMBLE_TOKEN, TUMBLE_NATS and TUMBLE_WORLD stand in for --server, --token,\n"
      "--nats and --world.\n"
      "Exit status: 0 success, 1 failure (server error, not permitted, connection, timeout), 2 usage error.");

  std::string server = to_string(default_endpoint());
  std::string token;
  double timeout_seconds = 10;
  bool json = false;
  app.add_option("--server", server, "Server address, HOST:PORT ([::1]:7400 for IPv6)")
      ->envname("TUMBLE_SERVER")
      ->capture_default_str()
      ->check(check_endpoint);
  app.add_option("--token", token, "Access token sent in Hello")->envname("TUMBLE_TOKEN");
  std::vector<std::string> nats;
  std::string world;
  std::string nats_credentials;
  app.add_option("--nats", nats,
                 "Reach the world through NATS instead of --server: NATS server URLs, comma-separated "
                 "(nats://[USER:PASSWORD@]HOST:PORT, tls://...)")
      ->envname("TUMBLE_NATS")
      ->delimiter(',')
      ->type_name("URL[,URL...]")
      ->check(check_nats_url);
  CLI::Option* world_option =
      app.add_option("--world", world, "With --nats: the world's name")->envname("TUMBLE_WORLD")->check(check_world);
  CLI::Option* credentials_option =
      app.add_option("--nats-creds", nats_credentials, "With --nats: a NATS credentials file (.creds)")
          ->type_name("FILE")
          ->check(CLI::ExistingFile);
  app.add_option("--timeout", timeout_seconds, "Seconds to wait for the connection and for each reply")
      ->capture_default_str()
      ->type_name("SECONDS")
      ->check(check_timeout);
  app.add_flag("--json", json, "Print one JSON object per line");

  CLI::App* bodies = app.add_subcommand("bodies", "List every body: id, name, shape, mass, position, speed, asleep");

  CLI::App* force = app.add_subcommand("force", "Apply a force (N, world frame) to a body");
  BodyArguments force_args;
  force_args.add_body(*force);
  force_args.add_vector(*force, "--force", "FX FY FZ", "Force (N), world frame");
  force_args.add_point(*force);
  force_args.add_duration(*force);

  CLI::App* torque = app.add_subcommand("torque", "Apply a torque (N m, world frame) to a body");
  BodyArguments torque_args;
  torque_args.add_body(*torque);
  torque_args.add_vector(*torque, "--torque", "TX TY TZ", "Torque (N m), world frame");
  torque_args.add_duration(*torque);

  CLI::App* impulse = app.add_subcommand("impulse", "Apply an impulse (N s, world frame) to a body at once");
  BodyArguments impulse_args;
  impulse_args.add_body(*impulse);
  impulse_args.add_vector(*impulse, "--impulse", "JX JY JZ", "Impulse (N s), world frame");
  impulse_args.add_point(*impulse);

  CLI::App* subscribe = app.add_subcommand("subscribe", "Print body poses as the world steps");
  std::vector<std::string> subscribe_bodies;
  double rate_hz = 30;
  std::uint64_t count = 0;
  std::string fields = "all";
  std::string encoding = "full";
  bool events = false;
  CLI::Option* subscribe_bodies_option =
      subscribe
          ->add_option("--bodies", subscribe_bodies, "Bodies to follow, names or ids, comma-separated; all when absent")
          ->delimiter(',')
          ->type_name("A,B,...")
          ->check(check_body);
  CLI::Option* rate_option = subscribe->add_option("--rate", rate_hz, "Frames per second; 0 for every tick")
                                 ->capture_default_str()
                                 ->type_name("HZ");
  CLI::Option* count_option =
      subscribe->add_option("--count", count, "Exit after this many frames; run until interrupted when absent")
          ->type_name("N")
          ->check(CLI::Range(std::uint64_t{1}, std::numeric_limits<std::uint64_t>::max()));
  CLI::Option* fields_option =
      subscribe
          ->add_option("--fields", fields,
                       "pose: positions and orientations; all: velocities too; either with ,joints (or joints "
                       "alone, for pose,joints): every joint's state too")
          ->capture_default_str()
          ->check(CLI::IsMember({"pose", "all", "joints", "pose,joints", "all,joints"}));
  CLI::Option* encoding_option = add_encoding_option(*subscribe, encoding);
  std::string subscribe_stream;
  CLI::Option* subscribe_stream_option = add_stream_option(*subscribe, subscribe_stream);
  subscribe->add_flag("--events", events,
                      "Also print bodies spawned, removed, falling asleep, waking, joints added, removed, broken, "
                      "and resets");
  bool reconnect = false;
  double reconnect_max_wait = std::chrono::duration<double>(kReconnectDefaultMaxWait).count();
  CLI::Option* reconnect_option = subscribe->add_flag(
      "--reconnect", reconnect,
      "When the connection is lost or refused, say why on stderr and try again, waiting 0.1 s, then twice as long "
      "each time (with jitter), and subscribe again");
  subscribe->add_option("--reconnect-max-wait", reconnect_max_wait, "Longest wait between two attempts to reconnect")
      ->capture_default_str()
      ->type_name("S")
      ->check(CLI::Range(0.01, 3600.0))
      ->needs(reconnect_option);

  CLI::App* spawn = app.add_subcommand("spawn", "Add a body to the world");
  std::string spawn_name;
  Vector3 box{};
  double sphere = 0;
  std::array<double, 2> capsule{};
  double mass = 1;
  bool is_static = false;
  bool is_kinematic = false;
  double friction = 0;
  double restitution = 0;
  StateArguments spawn_state;
  spawn->add_option("NAME", spawn_name, "Name of the new body; unique; \"\" for none")
      ->required()
      ->check(check_new_name);
  auto* shape = spawn->add_option_group("shape", "What the body is");
  CLI::Option* box_option =
      shape->add_option("--box", box, "Solid box of these half extents (m)")->type_name("HX HY HZ");
  CLI::Option* sphere_option = shape->add_option("--sphere", sphere, "Solid sphere of this radius (m)")->type_name("R");
  CLI::Option* capsule_option =
      shape->add_option("--capsule", capsule, "Capsule of radius R around a segment of half length HH (m) along y")
          ->type_name("R HH");
  shape->require_option(1);
  spawn->add_option("--mass", mass, "Mass (kg) of a dynamic body")->capture_default_str()->type_name("M");
  spawn_state.add(*spawn, "--at");
  CLI::Option* static_option = spawn->add_flag("--static", is_static, "Never moves");
  spawn->add_flag("--kinematic", is_kinematic, "Moves with its velocities, pushes others, ignores forces")
      ->excludes(static_option);
  CLI::Option* friction_option =
      spawn->add_option("--friction", friction, "Coulomb friction coefficient, >= 0")->type_name("F");
  CLI::Option* restitution_option =
      spawn->add_option("--restitution", restitution, "Bounciness, 0 (none) to 1 (elastic)")->type_name("E");

  CLI::App* remove = app.add_subcommand("remove", "Take a body out of the world");
  std::string remove_body;
  remove->add_option("BODY", remove_body, "Body name, or id when all digits")->required()->check(check_body);

  CLI::App* set = app.add_subcommand("set", "Overwrite parts of a body's state and wake it; the rest stays");
  std::string set_body;
  StateArguments set_state;
  set->add_option("BODY", set_body, "Body name, or id when all digits")->required()->check(check_body);
  set_state.add(*set, "--position");

  CLI::App* clear = app.add_subcommand("clear", "End the forces and torques of a body, or of every body");
  std::string clear_body;
  CLI::Option* clear_body_option =
      clear->add_option("BODY", clear_body, "Body name, or id when all digits; every body when absent")
          ->check(check_body);

  CLI::App* pause = app.add_subcommand("pause", "Stop stepping; commands and subscriptions go on");
  CLI::App* resume = app.add_subcommand("resume", "Step at the tick rate again");
  CLI::App* step = app.add_subcommand("step", "While paused, step N ticks (default 1) and print the last");
  std::uint32_t step_ticks = 1;
  step->add_option("N", step_ticks, "Ticks to step")->capture_default_str();
  CLI::App* reset = app.add_subcommand("reset", "Put the world back to the scene it was loaded from");
  CLI::App* tick_rate = app.add_subcommand("tick-rate", "Change the simulation's steps per second");
  double tick_rate_hz = 0;
  tick_rate->add_option("HZ", tick_rate_hz, "Steps per second, 1 to 10000")->required();
  CLI::App* stats = app.add_subcommand("stats", "Show the server's tick, load, bodies and clients");

  CLI::App* watch = app.add_subcommand("watch", "A live table of the bodies: name, position, speed, asleep");
  std::vector<std::string> watch_bodies;
  double watch_rate_hz = 10;
  std::uint64_t watch_count = 0;
  CLI::Option* watch_bodies_option =
      watch->add_option("--bodies", watch_bodies, "Bodies to show, names or ids, comma-separated; all when absent")
          ->delimiter(',')
          ->type_name("A,B,...")
          ->check(check_body);
  CLI::Option* watch_rate_option = watch->add_option("--rate", watch_rate_hz, "Tables per second; 0 for every tick")
                                       ->capture_default_str()
                                       ->type_name("HZ");
  CLI::Option* watch_count_option =
      watch->add_option("--count", watch_count, "Exit after this many tables; run until interrupted when absent")
          ->type_name("N")
          ->check(CLI::Range(std::uint64_t{1}, std::numeric_limits<std::uint64_t>::max()));
  std::string watch_encoding = "full";
  CLI::Option* watch_encoding_option = add_encoding_option(*watch, watch_encoding);
  std::string watch_stream;
  CLI::Option* watch_stream_option = add_stream_option(*watch, watch_stream);

  CLI::App* worlds =
      app.add_subcommand("worlds", "With --nats: list the worlds that answer (world, tick, rate, bodies, streams)");

  CLI::App* joints = app.add_subcommand("joints", "List every joint: id, name, type, bodies, position, speed, motor");
  CLI::App* joint = app.add_subcommand("joint", "Add or remove a joint");
  joint->require_subcommand(1);
  CLI::App* joint_add = joint->add_subcommand("add", "Join two bodies, or a body and the world, with a joint");
  JointArguments joint_args;
  joint_args.add(*joint_add);
  CLI::App* joint_remove = joint->add_subcommand("remove", "Take a joint out of the world");
  std::string joint_remove_ref;
  joint_remove->add_option("JOINT", joint_remove_ref, "Joint name, or id when all digits")
      ->required()
      ->check(check_joint);
  CLI::App* motor = app.add_subcommand("motor", "Drive a hinge or slider at a speed or to a position, or stop it");
  MotorArguments motor_args;
  motor_args.add(*motor);

  ParsedCommandLine parsed;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    std::ostringstream out;
    std::ostringstream err;
    parsed.exit_code = app.exit(error, out, err);
    if (parsed.exit_code == kExitSuccess) {
      parsed.text = out.str();
    } else {
      parsed.exit_code = kExitUsage;
      parsed.text = one_line(error.what());
    }
    return parsed;
  }

  // What CLI11 cannot say: which options go with --nats.
  const auto usage = [&parsed](std::string text) {
    parsed.exit_code = kExitUsage;
    parsed.text = std::move(text);
    return parsed;
  };
  if (nats.empty()) {
    if (app.got_subcommand(worlds)) return usage("worlds: lists the worlds served over NATS; give --nats URL");
    if (credentials_option->count() > 0) return usage("--nats-creds: goes with --nats");
    if (subscribe_stream_option->count() > 0 || watch_stream_option->count() > 0) {
      return usage("--stream: reads a stream published over NATS; give --nats URL and --world NAME");
    }
  } else {
    if (world_option->count() == 0 && !app.got_subcommand(worlds)) {
      return usage("--world: --nats needs the world's name (or $TUMBLE_WORLD); `tumble --nats " + nats.front() +
                   " worlds` lists them");
    }
    std::string conflict;
    if (app.got_subcommand(subscribe)) {
      conflict = stream_conflict({rate_option, fields_option, encoding_option, subscribe_bodies_option});
    } else if (app.got_subcommand(watch)) {
      conflict = stream_conflict({watch_rate_option, watch_encoding_option, watch_bodies_option});
    }
    if (!conflict.empty()) return usage(conflict);
  }

  Invocation invocation;
  invocation.global.server = *parse_endpoint(server).endpoint;
  invocation.global.token = token;
  invocation.global.timeout = timeout_from_seconds(timeout_seconds);
  invocation.global.json = json;
  invocation.global.nats = nats;
  invocation.global.world = nats.empty() ? std::string() : world;
  invocation.global.nats_credentials = nats_credentials;

  if (app.got_subcommand(bodies)) {
    invocation.command = BodiesCommand{};
  } else if (app.got_subcommand(force)) {
    ForceCommand command;
    command.body = body_ref(force_args.body);
    command.force = force_args.vector;
    command.at = force_args.point();
    command.local = force_args.local;
    command.duration = force_args.duration();
    command.persistent = force_args.persistent;
    invocation.command = std::move(command);
  } else if (app.got_subcommand(torque)) {
    TorqueCommand command;
    command.body = body_ref(torque_args.body);
    command.torque = torque_args.vector;
    command.duration = torque_args.duration();
    command.persistent = torque_args.persistent;
    invocation.command = std::move(command);
  } else if (app.got_subcommand(impulse)) {
    ImpulseCommand command;
    command.body = body_ref(impulse_args.body);
    command.impulse = impulse_args.vector;
    command.at = impulse_args.point();
    command.local = impulse_args.local;
    invocation.command = std::move(command);
  } else if (app.got_subcommand(subscribe)) {
    SubscribeCommand command;
    for (const std::string& name : subscribe_bodies) command.bodies.push_back(body_ref(name));
    command.rate_hz = rate_hz;
    if (count_option->count() > 0) command.count = count;
    command.poses_only = fields == "pose" || fields == "joints" || fields == "pose,joints";
    command.joints = fields.ends_with("joints");
    command.encoding = pose_encoding(encoding);
    command.events = events;
    command.stream = subscribe_stream;
    command.reconnect = reconnect;
    command.reconnect_max_wait =
        std::chrono::round<std::chrono::milliseconds>(std::chrono::duration<double>(reconnect_max_wait));
    invocation.command = std::move(command);
  } else if (app.got_subcommand(spawn)) {
    SpawnCommand command;
    command.name = spawn_name;
    if (box_option->count() > 0) {
      auto* half_extents = command.shape.mutable_box()->mutable_half_extents();
      half_extents->set_x(box[0]);
      half_extents->set_y(box[1]);
      half_extents->set_z(box[2]);
    } else if (sphere_option->count() > 0) {
      command.shape.mutable_sphere()->set_radius(sphere);
    } else if (capsule_option->count() > 0) {
      command.shape.mutable_capsule()->set_radius(capsule[0]);
      command.shape.mutable_capsule()->set_half_height(capsule[1]);
    }
    command.mass = mass;
    command.position = spawn_state.position;
    command.orientation = given(spawn_state.orientation_option, spawn_state.orientation);
    command.linear_velocity = spawn_state.linear_velocity;
    command.angular_velocity = spawn_state.angular_velocity;
    command.motion = is_static      ? tumble::v1::MOTION_STATIC
                     : is_kinematic ? tumble::v1::MOTION_KINEMATIC
                                    : tumble::v1::MOTION_DYNAMIC;
    command.friction = given(friction_option, friction);
    command.restitution = given(restitution_option, restitution);
    invocation.command = std::move(command);
  } else if (app.got_subcommand(remove)) {
    invocation.command = RemoveCommand{body_ref(remove_body)};
  } else if (app.got_subcommand(set)) {
    SetCommand command;
    command.body = body_ref(set_body);
    command.position = given(set_state.position_option, set_state.position);
    command.orientation = given(set_state.orientation_option, set_state.orientation);
    command.linear_velocity = given(set_state.linear_velocity_option, set_state.linear_velocity);
    command.angular_velocity = given(set_state.angular_velocity_option, set_state.angular_velocity);
    invocation.command = std::move(command);
  } else if (app.got_subcommand(clear)) {
    ClearCommand command;
    if (clear_body_option->count() > 0) command.body = body_ref(clear_body);
    invocation.command = std::move(command);
  } else if (app.got_subcommand(pause)) {
    invocation.command = PauseCommand{};
  } else if (app.got_subcommand(resume)) {
    invocation.command = ResumeCommand{};
  } else if (app.got_subcommand(step)) {
    invocation.command = StepCommand{step_ticks};
  } else if (app.got_subcommand(reset)) {
    invocation.command = ResetCommand{};
  } else if (app.got_subcommand(tick_rate)) {
    invocation.command = TickRateCommand{tick_rate_hz};
  } else if (app.got_subcommand(stats)) {
    invocation.command = StatsCommand{};
  } else if (app.got_subcommand(worlds)) {
    invocation.command = WorldsCommand{};
  } else if (app.got_subcommand(joints)) {
    invocation.command = JointsCommand{};
  } else if (joint->got_subcommand(joint_add)) {
    invocation.command = joint_args.command();
  } else if (joint->got_subcommand(joint_remove)) {
    invocation.command = JointRemoveCommand{joint_ref(joint_remove_ref)};
  } else if (app.got_subcommand(motor)) {
    auto command = motor_args.command();
    if (auto* problem = std::get_if<std::string>(&command)) return usage(*problem);
    invocation.command = std::get<MotorCommand>(std::move(command));
  } else {
    WatchCommand command;
    for (const std::string& name : watch_bodies) command.bodies.push_back(body_ref(name));
    command.rate_hz = watch_rate_hz;
    if (watch_count_option->count() > 0) command.count = watch_count;
    command.encoding = pose_encoding(watch_encoding);
    command.stream = watch_stream;
    invocation.command = std::move(command);
  }
  parsed.invocation = std::move(invocation);
  return parsed;
}

}  // namespace tumble::cli
