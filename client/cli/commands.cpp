#include "commands.h"

#include <chrono>
#include <string>
#include <variant>

#include "interrupt.h"
#include "output.h"
#include "requests.h"
#include "tumble_client/connection.h"
#include "tumble_client/pose_sample.h"

namespace tumble::cli {
namespace {

// How often a subscription that waits for frames looks for an interrupt.
constexpr auto kInterruptPollInterval = std::chrono::milliseconds(100);

client::Result<client::Connection> open(const GlobalOptions& global) {
  return client::Connection::connect(global.server, kClientName, global.token, global.timeout);
}

void emit(std::ostream& out, const std::string& text) { out << text << std::flush; }

std::optional<client::Failure> print_ack(const GlobalOptions& global, const client::Result<tumble::v1::Ack>& ack,
                                         std::ostream& out) {
  if (!ack) return ack.failure();
  emit(out, global.json ? json_line(ack_json(*ack)) : format_ack(*ack));
  return std::nullopt;
}

}  // namespace

std::optional<client::Failure> run(const Invocation& invocation, std::ostream& out) {
  const GlobalOptions& global = invocation.global;
  struct Dispatch {
    const GlobalOptions& global;
    std::ostream& out;
    std::optional<client::Failure> operator()(const BodiesCommand&) const { return run_bodies(global, out); }
    std::optional<client::Failure> operator()(const ForceCommand& c) const { return run_force(global, c, out); }
    std::optional<client::Failure> operator()(const TorqueCommand& c) const { return run_torque(global, c, out); }
    std::optional<client::Failure> operator()(const ImpulseCommand& c) const { return run_impulse(global, c, out); }
    std::optional<client::Failure> operator()(const SubscribeCommand& c) const {
      return run_subscribe(global, c, out);
    }
  };
  return std::visit(Dispatch{global, out}, invocation.command);
}

std::optional<client::Failure> run_bodies(const GlobalOptions& global, std::ostream& out) {
  auto connection = open(global);
  if (!connection) return connection.failure();
  auto list = connection->list_bodies(global.timeout);
  if (!list) return list.failure();
  emit(out, global.json ? json_line(body_list_json(*list)) : format_body_table(*list));
  return std::nullopt;
}

std::optional<client::Failure> run_force(const GlobalOptions& global, const ForceCommand& command, std::ostream& out) {
  auto connection = open(global);
  if (!connection) return connection.failure();
  return print_ack(global, connection->apply_force(make_apply_force(command), global.timeout), out);
}

std::optional<client::Failure> run_torque(const GlobalOptions& global, const TorqueCommand& command,
                                          std::ostream& out) {
  auto connection = open(global);
  if (!connection) return connection.failure();
  return print_ack(global, connection->apply_torque(make_apply_torque(command), global.timeout), out);
}

std::optional<client::Failure> run_impulse(const GlobalOptions& global, const ImpulseCommand& command,
                                           std::ostream& out) {
  auto connection = open(global);
  if (!connection) return connection.failure();
  return print_ack(global, connection->apply_impulse(make_apply_impulse(command), global.timeout), out);
}

std::optional<client::Failure> run_subscribe(const GlobalOptions& global, const SubscribeCommand& command,
                                             std::ostream& out) {
  auto connection = open(global);
  if (!connection) return connection.failure();
  auto list = connection->list_bodies(global.timeout);
  if (!list) return list.failure();
  const BodyNames names = body_names(*list);
  auto subscribed = connection->subscribe(make_subscribe(command), global.timeout);
  if (!subscribed) return subscribed.failure();
  const std::uint32_t subscription = subscribed->subscription_id();

  catch_interrupts();
  std::uint64_t shown = 0;
  while (!command.count || shown < *command.count) {
    if (interrupted()) break;
    auto message = connection->next_message(kInterruptPollInterval);
    if (!message) {
      if (message.failure().kind == client::FailureKind::timeout) continue;
      return message.failure();
    }
    if (message->has_error()) return client::server_failure(message->error());
    if (message->pose_frame().subscription_id() != subscription) continue;
    auto sample = client::unpack_pose_frame(message->pose_frame());
    if (!sample) return sample.failure();
    emit(out, global.json ? json_line(pose_sample_json(*sample, names)) : format_pose_sample(*sample, names));
    ++shown;
  }
  return std::nullopt;
}

}  // namespace tumble::cli
