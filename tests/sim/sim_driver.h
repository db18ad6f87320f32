// Driver: one Simulation driven as the network layer drives it, for the
// tests of its requests. Requests are checked first (request_check.h) and
// submitted; ticks run until their replies are in; the world's events are
// collected. Header-only; one thread.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/request_check.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace tumble::sim {

// The tick rate the tests run at (tumbled's default), and its tick in seconds.
inline constexpr double kRate = 240;
inline constexpr double kDt = 1.0 / kRate;

// Where the publisher draws the line between small interests, which go
// early, and large ones (net/publisher.cpp).
inline constexpr std::size_t kEarlyBodies = 64;

// A simulation of the scene `json` with `config`; a test failure (and
// null) when either is refused.
inline std::unique_ptr<Simulation> make_sim(const std::string& json, SimConfig config = {}) {
  tumble::v1::Scene scene;
  const Status parsed = parse_scene_json(json, &scene);
  EXPECT_TRUE(parsed.ok()) << parsed.message();
  std::unique_ptr<Simulation> sim;
  const Status status = Simulation::create(scene, config, &sim);
  EXPECT_TRUE(status.ok()) << status.message();
  return sim;
}

// The message of creating a simulation from `json`, or "" when it loads.
inline std::string load_error(const std::string& json) {
  tumble::v1::Scene scene;
  if (Status status = parse_scene_json(json, &scene); !status.ok()) return status.message();
  std::unique_ptr<Simulation> sim;
  Status status = Simulation::create(scene, SimConfig{}, &sim);
  return status.ok() ? "" : status.message();
}

class Driver {
 public:
  explicit Driver(std::unique_ptr<Simulation> sim) : sim_(std::move(sim)) {
    sim_->add_event_listener([this](std::shared_ptr<const WorldEvents> events) {
      events_.insert(events_.end(), events->begin(), events->end());
    });
  }

  Simulation& sim() { return *sim_; }
  const physics::World& world() { return sim_->world(); }
  std::vector<WorldEvent>& events() { return events_; }

  // Submits `message`; its reply lands in the returned slot once applied.
  std::shared_ptr<std::optional<tumble::v1::ServerMessage>> submit(tumble::v1::ClientMessage message) {
    message.set_request_id(++request_id_);
    auto slot = std::make_shared<std::optional<tumble::v1::ServerMessage>>();
    if (auto problem = check_request(message)) {
      tumble::v1::ServerMessage reply;
      reply.mutable_error()->set_request_id(message.request_id());
      reply.mutable_error()->set_code(problem->code);
      reply.mutable_error()->set_message(problem->message);
      *slot = std::move(reply);
      return slot;
    }
    sim_->submit(Command{message, [slot](tumble::v1::ServerMessage m) { *slot = std::move(m); }});
    return slot;
  }

  // Submits `message` and runs ticks (at most 100) until its reply is in.
  tumble::v1::ServerMessage request(tumble::v1::ClientMessage message) {
    auto slot = submit(std::move(message));
    for (int i = 0; i < 100 && !slot->has_value(); ++i) sim_->run_tick();
    EXPECT_TRUE(slot->has_value()) << "no reply";
    return slot->value_or(tumble::v1::ServerMessage{});
  }

  void run(int ticks) {
    for (int i = 0; i < ticks; ++i) sim_->run_tick();
  }

  physics::BodyId id_of(const char* name) {
    tumble::v1::BodyRef ref;
    ref.set_name(name);
    return sim_->resolve(ref);
  }

 private:
  std::unique_ptr<Simulation> sim_;
  std::vector<WorldEvent> events_;
  std::uint64_t request_id_ = 0;
};

}  // namespace tumble::sim
