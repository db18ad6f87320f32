#include "command_line.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include <CLI/CLI.hpp>

#include "exit_code.h"
#include "tumble_client/body_ref.h"

namespace tumble::cli {
namespace {

// The longest --timeout accepted, in seconds; well inside what a
// steady_clock duration holds.
constexpr double kMaxTimeoutSeconds = 1e6;

// A CLI11 check: the empty string when `text` is acceptable, else why not.
std::string check_endpoint(const std::string& text) {
  auto endpoint = client::parse_endpoint(text);
  return endpoint ? std::string() : endpoint.failure().message;
}

std::string check_body(const std::string& text) {
  auto ref = client::parse_body_ref(text);
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

// A body reference that check_body accepted.
tumble::v1::BodyRef body_ref(const std::string& text) { return client::parse_body_ref(text).value(); }

// The options a force, torque or impulse subcommand shares. Each add_*
// declares some of them; point() and duration() need theirs declared.
struct BodyArguments {
  std::string body;
  Vector3 vector{};
  Vector3 at{};
  bool local = false;
  double seconds = 0;
  std::uint32_t ticks = 0;
  CLI::Option* at_option = nullptr;
  CLI::Option* seconds_option = nullptr;
  CLI::Option* ticks_option = nullptr;

  void add_body(CLI::App& command) {
    command.add_option("BODY", body, "Body name, or id when all digits")->required()->check(check_body);
  }
  void add_vector(CLI::App& command, const std::string& name, const std::string& components,
                  const std::string& help) {
    command.add_option(name, vector, help)->required()->type_name(components);
  }
  void add_point(CLI::App& command) {
    at_option = command.add_option("--at", at, "Point of application (m), world frame unless --local; "
                                               "centre of mass when absent")
                    ->type_name("PX PY PZ");
    command.add_flag("--local", local, "--at is in the body frame, relative to the centre of mass")
        ->needs(at_option);
  }
  void add_duration(CLI::App& command) {
    seconds_option = command.add_option("--duration", seconds, "Seconds to apply for (rounded to whole ticks)")
                         ->type_name("S");
    ticks_option = command.add_option("--ticks", ticks, "Ticks to apply for")->type_name("N");
    seconds_option->excludes(ticks_option);
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
  app.set_version_flag("--version", TUMBLE_VERSION);
  app.footer(
      "Environment: TUMBLE_SERVER and TUMBLE_TOKEN stand in for --server and --token.\n"
      "Exit status: 0 success, 1 failure (server error, connection, timeout), 2 usage error.");

  std::string server(client::kDefaultServer);
  std::string token;
  double timeout_seconds = 10;
  bool json = false;
  app.add_option("--server", server, "Server address, HOST:PORT ([::1]:7400 for IPv6)")
      ->envname("TUMBLE_SERVER")
      ->capture_default_str()
      ->check(check_endpoint);
  app.add_option("--token", token, "Access token sent in Hello")->envname("TUMBLE_TOKEN");
  app.add_option("--timeout", timeout_seconds, "Seconds to wait for the connection and for each reply")
      ->capture_default_str()
      ->type_name("SECONDS")
      ->check(check_timeout);
  app.add_flag("--json", json, "Print one JSON object per line");

  CLI::App* bodies = app.add_subcommand("bodies", "List every body: id, name, shape, mass, position, speed");

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
  subscribe
      ->add_option("--bodies", subscribe_bodies, "Bodies to follow, names or ids, comma-separated; all when absent")
      ->delimiter(',')
      ->type_name("A,B,...")
      ->check(check_body);
  subscribe->add_option("--rate", rate_hz, "Frames per second; 0 for every tick")
      ->capture_default_str()
      ->type_name("HZ");
  CLI::Option* count_option =
      subscribe->add_option("--count", count, "Exit after this many frames; run until interrupted when absent")
          ->type_name("N")
          ->check(CLI::Range(std::uint64_t{1}, std::numeric_limits<std::uint64_t>::max()));

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

  Invocation invocation;
  invocation.global.server = client::parse_endpoint(server).value();
  invocation.global.token = token;
  invocation.global.timeout = timeout_from_seconds(timeout_seconds);
  invocation.global.json = json;

  if (app.got_subcommand(bodies)) {
    invocation.command = BodiesCommand{};
  } else if (app.got_subcommand(force)) {
    ForceCommand command;
    command.body = body_ref(force_args.body);
    command.force = force_args.vector;
    command.at = force_args.point();
    command.local = force_args.local;
    command.duration = force_args.duration();
    invocation.command = std::move(command);
  } else if (app.got_subcommand(torque)) {
    TorqueCommand command;
    command.body = body_ref(torque_args.body);
    command.torque = torque_args.vector;
    command.duration = torque_args.duration();
    invocation.command = std::move(command);
  } else if (app.got_subcommand(impulse)) {
    ImpulseCommand command;
    command.body = body_ref(impulse_args.body);
    command.impulse = impulse_args.vector;
    command.at = impulse_args.point();
    command.local = impulse_args.local;
    invocation.command = std::move(command);
  } else {
    SubscribeCommand command;
    for (const std::string& name : subscribe_bodies) command.bodies.push_back(body_ref(name));
    command.rate_hz = rate_hz;
    if (count_option->count() > 0) command.count = count;
    invocation.command = std::move(command);
  }
  parsed.invocation = std::move(invocation);
  return parsed;
}

}  // namespace tumble::cli
