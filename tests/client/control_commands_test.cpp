// The world-editing, clock and monitoring subcommands of `tumble`: their
// command lines, the requests built from them, and what they print.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "command_line.h"
#include "command_line_helpers.h"
#include "exit_code.h"
#include "output.h"
#include "requests.h"
#include "watch_state.h"

namespace tumble::cli {
namespace {

using testing::expect_usage_error;
using testing::parse;
using testing::parse_command;

TEST(SpawnCommandLine, EveryOption) {
  const auto spawn = parse_command<SpawnCommand>({"spawn",
                                                  "rock",
                                                  "--capsule",
                                                  "0.2",
                                                  "0.5",
                                                  "--mass",
                                                  "3",
                                                  "--at",
                                                  "1",
                                                  "2",
                                                  "3",
                                                  "--orientation",
                                                  "0",
                                                  "1",
                                                  "0",
                                                  "0",
                                                  "--velocity",
                                                  "4",
                                                  "5",
                                                  "6",
                                                  "--angular-velocity",
                                                  "7",
                                                  "8",
                                                  "9",
                                                  "--kinematic",
                                                  "--friction",
                                                  "0.1",
                                                  "--restitution",
                                                  "0.9"});
  EXPECT_EQ(spawn.name, "rock");
  ASSERT_TRUE(spawn.shape.has_capsule());
  EXPECT_EQ(spawn.shape.capsule().radius(), 0.2);
  EXPECT_EQ(spawn.shape.capsule().half_height(), 0.5);
  EXPECT_EQ(spawn.mass, 3);
  EXPECT_EQ(spawn.position, (Vector3{1, 2, 3}));
  ASSERT_TRUE(spawn.orientation);
  EXPECT_EQ(*spawn.orientation, (Quaternion{0, 1, 0, 0}));
  EXPECT_EQ(spawn.linear_velocity, (Vector3{4, 5, 6}));
  EXPECT_EQ(spawn.angular_velocity, (Vector3{7, 8, 9}));
  EXPECT_EQ(spawn.motion, tumble::v1::MOTION_KINEMATIC);
  EXPECT_EQ(spawn.friction, 0.1);
  EXPECT_EQ(spawn.restitution, 0.9);
}

TEST(SpawnCommandLine, DefaultsAndShapes) {
  const auto ball = parse_command<SpawnCommand>({"spawn", "ball", "--sphere", "0.5"});
  EXPECT_EQ(ball.shape.sphere().radius(), 0.5);
  EXPECT_EQ(ball.mass, 1);
  EXPECT_EQ(ball.position, (Vector3{0, 0, 0}));
  EXPECT_FALSE(ball.orientation);
  EXPECT_EQ(ball.motion, tumble::v1::MOTION_DYNAMIC);
  EXPECT_FALSE(ball.friction);
  EXPECT_FALSE(ball.restitution);

  const auto wall = parse_command<SpawnCommand>({"spawn", "", "--box", "1", "2", "0.5", "--static"});
  EXPECT_EQ(wall.name, "") << "an unnamed body";
  EXPECT_EQ(wall.shape.box().half_extents().y(), 2);
  EXPECT_EQ(wall.motion, tumble::v1::MOTION_STATIC);
}

TEST(SpawnCommandLine, UsageErrors) {
  expect_usage_error({"spawn", "rock"});
  expect_usage_error({"spawn", "rock", "--sphere", "1", "--capsule", "1", "1"});
  expect_usage_error({"spawn", "rock", "--capsule", "1"});
  expect_usage_error({"spawn", "--sphere", "1"});
  expect_usage_error({"spawn", "007", "--sphere", "1"});
  expect_usage_error({"spawn", "rock", "--sphere", "1", "--static", "--kinematic"});
  expect_usage_error({"spawn", "rock", "--sphere", "1", "--orientation", "1", "0", "0"});
}

TEST(ControlCommandLine, SetGivesOnlyWhatWasTyped) {
  const auto set =
      parse_command<SetCommand>({"set", "3", "--position", "1", "2", "3", "--angular-velocity", "0", "0", "1"});
  EXPECT_EQ(set.body.id(), 3u);
  ASSERT_TRUE(set.position);
  EXPECT_EQ(*set.position, (Vector3{1, 2, 3}));
  EXPECT_FALSE(set.orientation);
  EXPECT_FALSE(set.linear_velocity);
  ASSERT_TRUE(set.angular_velocity);
  EXPECT_EQ(*set.angular_velocity, (Vector3{0, 0, 1}));
  expect_usage_error({"set"});
}

TEST(ControlCommandLine, RemoveClearStepTickRate) {
  EXPECT_EQ(parse_command<RemoveCommand>({"remove", "crate"}).body.name(), "crate");
  expect_usage_error({"remove"});
  EXPECT_FALSE(parse_command<ClearCommand>({"clear"}).body);
  const auto clear = parse_command<ClearCommand>({"clear", "crate"});
  ASSERT_TRUE(clear.body);
  EXPECT_EQ(clear.body->name(), "crate");
  EXPECT_EQ(parse_command<StepCommand>({"step"}).ticks, 1u);
  EXPECT_EQ(parse_command<StepCommand>({"step", "25"}).ticks, 25u);
  expect_usage_error({"step", "-1"});
  EXPECT_EQ(parse_command<TickRateCommand>({"tick-rate", "120"}).rate_hz, 120);
  expect_usage_error({"tick-rate"});
  parse_command<PauseCommand>({"pause"});
  parse_command<ResumeCommand>({"resume"});
  parse_command<ResetCommand>({"reset"});
  parse_command<StatsCommand>({"stats"});
}

TEST(ControlCommandLine, PersistentForcesAndTorques) {
  EXPECT_TRUE(parse_command<ForceCommand>({"force", "crate", "--force", "1", "0", "0", "--persistent"}).persistent);
  EXPECT_FALSE(parse_command<ForceCommand>({"force", "crate", "--force", "1", "0", "0"}).persistent);
  EXPECT_TRUE(parse_command<TorqueCommand>({"torque", "crate", "--torque", "1", "0", "0", "--persistent"}).persistent);
  expect_usage_error({"force", "crate", "--force", "1", "0", "0", "--persistent", "--duration", "1"});
  expect_usage_error({"torque", "crate", "--torque", "1", "0", "0", "--persistent", "--ticks", "1"});
  expect_usage_error({"impulse", "crate", "--impulse", "1", "0", "0", "--persistent"});
}

TEST(ControlCommandLine, SubscribeFieldsAndEventsAndWatch) {
  const auto plain = parse_command<SubscribeCommand>({"subscribe"});
  EXPECT_FALSE(plain.poses_only);
  EXPECT_FALSE(plain.events);
  const auto pose = parse_command<SubscribeCommand>({"subscribe", "--fields", "pose", "--events"});
  EXPECT_TRUE(pose.poses_only);
  EXPECT_TRUE(pose.events);
  EXPECT_FALSE(parse_command<SubscribeCommand>({"subscribe", "--fields", "all"}).poses_only);
  expect_usage_error({"subscribe", "--fields", "velocity"});

  const auto watch = parse_command<WatchCommand>({"watch", "--bodies", "crate,2", "--count", "3"});
  ASSERT_EQ(watch.bodies.size(), 2u);
  EXPECT_EQ(watch.bodies[1].id(), 2u);
  EXPECT_EQ(watch.rate_hz, 10);
  EXPECT_EQ(watch.count, 3u);
  expect_usage_error({"watch", "--count", "0"});
}

TEST(ControlRequests, BodySpecFromSpawn) {
  SpawnCommand spawn;
  spawn.name = "rock";
  spawn.shape.mutable_sphere()->set_radius(0.5);
  spawn.mass = 2;
  spawn.position = {1, 2, 3};
  spawn.linear_velocity = {0, 0, -1};
  spawn.motion = tumble::v1::MOTION_STATIC;
  spawn.friction = 0.25;
  const tumble::v1::BodySpec spec = make_body_spec(spawn);
  EXPECT_EQ(spec.name(), "rock");
  EXPECT_EQ(spec.shape().sphere().radius(), 0.5);
  EXPECT_EQ(spec.mass(), 2);
  EXPECT_EQ(spec.position().z(), 3);
  EXPECT_EQ(spec.linear_velocity().z(), -1);
  EXPECT_FALSE(spec.has_orientation()) << "identity is the server's default";
  EXPECT_EQ(spec.motion(), tumble::v1::MOTION_STATIC);
  ASSERT_TRUE(spec.has_friction());
  EXPECT_EQ(spec.friction(), 0.25);
  EXPECT_FALSE(spec.has_restitution());
}

TEST(ControlRequests, SetClearSubscribeAndForce) {
  SetCommand set;
  set.body.set_name("crate");
  set.orientation = Quaternion{0.5, 0.5, 0.5, 0.5};
  const tumble::v1::SetBodyState state = make_set_body_state(set);
  EXPECT_FALSE(state.has_position());
  ASSERT_TRUE(state.has_orientation());
  EXPECT_EQ(state.orientation().w(), 0.5);
  EXPECT_FALSE(state.has_linear_velocity());
  EXPECT_FALSE(state.has_angular_velocity());

  EXPECT_FALSE(make_clear_forces(ClearCommand{}).has_body());

  SubscribeCommand subscribe;
  subscribe.poses_only = true;
  subscribe.events = true;
  const tumble::v1::Subscribe request = make_subscribe(subscribe);
  EXPECT_EQ(request.fields(), tumble::v1::POSE_FIELDS_POSE);
  EXPECT_EQ(request.events_size(), 9)
      << "spawned, removed, asleep, awake, reset, diverged, joint added, joint removed, joint broken";
  EXPECT_EQ(make_subscribe(SubscribeCommand{}).events_size(), 0);
  EXPECT_EQ(make_subscribe(SubscribeCommand{}).fields(), tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY);

  const tumble::v1::Subscribe watch = make_watch_subscribe(WatchCommand{});
  EXPECT_EQ(watch.fields(), tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY);
  EXPECT_EQ(watch.events_size(), 4) << "spawned, removed, asleep, awake";

  ForceCommand force;
  force.persistent = true;
  EXPECT_TRUE(make_apply_force(force).persistent());
  EXPECT_EQ(make_apply_force(force).duration_case(), tumble::v1::ApplyForce::DURATION_NOT_SET);
}

tumble::v1::Stats sample_stats() {
  tumble::v1::Stats stats;
  stats.set_request_id(3);
  stats.set_tick(1234);
  stats.set_sim_time(5.1416);
  stats.set_paused(true);
  stats.set_tick_rate_hz(240);
  stats.set_real_time_factor(0.998);
  stats.set_tick_ms_p50(0.125);
  stats.set_tick_ms_p99(1.5);
  stats.set_tick_cpu_ms_p50(0.1);
  stats.set_tick_cpu_ms_p99(0.75);
  stats.set_tick_start_late_ms_p50(0.05);
  stats.set_tick_start_late_ms_p99(2.25);
  stats.set_overruns(2);
  stats.set_bodies(5);
  stats.set_bodies_awake(3);
  stats.set_bodies_asleep(2);
  stats.set_bodies_diverged(1);
  stats.set_clients(4);
  stats.set_connections_refused(7);
  stats.set_clients_closed_for_errors(3);
  stats.set_bytes_sent(123456);
  return stats;
}

TEST(ControlOutput, StatsAsJsonAndText) {
  const nlohmann::json json = nlohmann::json::parse(json_line(stats_json(sample_stats())));
  EXPECT_EQ(json.size(), 20u);
  EXPECT_EQ(json["tick"], 1234);
  EXPECT_EQ(json["sim_time"], 5.1416);
  EXPECT_EQ(json["paused"], true);
  EXPECT_EQ(json["tick_rate_hz"], 240.0);
  EXPECT_EQ(json["tick_ms_p99"], 1.5);
  EXPECT_EQ(json["tick_cpu_ms_p99"], 0.75);
  EXPECT_EQ(json["tick_start_late_ms_p99"], 2.25);
  EXPECT_EQ(json["overruns"], 2);
  EXPECT_EQ(json["bodies"], 5);
  EXPECT_EQ(json["bodies_asleep"], 2);
  EXPECT_EQ(json["bodies_diverged"], 1);
  EXPECT_EQ(json["clients"], 4);
  EXPECT_EQ(json["connections_refused"], 7);
  EXPECT_EQ(json["clients_closed_for_errors"], 3);
  EXPECT_EQ(json["bytes_sent"], 123456);

  const std::string text = format_stats(sample_stats());
  EXPECT_NE(text.find("tick              1234\n"), std::string::npos) << text;
  EXPECT_NE(text.find("paused            yes\n"), std::string::npos) << text;
  EXPECT_NE(text.find("tick time p99     1.500 ms\n"), std::string::npos) << text;
  EXPECT_NE(text.find("tick CPU p99      0.750 ms\n"), std::string::npos) << text;
  EXPECT_NE(text.find("late start p99    2.250 ms\n"), std::string::npos) << text;
  EXPECT_NE(text.find("bodies            5 (3 awake, 2 asleep)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("bodies diverged   1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("refused clients   7\n"), std::string::npos) << text;
  EXPECT_NE(text.find("closed on errors  3\n"), std::string::npos) << text;
}

TEST(ControlOutput, CheckpointsAreABlockOfTheirOwnWhenTheServerWritesThem) {
  tumble::v1::Stats stats = sample_stats();
  EXPECT_EQ(format_stats(stats).find("checkpoints"), std::string::npos);
  EXPECT_FALSE(stats_json(stats).contains("checkpoints"));
  tumble::v1::Checkpoints& checkpoints = *stats.mutable_checkpoints();
  checkpoints.set_destination("bucket tumble_worlds, key demo");
  checkpoints.set_interval_s(1);
  checkpoints.set_written(12);
  checkpoints.set_failed(1);
  checkpoints.set_last_tick(2880);
  checkpoints.set_last_bytes(169004);
  checkpoints.set_last_write_ms(3.25);
  checkpoints.set_write_ms_max(9.5);
  checkpoints.set_last_capture_ms(0.5);
  checkpoints.set_capture_ms_max(1.25);

  const std::string text = format_stats(stats);
  const std::size_t block = text.find("\ncheckpoints\n");
  ASSERT_NE(block, std::string::npos) << text;
  EXPECT_EQ(text.substr(block + 1),
            "checkpoints\n"
            "  to       bucket tumble_worlds, key demo\n"
            "  every    1.000 s\n"
            "  written  12\n"
            "  failed   1\n"
            "  last     tick 2880, 169004 bytes\n"
            "  capture  0.500 ms (longest 1.250 ms)\n"
            "  write    3.250 ms (longest 9.500 ms)\n");
  EXPECT_EQ(json_line(stats_json(stats)["checkpoints"]),
            "{\"destination\": \"bucket tumble_worlds, key demo\", \"interval_s\": 1.0, \"written\": 12, "
            "\"failed\": 1, \"last_tick\": 2880, \"last_bytes\": 169004, \"last_write_ms\": 3.25, "
            "\"write_ms_max\": 9.5, \"last_capture_ms\": 0.5, \"capture_ms_max\": 1.25}\n");

  checkpoints.set_written(0);
  EXPECT_NE(format_stats(stats).find("  last     -\n"), std::string::npos) << "nothing written yet";
}

TEST(ControlOutput, AcksOfSpawnPauseAndStep) {
  tumble::v1::Ack ack;
  ack.set_request_id(2);
  ack.set_applied_tick(77);
  EXPECT_EQ(format_paused(ack), "paused at tick 77\n");
  EXPECT_EQ(format_stepped(ack), "stepped to tick 77\n");
  EXPECT_EQ(json_line(ack_json(ack)), "{\"applied_tick\": 77, \"request_id\": 2}\n") << "no body_id unless spawned";
  ack.set_body_id(0);
  EXPECT_EQ(format_spawned(ack), "spawned body 0 at tick 77\n");
  EXPECT_EQ(json_line(ack_json(ack)), "{\"body_id\": 0, \"applied_tick\": 77, \"request_id\": 2}\n");
}

TEST(ControlOutput, AStepSaysWhatCutItShortAndHowManyTicksItLeft) {
  tumble::v1::Ack ack;
  ack.set_request_id(3);
  ack.set_applied_tick(1234);
  ack.set_step_ticks_left(0);
  ack.set_step_ended_by(tumble::v1::STEP_END_COMPLETED);
  EXPECT_EQ(format_stepped(ack), "stepped to tick 1234\n");
  EXPECT_EQ(json_line(ack_json(ack)),
            "{\"applied_tick\": 1234, \"request_id\": 3, \"step_ended_by\": \"completed\", \"step_ticks_left\": 0}\n");
  const std::pair<tumble::v1::StepEnd, const char*> ends[] = {{tumble::v1::STEP_END_PAUSE, "pause"},
                                                              {tumble::v1::STEP_END_RESUME, "resume"},
                                                              {tumble::v1::STEP_END_RESET, "reset"}};
  for (const auto& [end, word] : ends) {
    ack.set_step_ended_by(end);
    ack.set_step_ticks_left(766);
    EXPECT_EQ(format_stepped(ack),
              "stepped to tick 1234, cut short by a " + std::string(word) + " with 766 ticks left\n");
    EXPECT_EQ(json_line(ack_json(ack)), "{\"applied_tick\": 1234, \"request_id\": 3, \"step_ended_by\": \"" +
                                            std::string(word) + "\", \"step_ticks_left\": 766}\n");
  }
}

TEST(ControlOutput, WorldEvents) {
  tumble::v1::WorldEvent event;
  event.set_tick(12);
  event.set_kind(tumble::v1::WORLD_EVENT_BODY_ASLEEP);
  event.set_body_id(7);
  event.set_body_name("crate");
  EXPECT_EQ(format_world_event(event), "tick 12  asleep  crate (#7)\n");
  EXPECT_EQ(json_line(world_event_json(event)),
            "{\"event\": \"asleep\", \"tick\": 12, \"id\": 7, \"name\": \"crate\"}\n");
  event.set_body_name("");
  EXPECT_EQ(format_world_event(event), "tick 12  asleep  #7\n");
  event.set_kind(tumble::v1::WORLD_EVENT_BODY_DIVERGED);
  event.set_body_name("flea");
  EXPECT_EQ(format_world_event(event), "tick 12  diverged  flea (#7)\n");
  EXPECT_EQ(json_line(world_event_json(event)),
            "{\"event\": \"diverged\", \"tick\": 12, \"id\": 7, \"name\": \"flea\"}\n");
  event.set_kind(tumble::v1::WORLD_EVENT_WORLD_RESET);
  EXPECT_EQ(format_world_event(event), "tick 12  reset\n");
  EXPECT_EQ(json_line(world_event_json(event)), "{\"event\": \"reset\", \"tick\": 12}\n");
}

client::PoseSample watch_sample() {
  client::PoseSample sample;
  sample.tick = 480;
  sample.sim_time = 2;
  client::BodyPose crate;
  crate.id = 0;
  crate.position = {1.f, 0.5f, 0.f};
  crate.linear_velocity = {3.f, 4.f, 0.f};
  client::BodyPose unnamed;
  unnamed.id = 7;
  unnamed.position = {-2.f, 0.f, 10.f};
  sample.bodies = {crate, unnamed};
  return sample;
}

WatchState crate_asleep() {
  tumble::v1::BodyList list;
  auto* crate = list.add_bodies();
  crate->set_id(0);
  crate->set_name("crate");
  crate->set_asleep(true);
  WatchState state;
  state.load(list);
  return state;
}

TEST(ControlOutput, WatchTable) {
  EXPECT_EQ(format_watch_table(watch_sample(), crate_asleep()),
            "tick 480  t=2.000s\n"
            "NAME   POSITION (m)             SPEED (m/s)  ASLEEP\n"
            "crate  (1.000, 0.500, 0.000)          5.000  yes\n"
            "#7     (-2.000, 0.000, 10.000)        0.000  no\n");
  const nlohmann::json json = nlohmann::json::parse(json_line(watch_json(watch_sample(), crate_asleep())));
  EXPECT_EQ(json["tick"], 480);
  ASSERT_EQ(json["bodies"].size(), 2u);
  EXPECT_EQ(json["bodies"][0]["name"], "crate");
  EXPECT_EQ(json["bodies"][0]["speed"], 5.0);
  EXPECT_EQ(json["bodies"][0]["asleep"], true);
  EXPECT_EQ(json["bodies"][1]["name"], "");
}

TEST(ControlOutput, PoseOnlySamplesLeaveOutVelocities) {
  client::PoseSample sample = watch_sample();
  sample.has_velocities = false;
  const std::string text = format_pose_sample(sample, {});
  EXPECT_EQ(text.find(" v ("), std::string::npos) << text;
  EXPECT_NE(text.find("quat ["), std::string::npos) << text;
  const nlohmann::json json = nlohmann::json::parse(json_line(pose_sample_json(sample, {})));
  EXPECT_FALSE(json["bodies"][0].contains("linear_velocity"));
  EXPECT_FALSE(json["bodies"][0].contains("angular_velocity"));
  EXPECT_TRUE(json["bodies"][0].contains("orientation"));
}

TEST(WatchStateTest, EventsKeepNamesAndSleepCurrent) {
  WatchState state = crate_asleep();
  EXPECT_EQ(state.name(0), "crate");
  EXPECT_TRUE(state.asleep(0));
  tumble::v1::WorldEvent event;
  event.set_kind(tumble::v1::WORLD_EVENT_BODY_AWAKE);
  event.set_body_id(0);
  state.apply(event);
  EXPECT_FALSE(state.asleep(0));
  event.set_kind(tumble::v1::WORLD_EVENT_BODY_SPAWNED);
  event.set_body_id(9);
  event.set_body_name("rock");
  state.apply(event);
  EXPECT_EQ(state.name(9), "rock");
  EXPECT_FALSE(state.asleep(9));
  event.set_kind(tumble::v1::WORLD_EVENT_BODY_REMOVED);
  state.apply(event);
  EXPECT_EQ(state.name(9), "");
  event.set_kind(tumble::v1::WORLD_EVENT_WORLD_RESET);
  event.set_body_id(0);
  state.apply(event);
  EXPECT_EQ(state.name(0), "crate") << "a reset alone changes nothing it knows";
}

}  // namespace
}  // namespace tumble::cli
