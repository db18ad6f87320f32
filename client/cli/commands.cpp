#include "commands.h"

#include <chrono>
#include <functional>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <variant>

#include "interrupt.h"
#include "output.h"
#include "reconnect_policy.h"
#include "requests.h"
#include "tumble_client/connection.h"
#include "tumble_client/nats_connection.h"
#include "tumble_client/pose_sample.h"
#include "tumble_client/pose_stream.h"
#include "watch_state.h"

namespace tumble::cli {
namespace {

// How often a subscription that waits for frames looks for an interrupt.
constexpr auto kInterruptPollInterval = std::chrono::milliseconds(100);

// ANSI: cursor home, then clear the screen; `watch` draws each table after it.
constexpr const char* kClearScreen = "\x1b[H\x1b[2J";

// The failure of a connection over NATS, led by the flag to look at.
client::Failure naming_the_flag(const GlobalOptions& global, client::Failure failure) {
  const bool credentials =
      !global.nats_credentials.empty() &&
      (failure.kind == client::FailureKind::invalid_argument ||
       (failure.kind == client::FailureKind::server && failure.code == tumble::v1::UNAUTHENTICATED));
  failure.message = (credentials ? "--nats-creds: " : "--nats: ") + failure.message;
  return failure;
}

client::Result<client::NatsConnection> open_nats(const GlobalOptions& global, const std::string& stream) {
  client::NatsOptions options;
  options.servers = global.nats;
  options.world = global.world;
  options.stream = stream;
  options.credentials_file = global.nats_credentials;
  options.client_name = kClientName;
  auto connection = client::NatsConnection::connect(options, global.timeout);
  if (!connection) return naming_the_flag(global, connection.failure());
  return connection;
}

// The world the options name: over NATS with --nats, else over TCP.
// `stream` is the NATS stream subscribe() is to read.
client::Result<std::unique_ptr<client::Transport>> open(const GlobalOptions& global, const std::string& stream = {}) {
  if (!global.nats.empty()) {
    auto connection = open_nats(global, stream);
    if (!connection) return connection.failure();
    return std::unique_ptr<client::Transport>(std::make_unique<client::NatsConnection>(std::move(connection.value())));
  }
  auto connection = client::Connection::connect(global.server, kClientName, global.token, global.timeout);
  if (!connection) return connection.failure();
  return std::unique_ptr<client::Transport>(std::make_unique<client::Connection>(std::move(connection.value())));
}

// The bodies' names, for output that shows names. A user who may not ask
// for them (an observer over NATS) sees ids instead: no failure.
client::Result<tumble::v1::BodyList> names_if_permitted(client::Transport& world, client::Timeout timeout) {
  auto list = world.list_bodies(timeout);
  if (!list && list.failure().code == tumble::v1::PERMISSION_DENIED) return tumble::v1::BodyList{};
  return list;
}

void emit(std::ostream& out, const std::string& text) { out << text << std::flush; }

// Prints an Ack as JSON, or as `format` words it for people.
std::optional<client::Failure> print_ack(const GlobalOptions& global, const client::Result<tumble::v1::Ack>& ack,
                                         std::ostream& out,
                                         std::string (*format)(const tumble::v1::Ack&) = format_ack) {
  if (!ack) return ack.failure();
  emit(out, global.json ? json_line(ack_json(*ack)) : format(*ack));
  return std::nullopt;
}

// What a subscription's loop does with one of its frames or events; a
// failure ends the loop.
struct StreamHandlers {
  std::function<std::optional<client::Failure>(const client::PoseSample&)> frame;
  std::function<void(const tumble::v1::WorldEvent&)> event;
};

// Reads the messages of `subscription` until `count` frames were handled
// or an interrupt: the shared loop of subscribe and watch.
std::optional<client::Failure> follow(client::Transport& connection, std::uint32_t subscription,
                                      std::optional<std::uint64_t> count, const StreamHandlers& handlers) {
  catch_interrupts();
  std::uint64_t shown = 0;
  client::PoseStream stream;
  while (!count || shown < *count) {
    if (interrupted()) break;
    auto message = connection.next_message(kInterruptPollInterval);
    if (!message) {
      if (message.failure().kind == client::FailureKind::timeout) continue;
      return message.failure();
    }
    if (message->has_error()) return client::server_failure(message->error());
    if (message->has_world_event()) {
      if (message->world_event().subscription_id() == subscription && handlers.event) {
        handlers.event(message->world_event());
      }
      continue;
    }
    if (message->pose_frame().subscription_id() != subscription) continue;
    auto sample = stream.decode(message->pose_frame());
    if (!sample) return sample.failure();
    if (auto failure = handlers.frame(*sample)) return failure;
    ++shown;
  }
  return std::nullopt;
}

}  // namespace

std::optional<client::Failure> run(const Invocation& invocation, std::ostream& out, bool out_is_terminal) {
  const GlobalOptions& global = invocation.global;
  struct Dispatch {
    const GlobalOptions& global;
    std::ostream& out;
    bool out_is_terminal;
    std::optional<client::Failure> operator()(const BodiesCommand&) const { return run_bodies(global, out); }
    std::optional<client::Failure> operator()(const ForceCommand& c) const { return run_force(global, c, out); }
    std::optional<client::Failure> operator()(const TorqueCommand& c) const { return run_torque(global, c, out); }
    std::optional<client::Failure> operator()(const ImpulseCommand& c) const { return run_impulse(global, c, out); }
    std::optional<client::Failure> operator()(const SubscribeCommand& c) const {
      return run_subscribe(global, c, out, std::cerr);
    }
    std::optional<client::Failure> operator()(const SpawnCommand& c) const { return run_spawn(global, c, out); }
    std::optional<client::Failure> operator()(const RemoveCommand& c) const { return run_remove(global, c, out); }
    std::optional<client::Failure> operator()(const SetCommand& c) const { return run_set(global, c, out); }
    std::optional<client::Failure> operator()(const ClearCommand& c) const { return run_clear(global, c, out); }
    std::optional<client::Failure> operator()(const PauseCommand&) const { return run_pause(global, out); }
    std::optional<client::Failure> operator()(const ResumeCommand&) const { return run_resume(global, out); }
    std::optional<client::Failure> operator()(const StepCommand& c) const { return run_step(global, c, out); }
    std::optional<client::Failure> operator()(const ResetCommand&) const { return run_reset(global, out); }
    std::optional<client::Failure> operator()(const TickRateCommand& c) const { return run_tick_rate(global, c, out); }
    std::optional<client::Failure> operator()(const StatsCommand&) const { return run_stats(global, out); }
    std::optional<client::Failure> operator()(const WatchCommand& c) const {
      return run_watch(global, c, out, out_is_terminal);
    }
    std::optional<client::Failure> operator()(const WorldsCommand&) const { return run_worlds(global, out); }
    std::optional<client::Failure> operator()(const JointsCommand&) const { return run_joints(global, out); }
    std::optional<client::Failure> operator()(const JointAddCommand& c) const { return run_joint_add(global, c, out); }
    std::optional<client::Failure> operator()(const JointRemoveCommand& c) const {
      return run_joint_remove(global, c, out);
    }
    std::optional<client::Failure> operator()(const MotorCommand& c) const { return run_motor(global, c, out); }
  };
  return std::visit(Dispatch{global, out, out_is_terminal}, invocation.command);
}

std::optional<client::Failure> run_bodies(const GlobalOptions& global, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  auto list = connection.list_bodies(global.timeout);
  if (!list) return list.failure();
  emit(out, global.json ? json_line(body_list_json(*list)) : format_body_table(*list));
  return std::nullopt;
}

std::optional<client::Failure> run_force(const GlobalOptions& global, const ForceCommand& command, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.apply_force(make_apply_force(command), global.timeout), out);
}

