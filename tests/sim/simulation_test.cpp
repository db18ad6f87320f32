// The simulation applying commands, stepped tick by tick without the clock.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "sim/request_check.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim_driver.h"

namespace tumble::sim {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

class SimulationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tumble::v1::Scene scene;
    // A free box of 2 kg in zero gravity and a sphere; exact numbers make exact expectations.
    ASSERT_TRUE(parse_scene_json(R"({"gravity": [0, 0, 0], "bodies": [
        {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2},
        {"name": "ball", "shape": {"sphere": {"radius": 1}}, "mass": 1, "position": [5, 0, 0]}]})",
                                 &scene)
                    .ok());
    SimConfig config;
    config.tick_rate_hz = kRate;
    ASSERT_TRUE(Simulation::create(scene, config, &sim_).ok());
    crate_ = sim_->world().body_id_at(0);
    ball_ = sim_->world().body_id_at(1);
  }

  // Submits `message` (checked as the network layer would) and returns the reply after one tick.
  ServerMessage request(ClientMessage message) {
    message.set_request_id(++request_id_);
    if (auto problem = check_request(message)) {
      ServerMessage reply;
      reply.mutable_error()->set_code(problem->code);
      reply.mutable_error()->set_message(problem->message);
      return reply;
    }
    auto reply = std::make_shared<ServerMessage>();
    sim_->submit(Command{message, [reply](ServerMessage m) { *reply = std::move(m); }});
    sim_->run_tick();
    return *reply;
  }

  static ClientMessage force(const std::string& body, double fx, double fy, double fz) {
    ClientMessage message;
    auto* f = message.mutable_apply_force();
    f->mutable_body()->set_name(body);
    f->mutable_force()->set_x(fx);
    f->mutable_force()->set_y(fy);
    f->mutable_force()->set_z(fz);
    return message;
  }

  std::unique_ptr<Simulation> sim_;
  physics::BodyId crate_ = 0;
  physics::BodyId ball_ = 0;
  std::uint64_t request_id_ = 0;
};

TEST_F(SimulationTest, ForceTakesEffectInTheStepOfItsAppliedTick) {
  sim_->run_tick();
  sim_->run_tick();
  const ServerMessage reply = request(force("crate", 4, 0, 0));
  ASSERT_TRUE(reply.has_ack()) << reply.DebugString();
  EXPECT_EQ(reply.ack().request_id(), request_id_);
  EXPECT_EQ(reply.ack().applied_tick(), 3u);
  EXPECT_EQ(sim_->tick(), 3u);
  // One tick of F = 4 N on 2 kg: v = F/M dt.
  EXPECT_NEAR(sim_->world().linear_velocity(crate_).x(), 4.0 / 2.0 * kDt, 1e-15);
  sim_->run_tick();
  EXPECT_NEAR(sim_->world().linear_velocity(crate_).x(), 4.0 / 2.0 * kDt, 1e-15) << "default is one tick";
}

TEST_F(SimulationTest, ForceLastsItsDurationInSecondsOrTicks) {
  ClientMessage by_seconds = force("crate", 2, 0, 0);
  by_seconds.mutable_apply_force()->set_seconds(0.5);  // 120 ticks at 240 Hz
  ASSERT_TRUE(request(by_seconds).has_ack());
  for (int i = 1; i < 200; ++i) sim_->run_tick();
  // Momentum = F T with T rounded to whole ticks.
  EXPECT_NEAR(sim_->world().linear_momentum(crate_).x(), 2.0 * 120 * kDt, 1e-12);

  ClientMessage by_ticks = force("ball", 0, 3, 0);
  by_ticks.mutable_apply_force()->set_ticks(7);
  ASSERT_TRUE(request(by_ticks).has_ack());
  for (int i = 1; i < 20; ++i) sim_->run_tick();
  EXPECT_NEAR(sim_->world().linear_momentum(ball_).y(), 3.0 * 7 * kDt, 1e-12);
}

