// The world-editing and clock requests applied by the simulation, stepped
// tick by tick without the clock: spawn, remove, set, persistent forces and
// clear, pause, step, resume, reset, tick rate, stats, and the events they
// raise.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "sim/request_check.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/world_state.h"
#include "sim_driver.h"

namespace tumble::sim {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// A free box of 2 kg and a ball of 1 kg in zero gravity, far apart.
const char* kFreeScene = R"({"gravity": [0, 0, 0], "bodies": [
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2},
    {"name": "ball", "shape": {"sphere": {"radius": 1}}, "mass": 1, "position": [5, 0, 0]}]})";

// A box resting on the ground under gravity: it falls asleep after a while.
const char* kRestingScene = R"({"gravity": [0, -9.81, 0], "bodies": [
    {"name": "ground", "static": true, "shape": {"plane": {"normal": [0, 1, 0], "offset": 0}}},
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2, "position": [0, 0.5, 0]}]})";

ClientMessage spawn_sphere(const std::string& name, double radius, double mass, double x, double y, double z) {
  ClientMessage message;
  auto* body = message.mutable_spawn_body()->mutable_body();
  body->set_name(name);
  body->mutable_shape()->mutable_sphere()->set_radius(radius);
  body->set_mass(mass);
  body->mutable_position()->set_x(x);
  body->mutable_position()->set_y(y);
  body->mutable_position()->set_z(z);
  return message;
}

ClientMessage persistent_force(const std::string& body, double fx) {
  ClientMessage message;
  auto* force = message.mutable_apply_force();
  force->mutable_body()->set_name(body);
  force->mutable_force()->set_x(fx);
  force->set_persistent(true);
  return message;
}

ClientMessage impulse(const std::string& body, double jx, double jy) {
  ClientMessage message;
  auto* m = message.mutable_apply_impulse();
  m->mutable_body()->set_name(body);
  m->mutable_impulse()->set_x(jx);
  m->mutable_impulse()->set_y(jy);
  return message;
}

ClientMessage clock(void (*set)(ClientMessage&)) {
  ClientMessage message;
  set(message);
  return message;
}

ClientMessage pause_message() {
  return clock([](ClientMessage& m) { m.mutable_pause(); });
}
ClientMessage resume_message() {
  return clock([](ClientMessage& m) { m.mutable_resume(); });
}
ClientMessage reset_message() {
  return clock([](ClientMessage& m) { m.mutable_reset(); });
}
ClientMessage stats_message() {
  return clock([](ClientMessage& m) { m.mutable_get_stats(); });
}
ClientMessage list_message() {
  return clock([](ClientMessage& m) { m.mutable_list_bodies(); });
}

ClientMessage step_message(std::uint32_t ticks) {
  ClientMessage message;
  message.mutable_step()->set_ticks(ticks);
  return message;
}

class ControlTest : public ::testing::Test {
 protected:
  Driver driver_{make_sim(kFreeScene)};
};

TEST_F(ControlTest, SpawnAddsABodyWithTheNextIdAndItsName) {
  driver_.run(3);
  const ServerMessage reply = driver_.request(spawn_sphere("rock", 0.5, 2, 0, 10, 0));
  ASSERT_TRUE(reply.has_ack()) << reply.DebugString();
  ASSERT_TRUE(reply.ack().has_body_id());
  EXPECT_EQ(reply.ack().body_id(), 2u);
  EXPECT_EQ(reply.ack().applied_tick(), 4u) << "the step of tick 4 is the first to include it";
  EXPECT_EQ(driver_.id_of("rock"), 2u);
  EXPECT_EQ(driver_.sim().body_count(), 3u);
  EXPECT_DOUBLE_EQ(driver_.world().mass(2), 2.0);
  EXPECT_DOUBLE_EQ(driver_.world().position(2).y(), 10.0);

  const ServerMessage list = driver_.request(list_message());
  ASSERT_EQ(list.body_list().bodies_size(), 3);
  EXPECT_EQ(list.body_list().bodies(2).name(), "rock");
  EXPECT_TRUE(list.body_list().bodies(2).shape().has_sphere());
}