std::optional<client::Failure> run_torque(const GlobalOptions& global, const TorqueCommand& command,
                                          std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.apply_torque(make_apply_torque(command), global.timeout), out);
}

std::optional<client::Failure> run_impulse(const GlobalOptions& global, const ImpulseCommand& command,
                                           std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.apply_impulse(make_apply_impulse(command), global.timeout), out);
}

namespace {

// Where a `tumble subscribe` stands across its connections.
struct SubscribeProgress {
  std::uint64_t shown = 0;  // frames printed, over every connection
  bool subscribed = false;  // the latest connection's subscription stood
  bool retried = false;     // an earlier connection failed
};

// One connection of `tumble subscribe`: connects, lists the bodies (for
// their names), subscribes and prints until `command.count` frames in all
// or an interrupt. After a retry, says on `notes` that it is back.
std::optional<client::Failure> subscribe_once(const GlobalOptions& global, const SubscribeCommand& command,
                                              std::ostream& out, std::ostream& notes, SubscribeProgress& progress) {
  progress.subscribed = false;
  auto link = open(global, command.stream);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  auto list = names_if_permitted(connection, global.timeout);
  if (!list) return list.failure();
  const BodyNames names = body_names(*list);
  auto subscribed = connection.subscribe(make_subscribe(command), global.timeout);
  if (!subscribed) return subscribed.failure();
  progress.subscribed = true;
  if (progress.retried) {
    notes << "tumble: reconnected to " << connection.describe() << " at tick " << list->tick() << std::endl;
  }

  StreamHandlers handlers;
  handlers.frame = [&](const client::PoseSample& sample) -> std::optional<client::Failure> {
    emit(out, global.json ? json_line(pose_sample_json(sample, names)) : format_pose_sample(sample, names));
    ++progress.shown;
    return std::nullopt;
  };
  handlers.event = [&](const tumble::v1::WorldEvent& event) {
    emit(out, global.json ? json_line(world_event_json(event)) : format_world_event(event));
  };
  std::optional<std::uint64_t> left;
  if (command.count) left = *command.count - progress.shown;
  return follow(connection, subscribed->subscription_id(), left, handlers);
}

}  // namespace