TEST_F(SimulationTest, ForceAtABodyPointSpinsTheBody) {
  // F = (0, 1, 0) N at body point (0.5, 0, 0): torque (r - x) x F = (0, 0, 0.5) for one tick.
  ClientMessage message = force("crate", 0, 1, 0);
  auto* f = message.mutable_apply_force();
  f->mutable_point()->set_x(0.5);
  f->set_point_frame(tumble::v1::FRAME_BODY);
  ASSERT_TRUE(request(message).has_ack());
  EXPECT_NEAR(sim_->world().angular_momentum(crate_).z(), 0.5 * kDt, 1e-15);
  EXPECT_NEAR(sim_->world().linear_momentum(crate_).y(), 1.0 * kDt, 1e-15);
}

TEST_F(SimulationTest, WorldPointIsTakenRelativeToTheCentreOfMass) {
  // The ball is at x = 5: a world point (5, 0, 1) is 1 m along +z from its centre.
  ClientMessage message = force("ball", 1, 0, 0);
  message.mutable_apply_force()->mutable_point()->set_x(5);
  message.mutable_apply_force()->mutable_point()->set_z(1);
  ASSERT_TRUE(request(message).has_ack());
  // (0, 0, 1) x (1, 0, 0) = (0, 1, 0).
  EXPECT_NEAR(sim_->world().angular_momentum(ball_).y(), 1.0 * kDt, 1e-15);
}

TEST_F(SimulationTest, ImpulseChangesMomentumAtOnce) {
  ClientMessage message;
  auto* impulse = message.mutable_apply_impulse();
  impulse->mutable_body()->set_id(ball_);
  impulse->mutable_impulse()->set_x(3);
  const ServerMessage reply = request(message);
  ASSERT_TRUE(reply.has_ack());
  EXPECT_DOUBLE_EQ(sim_->world().linear_momentum(ball_).x(), 3.0);
  EXPECT_DOUBLE_EQ(sim_->world().position(ball_).x(), 5.0 + 3.0 * kDt);
}

TEST_F(SimulationTest, TorqueSpinsUpAboutTheCentre) {
  ClientMessage message;
  auto* torque = message.mutable_apply_torque();
  torque->mutable_body()->set_name("crate");
  torque->mutable_torque()->set_y(2);
  torque->set_ticks(24);
  ASSERT_TRUE(request(message).has_ack());
  for (int i = 1; i < 30; ++i) sim_->run_tick();
  EXPECT_NEAR(sim_->world().angular_momentum(crate_).y(), 2.0 * 24 * kDt, 1e-12);
  EXPECT_TRUE(sim_->world().linear_momentum(crate_).isZero());
}

TEST_F(SimulationTest, UnknownBodyIsAnErrorAndChangesNothing) {
  const ServerMessage by_name = request(force("nobody", 1, 0, 0));
  ASSERT_TRUE(by_name.has_error());
  EXPECT_EQ(by_name.error().code(), tumble::v1::UNKNOWN_BODY);
  EXPECT_EQ(by_name.error().message(), "no body 'nobody' in the world");
  EXPECT_EQ(by_name.error().request_id(), request_id_);

  ClientMessage by_id;
  by_id.mutable_apply_impulse()->mutable_body()->set_id(999);
  by_id.mutable_apply_impulse()->mutable_impulse()->set_x(1);
  const ServerMessage reply = request(by_id);
  ASSERT_TRUE(reply.has_error());
  EXPECT_EQ(reply.error().message(), "no body 999 in the world");
  EXPECT_TRUE(sim_->world().linear_momentum(crate_).isZero());
  EXPECT_TRUE(sim_->world().linear_momentum(ball_).isZero());
}