TEST_F(ControlTest, SpawnRefusesADuplicateNameAndABadSpec) {
  const ServerMessage duplicate = driver_.request(spawn_sphere("crate", 0.5, 1, 0, 0, 9));
  ASSERT_TRUE(duplicate.has_error());
  EXPECT_EQ(duplicate.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_NE(duplicate.error().message().find("'crate' is used by another body"), std::string::npos);

  const ServerMessage negative = driver_.request(spawn_sphere("rock", -1, 1, 0, 0, 9));
  ASSERT_TRUE(negative.has_error());
  EXPECT_EQ(negative.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_NE(negative.error().message().find("body.shape.sphere.radius"), std::string::npos)
      << negative.error().message();

  ClientMessage empty;
  empty.mutable_spawn_body();
  EXPECT_EQ(driver_.request(empty).error().message(), "body is required");
  EXPECT_EQ(driver_.sim().body_count(), 2u);
}

TEST(ControlLimits, SpawnBeyondMaxBodiesIsResourceExhausted) {
  SimConfig config;
  config.max_bodies = 3;
  Driver driver(make_sim(kFreeScene, config));
  ASSERT_TRUE(driver.request(spawn_sphere("a", 1, 1, 0, 10, 0)).has_ack());
  const ServerMessage over = driver.request(spawn_sphere("b", 1, 1, 0, 20, 0));
  ASSERT_TRUE(over.has_error());
  EXPECT_EQ(over.error().code(), tumble::v1::RESOURCE_EXHAUSTED);
  EXPECT_EQ(driver.sim().body_count(), 3u);
}

TEST(ControlLimits, SpawnBeyondTheLastBodyIdIsResourceExhausted) {
  tumble::v1::WorldState state;
  make_sim(kFreeScene)->capture(&state);
  state.set_next_body_id(kMaxBodyIds - 1);
  std::unique_ptr<Simulation> sim;
  const Status status = Simulation::create_from_state(state, {}, &sim);
  ASSERT_TRUE(status.ok()) << status.message();
  Driver driver(std::move(sim));
  const ServerMessage last = driver.request(spawn_sphere("a", 1, 1, 0, 10, 0));
  ASSERT_TRUE(last.has_ack());
  EXPECT_EQ(last.ack().body_id(), kMaxBodyIds - 1);
  const ServerMessage over = driver.request(spawn_sphere("b", 1, 1, 0, 20, 0));
  ASSERT_TRUE(over.has_error());
  EXPECT_EQ(over.error().code(), tumble::v1::RESOURCE_EXHAUSTED);
  EXPECT_EQ(driver.sim().body_count(), 3u);
}

TEST(ControlLimits, ASceneOverMaxBodiesIsRefused) {
  tumble::v1::Scene scene;
  ASSERT_TRUE(parse_scene_json(kFreeScene, &scene).ok());
  SimConfig config;
  config.max_bodies = 1;
  std::unique_ptr<Simulation> sim;
  const Status status = Simulation::create(scene, config, &sim);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("2 bodies"), std::string::npos) << status.message();
}

TEST_F(ControlTest, RemoveTakesTheBodyAndItsForcesAndItsIdIsNotReused) {
  ASSERT_TRUE(driver_.request(persistent_force("ball", 1)).has_ack());
  ClientMessage remove;
  remove.mutable_remove_body()->mutable_body()->set_name("ball");
  const ServerMessage reply = driver_.request(remove);
  ASSERT_TRUE(reply.has_ack()) << reply.DebugString();
  EXPECT_EQ(driver_.sim().body_count(), 1u);
  EXPECT_EQ(driver_.id_of("ball"), physics::kInvalidBodyId);
  EXPECT_EQ(driver_.sim().loads().size(), 0u);

  const ServerMessage again = driver_.request(remove);
  ASSERT_TRUE(again.has_error());
  EXPECT_EQ(again.error().code(), tumble::v1::UNKNOWN_BODY);
  const ServerMessage spawned = driver_.request(spawn_sphere("ball", 1, 1, 0, 0, 0));
  ASSERT_TRUE(spawned.has_ack());
  EXPECT_EQ(spawned.ack().body_id(), 2u) << "the removed ball's id 1 stays unused";
}

TEST_F(ControlTest, SetReplacesOnlyTheGivenParts) {
  ASSERT_TRUE(driver_.request(impulse("crate", 2, 0)).has_ack());  // v = (1, 0, 0) on 2 kg
  ClientMessage set;
  auto* state = set.mutable_set_body_state();
  state->mutable_body()->set_name("crate");
  state->mutable_position()->set_y(7);
  // A quarter turn about z, given slightly off unit length as hand-typed numbers are.
  state->mutable_orientation()->set_w(0.70711);
  state->mutable_orientation()->set_z(0.70711);
  ASSERT_TRUE(driver_.request(set).has_ack());
  // The step after the set moved it from (0, 7, 0) with the kept velocity.
  EXPECT_DOUBLE_EQ(driver_.world().position(0).x(), 1.0 * kDt);
  EXPECT_DOUBLE_EQ(driver_.world().position(0).y(), 7.0);
  EXPECT_NEAR(driver_.world().linear_velocity(0).x(), 1.0, 1e-12);
  EXPECT_NEAR(driver_.world().orientation(0).norm(), 1.0, 1e-15);
  EXPECT_NEAR(driver_.world().orientation(0).z(), std::sqrt(0.5), 1e-12);

  ClientMessage velocity;
  velocity.mutable_set_body_state()->mutable_body()->set_id(0);
  velocity.mutable_set_body_state()->mutable_linear_velocity()->set_z(-3);
  ASSERT_TRUE(driver_.request(velocity).has_ack());
  EXPECT_DOUBLE_EQ(driver_.world().linear_velocity(0).z(), -3.0);
  EXPECT_DOUBLE_EQ(driver_.world().linear_velocity(0).x(), 0.0) << "a given velocity replaces the whole vector";
  EXPECT_DOUBLE_EQ(driver_.world().position(0).y(), 7.0);
}

TEST_F(ControlTest, SetRefusesANonUnitOrientationAndUnknownBodies) {
  ClientMessage set;
  set.mutable_set_body_state()->mutable_body()->set_name("crate");
  set.mutable_set_body_state()->mutable_orientation()->set_w(2);
  const ServerMessage reply = driver_.request(set);
  ASSERT_TRUE(reply.has_error());
  EXPECT_EQ(reply.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_NE(reply.error().message().find("orientation"), std::string::npos);

  ClientMessage ghost;
  ghost.mutable_set_body_state()->mutable_body()->set_name("ghost");
  EXPECT_EQ(driver_.request(ghost).error().code(), tumble::v1::UNKNOWN_BODY);
}

TEST(ControlSleep, SetWakesASleepingBody) {
  Driver driver(make_sim(kRestingScene));
  const physics::BodyId crate = driver.id_of("crate");
  for (int i = 0; i < 600 && driver.world().is_awake(crate); ++i) driver.run(1);
  ASSERT_FALSE(driver.world().is_awake(crate)) << "the resting crate never fell asleep";
  ClientMessage set;
  set.mutable_set_body_state()->mutable_body()->set_name("crate");
  ASSERT_TRUE(driver.request(set).has_ack());
  EXPECT_TRUE(driver.world().is_awake(crate));
}

TEST_F(ControlTest, PersistentForceActsEveryTickUntilCleared) {
  ASSERT_TRUE(driver_.request(persistent_force("crate", 4)).has_ack());  // the first tick
  driver_.run(99);
  // P = F n dt after n ticks.
  EXPECT_NEAR(driver_.world().linear_momentum(0).x(), 4.0 * 100 * kDt, 1e-12);

  ClientMessage clear;
  clear.mutable_clear_forces()->mutable_body()->set_name("crate");
  ASSERT_TRUE(driver_.request(clear).has_ack());
  const double momentum = driver_.world().linear_momentum(0).x();
  EXPECT_NEAR(momentum, 4.0 * 100 * kDt, 1e-12) << "the tick of the clear is the first without it";
  driver_.run(50);
  EXPECT_EQ(driver_.world().linear_momentum(0).x(), momentum);
}

TEST_F(ControlTest, ClearWithoutABodyEndsEveryLoad) {
  ASSERT_TRUE(driver_.request(persistent_force("crate", 1)).has_ack());
  ClientMessage torque;
  torque.mutable_apply_torque()->mutable_body()->set_name("ball");
  torque.mutable_apply_torque()->mutable_torque()->set_y(1);
  torque.mutable_apply_torque()->set_persistent(true);
  ASSERT_TRUE(driver_.request(torque).has_ack());
  ClientMessage timed = persistent_force("ball", 1);
  timed.mutable_apply_force()->set_persistent(false);
  timed.mutable_apply_force()->set_ticks(1000);
  ASSERT_TRUE(driver_.request(timed).has_ack());
  EXPECT_EQ(driver_.sim().loads().size(), 3u);

  ClientMessage clear;
  clear.mutable_clear_forces();
  ASSERT_TRUE(driver_.request(clear).has_ack());
  EXPECT_EQ(driver_.sim().loads().size(), 0u);
  const physics::Vec3 p = driver_.world().linear_momentum(1);
  const physics::Vec3 l = driver_.world().angular_momentum(1);
  driver_.run(10);
  EXPECT_EQ(driver_.world().linear_momentum(1), p);
  EXPECT_EQ(driver_.world().angular_momentum(1), l);
}

TEST_F(ControlTest, PersistentWithADurationIsRefused) {
  ClientMessage message = persistent_force("crate", 1);
  message.mutable_apply_force()->set_ticks(3);
  const ServerMessage reply = driver_.request(message);
  ASSERT_TRUE(reply.has_error());
  EXPECT_EQ(reply.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_EQ(driver_.sim().loads().size(), 0u);
}

// The longest durations a request may ask for stay timed loads: 1e6 s at
// 1e4 Hz is more ticks than 32 bits hold, and UINT32_MAX ticks is the
// persistent marker; both are capped at the longest timed load.
TEST_F(ControlTest, TheLongestDurationsAreCappedNotWrappedOrPersistent) {
  ClientMessage rate;
  rate.mutable_set_tick_rate()->set_rate_hz(10000);
  ASSERT_TRUE(driver_.request(rate).has_ack());
  ClientMessage by_seconds = persistent_force("crate", 1);
  by_seconds.mutable_apply_force()->set_persistent(false);
  by_seconds.mutable_apply_force()->set_seconds(1e6);
  ASSERT_TRUE(driver_.request(by_seconds).has_ack());
  ClientMessage by_ticks = persistent_force("ball", 1);
  by_ticks.mutable_apply_force()->set_persistent(false);
  by_ticks.mutable_apply_force()->set_ticks(BodyLoad::kPersistent);
  ASSERT_TRUE(driver_.request(by_ticks).has_ack());

  ASSERT_EQ(driver_.sim().loads().size(), 2u);
  for (const BodyLoad& load : driver_.sim().loads().loads()) {
    EXPECT_FALSE(load.persistent());
    EXPECT_GT(load.ticks_left, BodyLoad::kPersistent - 10);
  }
}

TEST_F(ControlTest, PausedTheTickStaysButCommandsAreApplied) {
  driver_.run(5);
  const ServerMessage paused = driver_.request(pause_message());
  ASSERT_TRUE(paused.has_ack());
  EXPECT_EQ(paused.ack().applied_tick(), 5u) << "the tick the world stays at";
  EXPECT_TRUE(driver_.sim().paused());
  driver_.run(20);
  EXPECT_EQ(driver_.sim().tick(), 5u);

  const ServerMessage pushed = driver_.request(impulse("crate", 2, 0));
  ASSERT_TRUE(pushed.has_ack());
  EXPECT_EQ(pushed.ack().applied_tick(), 5u) << "while paused an edit shows in the current tick";
  EXPECT_DOUBLE_EQ(driver_.world().linear_velocity(0).x(), 1.0);
  EXPECT_DOUBLE_EQ(driver_.world().position(0).x(), 0.0) << "no step while paused";
  const ServerMessage list = driver_.request(list_message());
  EXPECT_EQ(list.body_list().tick(), 5u);
  EXPECT_DOUBLE_EQ(list.body_list().bodies(0).linear_velocity().x(), 1.0);

  const ServerMessage resumed = driver_.request(resume_message());
  ASSERT_TRUE(resumed.has_ack());
  EXPECT_EQ(resumed.ack().applied_tick(), 6u);
  EXPECT_FALSE(driver_.sim().paused());
  EXPECT_EQ(driver_.sim().tick(), 6u);
  EXPECT_DOUBLE_EQ(driver_.world().position(0).x(), 1.0 * kDt);
}

TEST_F(ControlTest, StepWhileRunningIsAFailedPrecondition) {
  const ServerMessage reply = driver_.request(step_message(5));
  ASSERT_TRUE(reply.has_error());
  EXPECT_EQ(reply.error().code(), tumble::v1::FAILED_PRECONDITION);
  EXPECT_EQ(driver_.sim().tick(), 1u) << "it ran its one normal tick, no more";
}

TEST_F(ControlTest, StepRunsExactlyItsTicksAndAcksTheLast) {
  driver_.run(2);
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  ASSERT_TRUE(driver_.request(persistent_force("crate", 2)).has_ack());
  const std::uint64_t start = driver_.sim().tick();
  const ServerMessage stepped = driver_.request(step_message(5));
  ASSERT_TRUE(stepped.has_ack()) << stepped.DebugString();
  EXPECT_EQ(stepped.ack().applied_tick(), start + 5);
  EXPECT_EQ(stepped.ack().step_ended_by(), tumble::v1::STEP_END_COMPLETED);
  EXPECT_EQ(stepped.ack().step_ticks_left(), 0u);
  EXPECT_EQ(driver_.sim().tick(), start + 5);
  driver_.run(30);
  EXPECT_EQ(driver_.sim().tick(), start + 5) << "still paused after the step";
  EXPECT_NEAR(driver_.world().linear_momentum(0).x(), 2.0 * 5 * kDt, 1e-14) << "the force acted in 5 steps";
}

TEST_F(ControlTest, ASecondStepWhileOneIsUnderWayIsRefused) {
  // run_tick() runs one tick of a Step a call, so the Step is under way
  // between calls whatever the machine's speed.
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  auto first = driver_.submit(step_message(3));
  driver_.run(1);
  EXPECT_EQ(driver_.sim().tick(), 1u);
  EXPECT_FALSE(first->has_value()) << "one tick of three";
  auto second = driver_.submit(step_message(3));
  driver_.run(1);
  ASSERT_TRUE(second->has_value());
  EXPECT_EQ((*second)->error().code(), tumble::v1::FAILED_PRECONDITION);
  EXPECT_EQ(driver_.sim().tick(), 2u) << "the refused Step added no ticks";
  EXPECT_FALSE(first->has_value());
  driver_.run(1);
  ASSERT_TRUE(first->has_value());
  EXPECT_EQ((*first)->ack().applied_tick(), 3u) << "paused at tick 0, then 3 ticks";
  driver_.run(5);
  EXPECT_EQ(driver_.sim().tick(), 3u) << "paused again after the Step";
  // Once the first is done, a Step is accepted again.
  EXPECT_EQ(driver_.request(step_message(2)).ack().applied_tick(), 5u);
}

TEST_F(ControlTest, TwoStepsInOnePassTheSecondIsRefused) {
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  auto first = driver_.submit(step_message(3));
  auto second = driver_.submit(step_message(3));
  driver_.run(1);
  ASSERT_TRUE(second->has_value());
  EXPECT_EQ((*second)->error().code(), tumble::v1::FAILED_PRECONDITION);
  driver_.run(2);
  ASSERT_TRUE(first->has_value());
  EXPECT_EQ((*first)->ack().applied_tick(), 3u);
  EXPECT_EQ(driver_.sim().tick(), 3u);
}

// A Step of `ticks` with a force on `body` and, with `frame`, a frame reply.
ClientMessage step_with_force(std::uint32_t ticks, const std::string& body, double fx, bool frame) {
  ClientMessage message = step_message(ticks);
  auto* force = message.mutable_step()->add_forces();
  force->mutable_body()->set_name(body);
  force->mutable_force()->set_x(fx);
  message.mutable_step()->set_reply_frame(frame);
  return message;
}

TEST_F(ControlTest, AStepsForcesActOnItsTicksAndNoOthers) {
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  const ServerMessage stepped = driver_.request(step_with_force(10, "crate", 4, false));
  ASSERT_TRUE(stepped.has_ack()) << stepped.DebugString();
  EXPECT_EQ(stepped.ack().applied_tick(), 10u);
  EXPECT_FALSE(stepped.ack().has_frame()) << "no frame unless asked";
  EXPECT_NEAR(driver_.world().linear_momentum(0).x(), 4.0 * 10 * kDt, 1e-14) << "the force acted in 10 steps";
  EXPECT_EQ(driver_.sim().loads().size(), 0u) << "the Step's loads are not the world's";
  ASSERT_TRUE(driver_.request(step_message(5)).has_ack());
  EXPECT_NEAR(driver_.world().linear_momentum(0).x(), 4.0 * 10 * kDt, 1e-14) << "and in no step after";
}

TEST_F(ControlTest, AStepAnswersWithTheFrameOfItsLastTick) {
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  ClientMessage message = step_with_force(3, "crate", 2, true);
  auto* torque = message.mutable_step()->add_torques();
  torque->mutable_body()->set_name("ball");
  torque->mutable_torque()->set_z(0.4);
  const ServerMessage stepped = driver_.request(message);
  ASSERT_TRUE(stepped.has_ack()) << stepped.DebugString();
  const tumble::v1::PoseFrame& frame = stepped.ack().frame();
  EXPECT_EQ(frame.tick(), 3u);
  EXPECT_EQ(frame.tick(), stepped.ack().applied_tick());
  EXPECT_DOUBLE_EQ(frame.sim_time(), 3 * kDt);
  ASSERT_EQ(frame.ids_size(), 2) << "every body";
  EXPECT_EQ(frame.ids(0), 0u);
  EXPECT_EQ(frame.ids(1), 1u);
  ASSERT_EQ(frame.positions_size(), 6);
  ASSERT_EQ(frame.orientations_size(), 8);
  ASSERT_EQ(frame.linear_velocities_size(), 6);
  ASSERT_EQ(frame.angular_velocities_size(), 6);
  EXPECT_FLOAT_EQ(frame.linear_velocities(0), static_cast<float>(driver_.world().linear_velocity(0).x()));
  EXPECT_FLOAT_EQ(frame.positions(0), static_cast<float>(driver_.world().position(0).x()));
  EXPECT_GT(frame.positions(0), 0.0f) << "the frame is of the state after the force";
  EXPECT_FLOAT_EQ(frame.angular_velocities(5), static_cast<float>(driver_.world().angular_velocity(1).z()));
  EXPECT_GT(frame.angular_velocities(5), 0.0f);

  // Named bodies only, poses only.
  ClientMessage named = step_message(1);
  named.mutable_step()->set_reply_frame(true);
  named.mutable_step()->add_frame_bodies()->set_name("ball");
  named.mutable_step()->set_frame_fields(tumble::v1::POSE_FIELDS_POSE);
  const ServerMessage named_reply = driver_.request(named);
  const tumble::v1::PoseFrame& ball = named_reply.ack().frame();
  ASSERT_EQ(ball.ids_size(), 1);
  EXPECT_EQ(ball.ids(0), 1u);
  EXPECT_EQ(ball.positions_size(), 3);
  EXPECT_EQ(ball.linear_velocities_size(), 0);
  EXPECT_FLOAT_EQ(ball.positions(0), 5.0f);
}

TEST_F(ControlTest, AStepNamingAnUnknownBodyIsRefusedAndNothingIsApplied) {
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  ClientMessage message = step_with_force(3, "crate", 2, true);
  message.mutable_step()->add_frame_bodies()->set_name("nobody");
  const ServerMessage refused = driver_.request(message);
  ASSERT_TRUE(refused.has_error());
  EXPECT_EQ(refused.error().code(), tumble::v1::UNKNOWN_BODY);
  EXPECT_EQ(refused.error().message(), "no body 'nobody' in the world");
  driver_.run(3);
  EXPECT_EQ(driver_.sim().tick(), 0u) << "nothing stepped";
  EXPECT_EQ(driver_.request(step_message(2)).ack().applied_tick(), 2u);
  EXPECT_EQ(driver_.world().linear_momentum(0).x(), 0.0) << "the refused Step's force never acted";
}

TEST_F(ControlTest, AStepCutShortDropsItsForcesAndAnswersWithTheFrameItReached) {
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  auto step = driver_.submit(step_with_force(100, "crate", 2, true));
  driver_.run(3);  // one tick of the Step a call
  ASSERT_FALSE(step->has_value());
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  ASSERT_TRUE(step->has_value());
  const tumble::v1::Ack& ack = (*step)->ack();
  EXPECT_EQ(ack.step_ended_by(), tumble::v1::STEP_END_PAUSE);
  EXPECT_EQ(ack.frame().tick(), ack.applied_tick());
  EXPECT_EQ(ack.step_ticks_left(), 100 - ack.applied_tick());
  const double momentum = driver_.world().linear_momentum(0).x();
  EXPECT_NEAR(momentum, 2.0 * static_cast<double>(ack.applied_tick()) * kDt, 1e-14);
  ASSERT_TRUE(driver_.request(step_message(5)).has_ack());
  EXPECT_EQ(driver_.world().linear_momentum(0).x(), momentum) << "the force ended with its Step";
}

TEST_F(ControlTest, AStepsForcesTakeNoDuration) {
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  ClientMessage timed = step_with_force(3, "crate", 2, false);
  timed.mutable_step()->mutable_forces(0)->set_ticks(2);
  const ServerMessage refused = driver_.request(timed);
  ASSERT_TRUE(refused.has_error());
  EXPECT_EQ(refused.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_EQ(refused.error().message(),
            "forces[0]: a Step's force acts for the Step's ticks and takes no duration or persistent");
  ClientMessage nameless = step_with_force(3, "", 2, false);
  EXPECT_EQ(driver_.request(nameless).error().message(), "forces[0].body name must not be empty");
}

TEST_F(ControlTest, StepOutOfRangeIsInvalid) {
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  EXPECT_EQ(driver_.request(step_message(0)).error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_EQ(driver_.request(step_message(kMaxStepTicks + 1)).error().code(), tumble::v1::INVALID_ARGUMENT);
}

TEST_F(ControlTest, ResetRestoresTheSceneAndKeepsTheClock) {
  ASSERT_TRUE(driver_.request(impulse("crate", 2, 4)).has_ack());
  ASSERT_TRUE(driver_.request(persistent_force("crate", 3)).has_ack());
  ASSERT_TRUE(driver_.request(spawn_sphere("rock", 1, 1, 0, 20, 0)).has_ack());
  ClientMessage remove;
  remove.mutable_remove_body()->mutable_body()->set_name("ball");
  ASSERT_TRUE(driver_.request(remove).has_ack());
  driver_.run(10);
  const std::uint64_t before = driver_.sim().tick();

  const ServerMessage reply = driver_.request(reset_message());
  ASSERT_TRUE(reply.has_ack());
  EXPECT_EQ(reply.ack().applied_tick(), before + 1);
  EXPECT_EQ(driver_.sim().tick(), before + 1) << "the tick goes on";
  EXPECT_EQ(driver_.sim().body_count(), 2u);
  EXPECT_EQ(driver_.id_of("crate"), 0u);
  EXPECT_EQ(driver_.id_of("ball"), 1u);
  EXPECT_EQ(driver_.id_of("rock"), physics::kInvalidBodyId);
  EXPECT_EQ(driver_.sim().loads().size(), 0u);
  // One step of nothing from the scene's state: exactly where it started.
  EXPECT_EQ(driver_.world().position(0), physics::Vec3::Zero());
  EXPECT_EQ(driver_.world().position(1), physics::Vec3(5, 0, 0));
  EXPECT_TRUE(driver_.world().linear_momentum(0).isZero(0));
  const ServerMessage spawned = driver_.request(spawn_sphere("rock", 1, 1, 0, 20, 0));
  EXPECT_EQ(spawned.ack().body_id(), 3u) << "ids handed out before the reset are not reused";
}

TEST_F(ControlTest, AfterAResetTheWorldMovesExactlyAsAFreshOne) {
  // The same commands from the scene give bit-identical states, reset or fresh.
  const auto drive = [](Driver& driver) {
    driver.request(impulse("crate", 1, 0.5));
    driver.request(persistent_force("ball", -2));
    driver.run(50);
  };
  Driver fresh(make_sim(kFreeScene));
  drive(fresh);
  driver_.request(impulse("ball", 7, 7));
  driver_.run(30);
  driver_.request(reset_message());
  drive(driver_);
  for (physics::BodyId id : {0u, 1u}) {
    EXPECT_EQ(driver_.world().position(id), fresh.world().position(id));
    EXPECT_EQ(driver_.world().linear_momentum(id), fresh.world().linear_momentum(id));
    EXPECT_EQ(driver_.world().angular_momentum(id), fresh.world().angular_momentum(id));
  }
}

TEST(ControlSleep, AResetWorldWithContactsMovesExactlyAsAFreshOne) {
  // Contacts, warm-started impulses and sleep all start over: a box dropped
  // onto the ground after a reset lands exactly as it does in a fresh world.
  const auto drop = [](Driver& driver) {
    ClientMessage set;
    set.mutable_set_body_state()->mutable_body()->set_name("crate");
    set.mutable_set_body_state()->mutable_position()->set_y(2);
    set.mutable_set_body_state()->mutable_angular_velocity()->set_z(1);
    driver.request(set);
    driver.run(300);
  };
  Driver fresh(make_sim(kRestingScene));
  fresh.run(1);
  drop(fresh);
  Driver reset(make_sim(kRestingScene));
  reset.request(impulse("crate", 3, 5));
  reset.run(400);
  reset.request(reset_message());  // and the first step of the scene, as fresh.run(1)
  drop(reset);
  const physics::BodyId crate = fresh.id_of("crate");
  EXPECT_EQ(reset.world().position(crate), fresh.world().position(crate));
  EXPECT_EQ(reset.world().orientation(crate).coeffs(), fresh.world().orientation(crate).coeffs());
  EXPECT_EQ(reset.world().linear_momentum(crate), fresh.world().linear_momentum(crate));
  EXPECT_EQ(reset.world().is_awake(crate), fresh.world().is_awake(crate));
}

TEST_F(ControlTest, ResetWhilePausedStaysPaused) {
  ASSERT_TRUE(driver_.request(pause_message()).has_ack());
  ASSERT_TRUE(driver_.request(impulse("crate", 2, 0)).has_ack());
  const std::uint64_t tick = driver_.sim().tick();
  const ServerMessage reply = driver_.request(reset_message());
  EXPECT_EQ(reply.ack().applied_tick(), tick);
  EXPECT_TRUE(driver_.sim().paused());
  EXPECT_EQ(driver_.sim().tick(), tick);
  EXPECT_TRUE(driver_.world().linear_momentum(0).isZero(0));
}

TEST_F(ControlTest, EditsReportSpawnedRemovedAndResetEvents) {
  const ServerMessage spawned = driver_.request(spawn_sphere("rock", 1, 1, 0, 20, 0));
  ClientMessage remove;
  remove.mutable_remove_body()->mutable_body()->set_name("ball");
  const ServerMessage removed = driver_.request(remove);
  driver_.request(reset_message());
  const auto& events = driver_.events();
  ASSERT_EQ(events.size(), 5u);
  EXPECT_EQ(events[0].kind, WorldEventKind::body_spawned);
  EXPECT_EQ(events[0].body, 2u);
  EXPECT_EQ(events[0].name, "rock");
  EXPECT_EQ(events[0].tick, spawned.ack().applied_tick());
  EXPECT_EQ(events[1].kind, WorldEventKind::body_removed);
  EXPECT_EQ(events[1].name, "ball");
  EXPECT_EQ(events[1].tick, removed.ack().applied_tick());
  EXPECT_EQ(events[2].kind, WorldEventKind::world_reset);
  EXPECT_EQ(events[3].kind, WorldEventKind::body_removed) << "the spawned rock goes";
  EXPECT_EQ(events[3].body, 2u);
  EXPECT_EQ(events[4].kind, WorldEventKind::body_spawned) << "the removed ball comes back";
  EXPECT_EQ(events[4].body, 1u);
  EXPECT_EQ(events[4].name, "ball");
}

TEST(ControlSleep, SleepEventsAreReportedOnlyWhenWanted) {
  Driver driver(make_sim(kRestingScene));
  driver.run(400);  // asleep by now, unreported
  ASSERT_FALSE(driver.world().is_awake(1));
  EXPECT_TRUE(driver.events().empty());

  driver.sim().set_sleep_events_wanted(true);
  driver.run(1);
  EXPECT_TRUE(driver.events().empty()) << "the states when watching starts are not events";
  const ServerMessage woken = driver.request(impulse("crate", 0, 3));
  ASSERT_EQ(driver.events().size(), 1u);
  EXPECT_EQ(driver.events()[0].kind, WorldEventKind::body_awake);
  EXPECT_EQ(driver.events()[0].name, "crate");
  EXPECT_EQ(driver.events()[0].tick, woken.ack().applied_tick());
  for (int i = 0; i < 1200 && driver.events().size() < 2; ++i) driver.run(1);
  ASSERT_EQ(driver.events().size(), 2u);
  EXPECT_EQ(driver.events()[1].kind, WorldEventKind::body_asleep);
  EXPECT_EQ(driver.events()[1].tick, driver.sim().tick());
  EXPECT_FALSE(driver.world().is_awake(1));
}

TEST(ControlSleep, SleepEventsAreWatchedWhileAnySourceWantsThem) {
  Driver driver(make_sim(kRestingScene));
  driver.run(400);  // asleep by now
  ASSERT_FALSE(driver.world().is_awake(1));
  const PublishSource other = driver.sim().add_publish_source();
  driver.sim().set_sleep_events_wanted(true, other);
  driver.sim().set_sleep_events_wanted(false);  // source 0 does not want them; the other still does
  driver.run(1);
  driver.request(impulse("crate", 0, 3));
  ASSERT_EQ(driver.events().size(), 1u);
  EXPECT_EQ(driver.events()[0].kind, WorldEventKind::body_awake);
  driver.sim().set_sleep_events_wanted(false, other);
  for (int i = 0; i < 1200 && driver.world().is_awake(1); ++i) driver.run(1);
  ASSERT_FALSE(driver.world().is_awake(1));
  EXPECT_EQ(driver.events().size(), 1u) << "nobody wants sleep events any more";
}

TEST_F(ControlTest, SetTickRateChangesTheStepFromTheNextTick) {
  driver_.run(24);  // 0.1 s at 240 Hz
  ClientMessage rate;
  rate.mutable_set_tick_rate()->set_rate_hz(60);
  const ServerMessage reply = driver_.request(rate);
  ASSERT_TRUE(reply.has_ack());
  EXPECT_EQ(reply.ack().applied_tick(), 25u);
  EXPECT_DOUBLE_EQ(driver_.sim().tick_rate_hz(), 60);
  EXPECT_NEAR(driver_.sim().sim_time(), 0.1 + 1.0 / 60, 1e-12);

  // A force of 1 s now lasts 60 ticks of 1/60 s: P = F t exactly as before.
  ClientMessage force = persistent_force("crate", 2);
  force.mutable_apply_force()->set_persistent(false);
  force.mutable_apply_force()->set_seconds(1);
  ASSERT_TRUE(driver_.request(force).has_ack());
  driver_.run(100);
  EXPECT_NEAR(driver_.world().linear_momentum(0).x(), 2.0, 1e-12);

  for (double bad : {0.0, 0.5, 20000.0, std::nan("")}) {
    rate.mutable_set_tick_rate()->set_rate_hz(bad);
    EXPECT_EQ(driver_.request(rate).error().code(), tumble::v1::INVALID_ARGUMENT) << bad;
  }
}

TEST_F(ControlTest, StatsReportTheClockTheBodiesAndTheStepTimes) {
  driver_.run(30);
  const ServerMessage reply = driver_.request(stats_message());
  ASSERT_TRUE(reply.has_stats()) << reply.DebugString();
  const auto& stats = reply.stats();
  EXPECT_EQ(stats.request_id(), 1u);
  EXPECT_EQ(stats.tick(), 30u) << "as of the tick the request was applied in";
  EXPECT_NEAR(stats.sim_time(), 30 * kDt, 1e-12);
  EXPECT_FALSE(stats.paused());
  EXPECT_DOUBLE_EQ(stats.tick_rate_hz(), 240);
  EXPECT_EQ(stats.bodies(), 2u);
  EXPECT_EQ(stats.bodies_awake(), 2u);
  EXPECT_EQ(stats.bodies_asleep(), 0u);
  EXPECT_EQ(stats.overruns(), 0u);
  EXPECT_GT(stats.tick_ms_p99(), 0.0);
  EXPECT_LE(stats.tick_ms_p50(), stats.tick_ms_p99());
  // CPU time is read inside each tick's wall-clock span.
  EXPECT_GT(stats.tick_cpu_ms_p99(), 0.0);
  EXPECT_LE(stats.tick_cpu_ms_p50(), stats.tick_ms_p50());
  EXPECT_LE(stats.tick_cpu_ms_p99(), stats.tick_ms_p99());
  EXPECT_EQ(stats.tick_start_late_ms_p99(), 0.0) << "stepped by hand, not by the loop";
  EXPECT_EQ(stats.clients(), 0u) << "the network layer fills those";

  driver_.request(pause_message());
  const ServerMessage paused = driver_.request(stats_message());
  EXPECT_TRUE(paused.stats().paused());
  EXPECT_EQ(paused.stats().real_time_factor(), 0.0);
}

TEST_F(ControlTest, AnEditWhilePausedIsPublishedAtOnceOutOfBand) {
  std::vector<std::shared_ptr<const Snapshot>> snapshots;
  driver_.sim().add_snapshot_listener([&](std::shared_ptr<const Snapshot> s) { snapshots.push_back(std::move(s)); });
  driver_.sim().set_publish_interest({PublishInterest{}}, kEarlyBodies);  // every body, every tick
  driver_.request(pause_message());
  snapshots.clear();
  driver_.run(10);
  EXPECT_TRUE(snapshots.empty()) << "nothing new while paused";

  driver_.sim().request_snapshot();
  driver_.run(1);
  ASSERT_EQ(snapshots.size(), 1u) << "a new subscriber is served while paused";
  EXPECT_FALSE(snapshots[0]->out_of_band);

  const ServerMessage spawned = driver_.request(spawn_sphere("rock", 1, 1, 0, 20, 0));
  ASSERT_EQ(snapshots.size(), 2u);
  EXPECT_TRUE(snapshots[1]->out_of_band);
  EXPECT_EQ(snapshots[1]->tick, spawned.ack().applied_tick());
  EXPECT_EQ(snapshots[1]->body_count(), 3u);
}

}  // namespace
}  // namespace tumble::sim