std::optional<client::Failure> run_subscribe(const GlobalOptions& global, const SubscribeCommand& command,
                                             std::ostream& out, std::ostream& notes) {
  SubscribeProgress progress;
  if (!command.reconnect) return subscribe_once(global, command, out, notes, progress);
  catch_interrupts();
  ReconnectBackoff backoff(command.reconnect_max_wait);
  for (;;) {
    std::optional<client::Failure> failure = subscribe_once(global, command, out, notes, progress);
    if (!failure || interrupted()) return std::nullopt;
    if (!worth_reconnecting(*failure)) return failure;
    if (progress.subscribed) backoff.reset();  // it served: the next wait is the first again
    progress.retried = true;
    const std::chrono::milliseconds wait = backoff.next_wait();
    std::ostringstream note;  // its own stream, so `notes` keeps its number format
    note << "tumble: " << failure->message << "; reconnecting in " << std::fixed << std::setprecision(2)
         << std::chrono::duration<double>(wait).count() << " s\n";
    notes << note.str() << std::flush;
    if (!sleep_unless_interrupted(wait)) return std::nullopt;
  }
}

std::optional<client::Failure> run_spawn(const GlobalOptions& global, const SpawnCommand& command, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.spawn_body(make_body_spec(command), global.timeout), out, format_spawned);
}

std::optional<client::Failure> run_remove(const GlobalOptions& global, const RemoveCommand& command,
                                          std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.remove_body(command.body, global.timeout), out);
}

std::optional<client::Failure> run_set(const GlobalOptions& global, const SetCommand& command, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.set_body_state(make_set_body_state(command), global.timeout), out);
}