TEST_F(SimulationTest, NonFiniteNumbersAreRefusedBeforeTheyReachTheWorld) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double bad : {nan, inf, -inf, 1e300}) {
    const ServerMessage reply = request(force("crate", bad, 0, 0));
    ASSERT_TRUE(reply.has_error());
    EXPECT_EQ(reply.error().code(), tumble::v1::INVALID_ARGUMENT);
    EXPECT_NE(reply.error().message().find("force"), std::string::npos) << reply.error().message();
  }
  ClientMessage bad_duration = force("crate", 1, 0, 0);
  bad_duration.mutable_apply_force()->set_seconds(-1);
  EXPECT_EQ(request(bad_duration).error().code(), tumble::v1::INVALID_ARGUMENT);
  ClientMessage no_body;
  no_body.mutable_apply_force()->mutable_force()->set_x(1);
  EXPECT_EQ(request(no_body).error().message(), "body is required");
  EXPECT_TRUE(sim_->world().linear_momentum(crate_).isZero());
}

TEST_F(SimulationTest, ListBodiesDescribesEveryBody) {
  ClientMessage message;
  message.mutable_list_bodies();
  const ServerMessage reply = request(message);
  ASSERT_TRUE(reply.has_body_list());
  const auto& list = reply.body_list();
  ASSERT_EQ(list.bodies_size(), 2);
  EXPECT_EQ(list.bodies(0).name(), "crate");
  EXPECT_TRUE(list.bodies(0).shape().has_box());
  EXPECT_DOUBLE_EQ(list.bodies(0).mass(), 2);
  EXPECT_EQ(list.bodies(1).name(), "ball");
  EXPECT_DOUBLE_EQ(list.bodies(1).position().x(), 5);
  EXPECT_DOUBLE_EQ(list.bodies(1).orientation().w(), 1);
}

TEST_F(SimulationTest, ABodyWhoseStateDivergesIsRemovedWithEventsAndCounted) {
  std::vector<WorldEvent> events;
  sim_->add_event_listener(
      [&](std::shared_ptr<const WorldEvents> batch) { events.insert(events.end(), batch->begin(), batch->end()); });
  // Every number within the ranges: the lightest body and the largest force.
  // a = 1e9 N / 1e-6 kg = 1e15 m/s^2, so one step of 1/240 s makes v = 4.2e12 m/s.
  ClientMessage spawn;
  auto* body = spawn.mutable_spawn_body()->mutable_body();
  body->set_name("flea");
  body->mutable_shape()->mutable_sphere()->set_radius(0.01);
  body->set_mass(1e-6);
  body->mutable_position()->set_y(10);
  const ServerMessage spawned = request(spawn);
  ASSERT_TRUE(spawned.has_ack()) << spawned.ShortDebugString();
  const physics::BodyId flea = spawned.ack().body_id();
  ClientMessage push = force("flea", 1e9, 0, 0);
  push.mutable_apply_force()->set_persistent(true);
  const ServerMessage pushed = request(push);  // the step of this tick diverges
  ASSERT_TRUE(pushed.has_ack()) << pushed.ShortDebugString();
  const std::uint64_t diverged_at = sim_->tick();

  EXPECT_FALSE(sim_->world().contains(flea));
  EXPECT_EQ(sim_->body_count(), 2u);
  EXPECT_TRUE(sim_->loads().loads().empty()) << "the persistent force went with the body";
  EXPECT_EQ(sim_->resolve([] {
    tumble::v1::BodyRef ref;
    ref.set_name("flea");
    return ref;
  }()),
            physics::kInvalidBodyId);
  // diverged, then removed, both of the tick of the step; nothing else of the flea after its spawn.
  ASSERT_GE(events.size(), 3u);
  const WorldEvent& divergence = events[events.size() - 2];
  const WorldEvent& removal = events.back();
  EXPECT_EQ(divergence.kind, WorldEventKind::body_diverged);
  EXPECT_EQ(divergence.body, flea);
  EXPECT_EQ(divergence.name, "flea");
  EXPECT_EQ(divergence.tick, diverged_at);
  EXPECT_EQ(removal.kind, WorldEventKind::body_removed);
  EXPECT_EQ(removal.body, flea);
  EXPECT_EQ(removal.tick, diverged_at);

  ClientMessage stats;
  stats.mutable_get_stats();
  EXPECT_EQ(request(stats).stats().bodies_diverged(), 1u);
  // The world goes on; the others are untouched, and what is saved restores.
  EXPECT_TRUE(sim_->world().position(crate_).isZero());
  tumble::v1::WorldState state;
  sim_->capture(&state);
  EXPECT_EQ(state.bodies_size(), 2);
  std::unique_ptr<Simulation> resumed;
  const Status status = Simulation::create_from_state(state, SimConfig{}, &resumed);
  EXPECT_TRUE(status.ok()) << status.message();
}

TEST_F(SimulationTest, ABodyThatTurnsNaNIsRemovedBeforeAnyoneSeesIt) {
  std::vector<std::shared_ptr<const Snapshot>> snapshots;
  sim_->add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) { snapshots.push_back(std::move(s)); });
  // Past the request checks, as a bug would be: a force that is not a number.
  ClientMessage poison = force("ball", std::nan(""), 0, 0);
  poison.set_request_id(++request_id_);
  sim_->submit(Command{poison, nullptr});
  sim_->request_snapshot();
  sim_->run_tick();
  EXPECT_FALSE(sim_->world().contains(ball_));
  ASSERT_FALSE(snapshots.empty());
  for (const double value : snapshots.back()->positions) EXPECT_TRUE(std::isfinite(value));
  EXPECT_EQ(snapshots.back()->ids.size(), 1u);
  ClientMessage stats;
  stats.mutable_get_stats();
  EXPECT_EQ(request(stats).stats().bodies_diverged(), 1u);
}

TEST_F(SimulationTest, PublishesOnTheTicksItsPeriodsDivideAndWhenAsked) {
  std::vector<std::uint64_t> ticks;
  sim_->add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) { ticks.push_back(s->tick); });
  for (int i = 0; i < 5; ++i) sim_->run_tick();
  EXPECT_TRUE(ticks.empty()) << "nobody subscribed";
  sim_->set_publish_interest({PublishInterest{4, true, {}}, PublishInterest{6, false, {ball_}}}, kEarlyBodies);
  for (int i = 0; i < 7; ++i) sim_->run_tick();  // ticks 6..12
  // At 12 both are due: the ball on its own first, then every body.
  EXPECT_EQ(ticks, (std::vector<std::uint64_t>{6, 8, 12, 12}));
  sim_->request_snapshot();
  sim_->run_tick();
  EXPECT_EQ(ticks.back(), 13u);
}

TEST_F(SimulationTest, PublishesForTheUnionOfItsSourcesToEveryListener) {
  std::vector<std::uint64_t> first;
  std::vector<std::uint64_t> second;
  sim_->add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) { first.push_back(s->tick); });
  sim_->add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) {
    EXPECT_TRUE(s->all_bodies);
    second.push_back(s->tick);
  });
  const PublishSource other = sim_->add_publish_source();
  ASSERT_NE(other, 0u);
  // Source 0 every 4 ticks, the other every 6: each is served, neither replaces the other.
  sim_->set_publish_interest({PublishInterest{4, true, {}}}, kEarlyBodies);
  sim_->set_publish_interest({PublishInterest{6, true, {}}}, 0, other);
  for (int i = 0; i < 12; ++i) sim_->run_tick();  // ticks 1..12
  EXPECT_EQ(first, (std::vector<std::uint64_t>{4, 6, 8, 12}));
  EXPECT_EQ(second, first);
  // One source going quiet leaves the other's interest in place.
  sim_->set_publish_interest({}, kEarlyBodies);
  first.clear();
  for (int i = 0; i < 12; ++i) sim_->run_tick();  // ticks 13..24
  EXPECT_EQ(first, (std::vector<std::uint64_t>{18, 24}));
}