std::optional<client::Failure> run_clear(const GlobalOptions& global, const ClearCommand& command, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.clear_forces(make_clear_forces(command), global.timeout), out);
}

std::optional<client::Failure> run_pause(const GlobalOptions& global, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.pause(global.timeout), out, format_paused);
}

std::optional<client::Failure> run_resume(const GlobalOptions& global, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.resume(global.timeout), out);
}

std::optional<client::Failure> run_step(const GlobalOptions& global, const StepCommand& command, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.step(command.ticks, global.timeout), out, format_stepped);
}

std::optional<client::Failure> run_reset(const GlobalOptions& global, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.reset(global.timeout), out);
}

std::optional<client::Failure> run_tick_rate(const GlobalOptions& global, const TickRateCommand& command,
                                             std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.set_tick_rate(command.rate_hz, global.timeout), out);
}

std::optional<client::Failure> run_stats(const GlobalOptions& global, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  auto stats = connection.get_stats(global.timeout);
  if (!stats) return stats.failure();
  emit(out, global.json ? json_line(stats_json(*stats)) : format_stats(*stats));
  return std::nullopt;
}

std::optional<client::Failure> run_watch(const GlobalOptions& global, const WatchCommand& command, std::ostream& out,
                                         bool out_is_terminal) {
  auto link = open(global, command.stream);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  // Subscribe first, then list: every event after the list's tick is queued
  // by the time the list arrives, and applying the older ones again is harmless.
  auto subscribed = connection.subscribe(make_watch_subscribe(command), global.timeout);
  if (!subscribed) return subscribed.failure();
  auto list = names_if_permitted(connection, global.timeout);
  if (!list) return list.failure();
  WatchState state;
  state.load(*list);

  bool first = true;
  StreamHandlers handlers;
  handlers.event = [&](const tumble::v1::WorldEvent& event) { state.apply(event); };
  handlers.frame = [&](const client::PoseSample& sample) -> std::optional<client::Failure> {
    if (global.json) {
      emit(out, json_line(watch_json(sample, state)));
    } else if (out_is_terminal) {
      emit(out, kClearScreen + format_watch_table(sample, state));
    } else {
      emit(out, (first ? "" : "\n") + format_watch_table(sample, state));
    }
    first = false;
    return std::nullopt;
  };
  return follow(connection, subscribed->subscription_id(), command.count, handlers);
}

std::optional<client::Failure> run_worlds(const GlobalOptions& global, std::ostream& out) {
  auto connection = open_nats(global, {});
  if (!connection) return connection.failure();
  auto worlds = connection->find_worlds(client::kWorldsQuietPeriod, global.timeout);
  if (!worlds) return worlds.failure();
  if (global.json) {
    std::string lines;
    for (const tumble::v1::WorldInfo& info : *worlds) lines += json_line(world_info_json(info));
    emit(out, lines);
  } else {
    emit(out, format_world_table(*worlds));
  }
  return std::nullopt;
}

std::optional<client::Failure> run_joints(const GlobalOptions& global, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  auto list = connection.list_joints(global.timeout);
  if (!list) return list.failure();
  emit(out, global.json ? json_line(joint_list_json(*list)) : format_joint_table(*list));
  return std::nullopt;
}

std::optional<client::Failure> run_joint_add(const GlobalOptions& global, const JointAddCommand& command,
                                             std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.add_joint(make_joint_spec(command), global.timeout), out, format_joint_added);
}

std::optional<client::Failure> run_joint_remove(const GlobalOptions& global, const JointRemoveCommand& command,
                                                std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.remove_joint(command.joint, global.timeout), out);
}

std::optional<client::Failure> run_motor(const GlobalOptions& global, const MotorCommand& command, std::ostream& out) {
  auto link = open(global);
  if (!link) return link.failure();
  client::Transport& connection = **link;
  return print_ack(global, connection.set_joint_motor(make_set_joint_motor(command), global.timeout), out);
}

}  // namespace tumble::cli