TEST_F(SimulationTest, EveryEventListenerAndStatsHookIsServed) {
  std::size_t batches_a = 0;
  std::size_t batches_b = 0;
  sim_->add_event_listener([&](std::shared_ptr<const WorldEvents>) { ++batches_a; });
  sim_->add_event_listener([&](std::shared_ptr<const WorldEvents>) { ++batches_b; });
  sim_->add_stats_hook([](tumble::v1::Stats* stats) { stats->mutable_nats()->set_world("hooked"); });
  ClientMessage remove;
  remove.mutable_remove_body()->mutable_body()->set_name("ball");
  ASSERT_TRUE(request(remove).has_ack());
  EXPECT_EQ(batches_a, 1u);
  EXPECT_EQ(batches_b, 1u);
  ClientMessage stats;
  stats.mutable_get_stats();
  EXPECT_EQ(request(stats).stats().nats().world(), "hooked");
}

TEST_F(SimulationTest, SnapshotHoldsOnlyTheBodiesTheDueInterestsRead) {
  std::vector<std::shared_ptr<const Snapshot>> snapshots;
  sim_->add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) { snapshots.push_back(std::move(s)); });
  // The ball and an id that is not in the world (a body removed before the
  // interest caught up) every tick, the crate every second tick, every
  // body every third.
  const physics::BodyId gone = ball_ + 100;
  ASSERT_LT(crate_, ball_);
  sim_->set_publish_interest(
      {PublishInterest{1, false, {ball_, gone}}, PublishInterest{2, false, {crate_}}, PublishInterest{3, true, {}}},
      kEarlyBodies);
  for (int i = 0; i < 6; ++i) sim_->run_tick();  // ticks 1..6
  // Ticks 3 and 6 publish the filtered bodies first, then every body.
  ASSERT_EQ(snapshots.size(), 8u);
  for (std::size_t k = 0; k < snapshots.size(); ++k) {
    const auto& s = snapshots[k];
    EXPECT_EQ(s->more_follows, s->tick % 3 == 0 && !s->all_bodies) << "tick " << s->tick;
    if (s->more_follows) {
      ASSERT_LT(k + 1, snapshots.size());
      EXPECT_EQ(snapshots[k + 1]->tick, s->tick);
      EXPECT_TRUE(snapshots[k + 1]->all_bodies);
    }
    if (s->all_bodies) {
      EXPECT_EQ(s->tick % 3, 0u);
      EXPECT_EQ(s->body_count(), 2u) << "tick " << s->tick;
      EXPECT_TRUE(s->covers(true, {}));
      continue;
    }
    EXPECT_FALSE(s->covers(true, {}));
    EXPECT_TRUE(s->covers(false, {ball_}));
    EXPECT_TRUE(s->covers(false, {gone})) << "a body that left the world is covered by its absence";
    if (s->tick % 2 == 0) {
      EXPECT_EQ(s->ids, (std::vector<physics::BodyId>{crate_, ball_})) << "tick " << s->tick;
      EXPECT_EQ(s->wanted, (std::vector<physics::BodyId>{crate_, ball_, gone}));
      EXPECT_TRUE(s->covers(false, {crate_, ball_}));
    } else {
      EXPECT_EQ(s->ids, (std::vector<physics::BodyId>{ball_})) << "tick " << s->tick;
      EXPECT_EQ(s->wanted, (std::vector<physics::BodyId>{ball_, gone}));
      EXPECT_FALSE(s->covers(false, {crate_})) << "the crate was not asked for";
    }
    EXPECT_EQ(s->positions.size(), 3 * s->body_count());
    EXPECT_EQ(s->orientations.size(), 4 * s->body_count());
  }
  // The ball's values in it are the world's after the step.
  snapshots.clear();
  ClientMessage push;
  push.mutable_apply_impulse()->mutable_body()->set_name("ball");
  push.mutable_apply_impulse()->mutable_impulse()->set_y(2);
  request(push);
  ASSERT_EQ(snapshots.size(), 1u);
  const Snapshot& only = *snapshots[0];
  ASSERT_EQ(only.body_count(), 1u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(only.positions[static_cast<std::size_t>(k)], sim_->world().position(ball_)[k]);
    EXPECT_EQ(only.linear_velocities[static_cast<std::size_t>(k)], sim_->world().linear_velocity(ball_)[k]);
  }
  EXPECT_DOUBLE_EQ(only.linear_velocities[1], 2.0);
  EXPECT_EQ(only.orientations[0], sim_->world().orientation(ball_).w());
}

// A world of `count` spheres 1 m apart along x, without gravity (ids 0 ..
// count - 1); null if it could not be made.
std::unique_ptr<Simulation> row_of_spheres(int count) {
  std::string json = R"({"gravity": [0, 0, 0], "bodies": [)";
  for (int i = 0; i < count; ++i) {
    json += std::string(i > 0 ? "," : "") + R"({"shape": {"sphere": {"radius": 0.2}}, "mass": 1, "position": [)" +
            std::to_string(i) + ", 0, 0]}";
  }
  tumble::v1::Scene scene;
  std::unique_ptr<Simulation> sim;
  if (!parse_scene_json(json + "]}", &scene).ok() || !Simulation::create(scene, SimConfig{}, &sim).ok()) return nullptr;
  return sim;
}

TEST(SimulationSnapshots, SmallStreamsGoFirstAndMostOfTheWorldIsCopiedWhole) {
  // 200 spheres: a probe of one body every tick, and 150 bodies by id
  // every fourth tick (a viewer of most of the world).
  std::unique_ptr<Simulation> sim = row_of_spheres(200);
  ASSERT_TRUE(sim);
  std::vector<physics::BodyId> most;
  for (physics::BodyId id = 10; id < 160; ++id) most.push_back(id);
  const physics::BodyId probe = 3;
  sim->set_publish_interest({PublishInterest{1, false, {probe}}, PublishInterest{4, false, most}}, kEarlyBodies);
  std::vector<std::shared_ptr<const Snapshot>> snapshots;
  sim->add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) { snapshots.push_back(std::move(s)); });
  for (int i = 0; i < 8; ++i) sim->run_tick();  // ticks 1..8

  ASSERT_EQ(snapshots.size(), 10u) << "two snapshots at ticks 4 and 8";
  std::size_t k = 0;
  for (std::uint64_t tick = 1; tick <= 8; ++tick) {
    const Snapshot& first = *snapshots[k++];
    EXPECT_EQ(first.tick, tick);
    EXPECT_FALSE(first.all_bodies);
    EXPECT_EQ(first.ids, (std::vector<physics::BodyId>{probe})) << "tick " << tick;
    EXPECT_EQ(first.more_follows, tick % 4 == 0) << "tick " << tick;
    if (tick % 4 != 0) continue;
    EXPECT_FALSE(first.covers(false, most)) << "the large stream waits for the next one";
    const Snapshot& second = *snapshots[k++];
    EXPECT_EQ(second.tick, tick);
    EXPECT_FALSE(second.more_follows);
    EXPECT_TRUE(second.all_bodies) << "151 of 200 bodies: the whole world, copied in one pass";
    EXPECT_EQ(second.body_count(), 200u);
    EXPECT_TRUE(second.covers(false, most));
    EXPECT_TRUE(second.covers(false, {probe}));
  }
}

TEST(SimulationSnapshots, LargeStreamsDueTogetherGetTheUnionOfTheirBodies) {
  // 400 spheres; two overlapping filters of 120 bodies each (every 2nd and
  // every 3rd tick), neither nor their union most of the world, and a
  // probe every tick.
  std::unique_ptr<Simulation> sim = row_of_spheres(400);
  ASSERT_TRUE(sim);
  std::vector<physics::BodyId> evens;  // 0, 2, ..., 238
  std::vector<physics::BodyId> run;    // 100 .. 219
  for (physics::BodyId id = 0; id < 240; id += 2) evens.push_back(id);
  for (physics::BodyId id = 100; id < 220; ++id) run.push_back(id);
  const physics::BodyId probe = 399;
  sim->set_publish_interest(
      {PublishInterest{3, false, run}, PublishInterest{1, false, {probe}}, PublishInterest{2, false, evens}},
      kEarlyBodies);
  std::vector<std::shared_ptr<const Snapshot>> snapshots;
  sim->add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) { snapshots.push_back(std::move(s)); });
  for (int i = 0; i < 6; ++i) sim->run_tick();  // ticks 1..6

  // The large snapshot holds every due stream's bodies, the probe's too.
  const auto with_probe = [&](std::vector<physics::BodyId> ids) {
    ids.push_back(probe);
    return ids;
  };
  std::vector<physics::BodyId> both;
  std::set_union(evens.begin(), evens.end(), run.begin(), run.end(), std::back_inserter(both));
  ASSERT_EQ(both.size(), 180u);
  std::size_t k = 0;
  for (std::uint64_t tick = 1; tick <= 6; ++tick) {
    ASSERT_LT(k, snapshots.size());
    const Snapshot& first = *snapshots[k++];
    EXPECT_EQ(first.ids, (std::vector<physics::BodyId>{probe})) << "tick " << tick;
    const bool large_due = tick % 2 == 0 || tick % 3 == 0;
    EXPECT_EQ(first.more_follows, large_due) << "tick " << tick;
    if (!large_due) continue;
    ASSERT_LT(k, snapshots.size());
    const Snapshot& second = *snapshots[k++];
    EXPECT_EQ(second.tick, tick);
    EXPECT_FALSE(second.all_bodies) << "at most 181 of 400 bodies keep their filter";
    const std::vector<physics::BodyId> expected = with_probe(tick % 6 == 0 ? both : tick % 2 == 0 ? evens : run);
    EXPECT_EQ(second.wanted, expected) << "tick " << tick;
    EXPECT_EQ(second.ids, expected) << "tick " << tick;
    EXPECT_EQ(second.covers(false, run), tick % 3 == 0) << "tick " << tick;
    EXPECT_EQ(second.covers(false, evens), tick % 2 == 0) << "tick " << tick;
  }
  EXPECT_EQ(k, snapshots.size());
}

TEST_F(SimulationTest, SnapshotHoldsThePosesAfterTheStep) {
  std::shared_ptr<const Snapshot> last;
  sim_->add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) { last = std::move(s); });
  sim_->request_snapshot();
  ClientMessage message;
  message.mutable_apply_impulse()->mutable_body()->set_name("ball");
  message.mutable_apply_impulse()->mutable_impulse()->set_y(2);
  request(message);
  ASSERT_TRUE(last);
  ASSERT_EQ(last->body_count(), 2u);
  EXPECT_EQ(last->ids[1], ball_);
  EXPECT_DOUBLE_EQ(last->positions[3 + 0], 5.0);
  EXPECT_DOUBLE_EQ(last->positions[3 + 1], 2.0 * kDt);
  EXPECT_DOUBLE_EQ(last->linear_velocities[3 + 1], 2.0);
  EXPECT_DOUBLE_EQ(last->orientations[4 + 0], 1.0);
  EXPECT_FALSE(last->out_of_band);
}

// How many threads of this process are named "tumbled-sim" (simulation.cpp
// names its thread so).
std::size_t sim_threads() {
  std::size_t count = 0;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (std::getline(comm, name) && name == "tumbled-sim") ++count;
  }
  return count;
}

// Waits up to 10 s until sim_threads() is `count`: a joined thread may stay
// in /proc for a moment before the kernel reaps it.
bool sim_threads_become(std::size_t count) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (sim_threads() != count) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

TEST_F(SimulationTest, RunsOnItsOwnThreadAtTheTickRate) {
  ASSERT_TRUE(sim_threads_become(0)) << "a sim thread of another test is still running";
  sim_->start();
  // Generous bound on a shared machine: only that ticks advance, not how fast.
  for (int i = 0; i < 500 && sim_->tick() < 24; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(sim_threads(), 1u);
  sim_->stop();
  const std::uint64_t stopped_at = sim_->tick();
  EXPECT_GE(stopped_at, 24u);
  // stop() joins the sim thread: it is gone, and stepped nothing after stop() returned.
  EXPECT_TRUE(sim_threads_become(0)) << "the sim thread outlived stop()";
  EXPECT_EQ(sim_->tick(), stopped_at);
}

}  // namespace
}  // namespace tumble::sim
