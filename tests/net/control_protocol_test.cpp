// The world-editing, clock, stats and event messages on a real socket:
// what each request is answered with, what subscribers see, and that the
// stream stays usable after a refusal.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "raw_client.h"
#include "replies.h"
#include "requests.h"
#include "test_scenes.h"
#include "test_server.h"
#include "wire/frame.h"

namespace tumble::test {
namespace {

using namespace std::chrono_literals;
using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

ClientMessage empty_request(std::uint64_t id, void (*kind)(ClientMessage&)) {
  ClientMessage m;
  m.set_request_id(id);
  kind(m);
  return m;
}

ClientMessage pause(std::uint64_t id) {
  return empty_request(id, [](ClientMessage& m) { m.mutable_pause(); });
}
ClientMessage resume(std::uint64_t id) {
  return empty_request(id, [](ClientMessage& m) { m.mutable_resume(); });
}
ClientMessage step(std::uint64_t id, std::uint32_t ticks) {
  ClientMessage m;
  m.set_request_id(id);
  m.mutable_step()->set_ticks(ticks);
  return m;
}

ClientMessage subscribe_to_fields(std::uint64_t id, double rate_hz, tumble::v1::PoseFields fields,
                                  std::initializer_list<tumble::v1::WorldEventKind> events = {},
                                  std::initializer_list<const char*> bodies = {}) {
  ClientMessage m;
  m.set_request_id(id);
  m.mutable_subscribe()->set_rate_hz(rate_hz);
  m.mutable_subscribe()->set_fields(fields);
  for (auto kind : events) m.mutable_subscribe()->add_events(kind);
  for (const char* name : bodies) m.mutable_subscribe()->add_bodies()->set_name(name);
  return m;
}

class ControlProtocolTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(client_.handshake()); }

  // Sends `message` and returns its reply, skipping frames and keeping the
  // world events that arrive first in events_.
  ServerMessage call(const ClientMessage& message) {
    EXPECT_TRUE(client_.send(message));
    const std::uint64_t id = message.request_id();
    auto reply = client_.read_until([&](const ServerMessage& m) {
      if (m.has_world_event()) events_.push_back(m.world_event());
      return is_reply_to(m, id);
    });
    EXPECT_TRUE(reply.has_value()) << "no reply to request " << id;
    return reply.value_or(ServerMessage{});
  }

  TestServer server_{kCrateAndBallScene};
  RawClient client_{server_.port()};
  std::vector<tumble::v1::WorldEvent> events_;
};

TEST_F(ControlProtocolTest, SpawnIsAckedWithTheNewBodysId) {
  const ServerMessage reply = call(spawn_sphere(1, "rock", 0.25));
  ASSERT_TRUE(reply.has_ack()) << reply.DebugString();
  ASSERT_TRUE(reply.ack().has_body_id());
  EXPECT_EQ(reply.ack().body_id(), 2u);
  EXPECT_GT(reply.ack().applied_tick(), 0u);

  ClientMessage list;
  list.set_request_id(2);
  list.mutable_list_bodies();
  const ServerMessage bodies = call(list);
  ASSERT_EQ(bodies.body_list().bodies_size(), 3);
  EXPECT_EQ(bodies.body_list().bodies(2).name(), "rock");
  EXPECT_DOUBLE_EQ(bodies.body_list().bodies(2).shape().sphere().radius(), 0.25);
  EXPECT_FALSE(bodies.body_list().bodies(2).asleep());
}

// A kinematic body standing still has no velocity and no mass either, like
// a static one: only the motion tells them apart.
TEST_F(ControlProtocolTest, TheBodyListSaysHowEachBodyMoves) {
  ClientMessage wall = spawn_sphere(1, "wall", 0.5);
  wall.mutable_spawn_body()->mutable_body()->set_motion(tumble::v1::MOTION_STATIC);
  ASSERT_TRUE(call(wall).has_ack());
  ClientMessage lift = spawn_sphere(2, "lift", 0.5);
  lift.mutable_spawn_body()->mutable_body()->set_motion(tumble::v1::MOTION_KINEMATIC);
  ASSERT_TRUE(call(lift).has_ack());

  ClientMessage list;
  list.set_request_id(3);
  list.mutable_list_bodies();
  const ServerMessage bodies = call(list);
  ASSERT_EQ(bodies.body_list().bodies_size(), 4);
  EXPECT_EQ(bodies.body_list().bodies(0).name(), "crate");
  EXPECT_EQ(bodies.body_list().bodies(0).motion(), tumble::v1::MOTION_DYNAMIC);
  EXPECT_EQ(bodies.body_list().bodies(2).name(), "wall");
  EXPECT_EQ(bodies.body_list().bodies(2).motion(), tumble::v1::MOTION_STATIC);
  EXPECT_EQ(bodies.body_list().bodies(3).name(), "lift");
  EXPECT_EQ(bodies.body_list().bodies(3).motion(), tumble::v1::MOTION_KINEMATIC);
  EXPECT_EQ(bodies.body_list().bodies(3).mass(), 0);
}

TEST_F(ControlProtocolTest, ABadSpawnGetsInvalidArgumentAndTheSessionGoesOn) {
  const ServerMessage negative = call(spawn_sphere(1, "rock", -1));
  ASSERT_TRUE(negative.has_error());
  EXPECT_EQ(negative.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_NE(negative.error().message().find("body.shape.sphere.radius"), std::string::npos)
      << negative.error().message();
  const ServerMessage duplicate = call(spawn_sphere(2, "ball", 1));
  ASSERT_TRUE(duplicate.has_error());
  EXPECT_EQ(duplicate.error().code(), tumble::v1::INVALID_ARGUMENT);
  EXPECT_TRUE(call(spawn_sphere(3, "rock", 1)).has_ack());
}

TEST_F(ControlProtocolTest, RemoveAndSetAreAcked) {
  ClientMessage set;
  set.set_request_id(1);
  set.mutable_set_body_state()->mutable_body()->set_name("ball");
  set.mutable_set_body_state()->mutable_position()->set_z(-4);
  ASSERT_TRUE(call(set).has_ack());
  ClientMessage remove;
  remove.set_request_id(2);
  remove.mutable_remove_body()->mutable_body()->set_name("ball");
  ASSERT_TRUE(call(remove).has_ack());
  remove.set_request_id(3);
  const ServerMessage again = call(remove);
  ASSERT_TRUE(again.has_error());
  EXPECT_EQ(again.error().code(), tumble::v1::UNKNOWN_BODY);
  EXPECT_EQ(server_.sim().body_count(), 1u);
}

TEST_F(ControlProtocolTest, PauseStepResumeAnswerWithTheirTicks) {
  const ServerMessage step_running = call(step(1, 5));
  ASSERT_TRUE(step_running.has_error());
  EXPECT_EQ(step_running.error().code(), tumble::v1::FAILED_PRECONDITION);

  const ServerMessage paused = call(pause(2));
  ASSERT_TRUE(paused.has_ack());
  const std::uint64_t at = paused.ack().applied_tick();
  const ServerMessage stepped = call(step(3, 5));
  ASSERT_TRUE(stepped.has_ack()) << stepped.DebugString();
  EXPECT_EQ(stepped.ack().applied_tick(), at + 5);
  const ServerMessage stats = call(get_stats(4));
  EXPECT_EQ(stats.stats().tick(), at + 5);
  EXPECT_TRUE(stats.stats().paused());

  const ServerMessage resumed = call(resume(5));
  ASSERT_TRUE(resumed.has_ack());
  EXPECT_EQ(resumed.ack().applied_tick(), at + 6);
  EXPECT_FALSE(call(get_stats(6)).stats().paused());
}

TEST_F(ControlProtocolTest, StatsCountTheClientsAndTheBytesSent) {
  RawClient other(server_.port());
  ASSERT_TRUE(other.handshake());
  const ServerMessage first = call(get_stats(1));
  ASSERT_TRUE(first.has_stats()) << first.DebugString();
  EXPECT_EQ(first.stats().clients(), 2u);
  EXPECT_EQ(first.stats().bodies(), 2u);
  EXPECT_DOUBLE_EQ(first.stats().tick_rate_hz(), 240);
  EXPECT_GT(first.stats().bytes_sent(), 0u) << "two Welcomes at least";
  const ServerMessage second = call(get_stats(2));
  // Nothing else was written since (no subscriptions): the first Stats,
  // its frame exactly.
  EXPECT_EQ(second.stats().bytes_sent() - first.stats().bytes_sent(), wire::encode_frame(first).size());
}

TEST_F(ControlProtocolTest, PoseOnlyFramesCarryNoVelocities) {
  ASSERT_TRUE(call(subscribe_to_fields(1, 60, tumble::v1::POSE_FIELDS_POSE)).has_subscribed());
  const auto frame = client_.read_until([](const ServerMessage& m) { return m.has_pose_frame(); });
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->pose_frame().ids_size(), 2);
  EXPECT_EQ(frame->pose_frame().positions_size(), 6);
  EXPECT_EQ(frame->pose_frame().orientations_size(), 8);
  EXPECT_EQ(frame->pose_frame().linear_velocities_size(), 0);
  EXPECT_EQ(frame->pose_frame().angular_velocities_size(), 0);

  ASSERT_TRUE(call(subscribe_to_fields(2, 60, tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY)).has_subscribed());
  const auto full = client_.read_until(
      [](const ServerMessage& m) { return m.has_pose_frame() && m.pose_frame().linear_velocities_size() > 0; });
  ASSERT_TRUE(full) << "the default, pose and velocity, has velocities";
  EXPECT_EQ(full->pose_frame().angular_velocities_size(), 6);
}

TEST_F(ControlProtocolTest, ASubscriptionWhilePausedGetsTheCurrentStateAndThenNothing) {
  const std::uint64_t at = call(pause(1)).ack().applied_tick();
  const ServerMessage subscribed = call(subscribe_to_fields(2, 240, tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY));
  ASSERT_TRUE(subscribed.has_subscribed());
  const auto first = client_.read_until([](const ServerMessage& m) { return m.has_pose_frame(); });
  ASSERT_TRUE(first) << "the current state at once, paused or not";
  EXPECT_EQ(first->pose_frame().tick(), at);
  // Two requests, each answered by a pass of the sim loop after the one
  // before: a pass that stepped would have sent a frame before the second
  // reply. Nothing but the replies arrives.
  for (const std::uint64_t id : {std::uint64_t{3}, std::uint64_t{4}}) {
    std::vector<std::uint64_t> frame_ticks;
    ASSERT_TRUE(client_.send(list_bodies(id)));
    ASSERT_TRUE(client_.read_until([&](const ServerMessage& m) {
      if (m.has_pose_frame()) frame_ticks.push_back(m.pose_frame().tick());
      return is_reply_to(m, id);
    })) << "no reply to request "
        << id;
    EXPECT_TRUE(frame_ticks.empty()) << "a frame of tick " << frame_ticks.front() << " while paused at " << at;
  }
}

TEST_F(ControlProtocolTest, AnEditWhilePausedReachesSubscribersAtOnce) {
  const std::uint64_t at = call(pause(1)).ack().applied_tick();
  ASSERT_TRUE(call(subscribe_to_fields(2, 30, tumble::v1::POSE_FIELDS_POSE, {}, {"ball"})).has_subscribed());
  ASSERT_TRUE(client_.read_until([](const ServerMessage& m) { return m.has_pose_frame(); }));
  ClientMessage set;
  set.set_request_id(3);
  set.mutable_set_body_state()->mutable_body()->set_name("ball");
  set.mutable_set_body_state()->mutable_position()->set_y(2);
  ASSERT_TRUE(call(set).has_ack());
  const auto frame = client_.read_until([](const ServerMessage& m) { return m.has_pose_frame(); });
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->pose_frame().tick(), at);
  EXPECT_FLOAT_EQ(frame->pose_frame().positions(1), 2.0f);
}

TEST_F(ControlProtocolTest, SubscribersHearOfSpawnsAndRemovalsBeforeTheFrame) {
  const ServerMessage subscribed =
      call(subscribe_to_fields(1, 30, tumble::v1::POSE_FIELDS_POSE,
                               {tumble::v1::WORLD_EVENT_BODY_SPAWNED, tumble::v1::WORLD_EVENT_BODY_REMOVED}));
  ASSERT_TRUE(subscribed.has_subscribed());
  const std::uint32_t subscription = subscribed.subscribed().subscription_id();
  ASSERT_TRUE(client_.send(spawn_sphere(2, "rock", 0.5)));
  std::uint64_t applied = 0;
  std::uint64_t event_tick = 0;
  bool frame_with_rock = false;
  // Read until a frame shows the rock: the event must have come before it.
  for (int i = 0; i < 100 && !frame_with_rock; ++i) {
    const auto m = client_.read();
    ASSERT_TRUE(m);
    if (is_reply_to(*m, 2)) applied = m->ack().applied_tick();
    if (m->has_world_event()) {
      const auto& event = m->world_event();
      EXPECT_EQ(event.subscription_id(), subscription);
      EXPECT_EQ(event.kind(), tumble::v1::WORLD_EVENT_BODY_SPAWNED);
      EXPECT_EQ(event.body_id(), 2u);
      EXPECT_EQ(event.body_name(), "rock");
      event_tick = event.tick();
    }
    if (m->has_pose_frame() && m->pose_frame().ids_size() == 3) {
      frame_with_rock = true;
      EXPECT_NE(event_tick, 0u) << "the event comes before the first frame that shows the body";
    }
  }
  ASSERT_TRUE(frame_with_rock);
  EXPECT_EQ(event_tick, applied);

  ClientMessage remove;
  remove.set_request_id(3);
  remove.mutable_remove_body()->mutable_body()->set_id(2);
  ASSERT_TRUE(client_.send(remove));
  const auto removed = client_.read_until([](const ServerMessage& m) { return m.has_world_event(); });
  ASSERT_TRUE(removed);
  EXPECT_EQ(removed->world_event().kind(), tumble::v1::WORLD_EVENT_BODY_REMOVED);
  EXPECT_EQ(removed->world_event().body_name(), "rock");
}

TEST_F(ControlProtocolTest, ANamedSubscriptionHearsOnlyOfItsBodiesAndOfResets) {
  const ServerMessage subscribed = call(subscribe_to_fields(
      1, 30, tumble::v1::POSE_FIELDS_POSE,
      {tumble::v1::WORLD_EVENT_BODY_SPAWNED, tumble::v1::WORLD_EVENT_BODY_REMOVED, tumble::v1::WORLD_EVENT_WORLD_RESET},
      {"ball"}));
  ASSERT_TRUE(subscribed.has_subscribed());
  ASSERT_TRUE(call(spawn_sphere(2, "rock", 0.5)).has_ack());
  ClientMessage remove;
  remove.set_request_id(3);
  remove.mutable_remove_body()->mutable_body()->set_name("ball");
  ASSERT_TRUE(call(remove).has_ack());
  ClientMessage reset;
  reset.set_request_id(4);
  reset.mutable_reset();
  ASSERT_TRUE(call(reset).has_ack());
  // Every event of those ticks arrives before the replies to two later
  // requests, each answered by a later pass of the sim loop.
  for (const std::uint64_t id : {std::uint64_t{5}, std::uint64_t{6}}) {
    ASSERT_TRUE(client_.send(list_bodies(id)));
    ASSERT_TRUE(client_.read_until([&](const ServerMessage& m) {
      if (m.has_world_event()) events_.push_back(m.world_event());
      return is_reply_to(m, id);
    })) << "no reply to request "
        << id;
  }
  std::vector<tumble::v1::WorldEventKind> kinds;
  for (const auto& event : events_) kinds.push_back(event.kind());
  // Not the rock's spawn; the ball's removal; the reset; not the ball's return (it left the filter).
  EXPECT_EQ(kinds, (std::vector<tumble::v1::WorldEventKind>{tumble::v1::WORLD_EVENT_BODY_REMOVED,
                                                            tumble::v1::WORLD_EVENT_WORLD_RESET}));
}

TEST_F(ControlProtocolTest, AnUnknownEventKindIsInvalid) {
  ClientMessage m = subscribe_to_fields(1, 30, tumble::v1::POSE_FIELDS_POSE);
  m.mutable_subscribe()->add_events(static_cast<tumble::v1::WorldEventKind>(99));
  const ServerMessage reply = call(m);
  ASSERT_TRUE(reply.has_error());
  EXPECT_EQ(reply.error().code(), tumble::v1::INVALID_ARGUMENT);
}

TEST_F(ControlProtocolTest, AStreamOfFewerBodiesIsSentFirstInItsTick) {
  // Publisher order: cheapest stream first, whatever order they were made in.
  const std::uint64_t at = call(pause(1)).ack().applied_tick();
  // Each stream's first frame (of the paused tick) is read before the step:
  // one still unsent would be replaced in its place in the queue by the
  // stepped tick's, and the order read would be the order of subscribing.
  const auto subscribe_and_read_first_frame = [&](const ClientMessage& subscribe) {
    EXPECT_TRUE(client_.send(subscribe));
    ServerMessage reply;
    bool framed = false;
    EXPECT_TRUE(client_.read_until([&](const ServerMessage& m) {
      if (is_reply_to(m, subscribe.request_id())) reply = m;
      // Paused: the only frame is the new stream's first.
      framed = framed || (m.has_pose_frame() && m.pose_frame().tick() == at);
      return reply.has_subscribed() && framed;
    })) << "the Subscribed reply and the first frame of request "
        << subscribe.request_id();
    return reply;
  };
  const ServerMessage all = subscribe_and_read_first_frame(subscribe_to_fields(2, 240, tumble::v1::POSE_FIELDS_POSE));
  const ServerMessage ball =
      subscribe_and_read_first_frame(subscribe_to_fields(3, 240, tumble::v1::POSE_FIELDS_POSE, {}, {"ball"}));
  ASSERT_TRUE(all.has_subscribed() && ball.has_subscribed());
  // The frames of the stepped tick may come before the Step's Ack or after
  // it, so both are read together.
  ASSERT_TRUE(client_.send(step(4, 1)));
  std::vector<std::uint32_t> order;
  bool acked = false;
  while (order.size() < 2 || !acked) {
    const auto m =
        client_.read_until([](const ServerMessage& reply) { return reply.has_pose_frame() || is_reply_to(reply, 4); });
    ASSERT_TRUE(m) << "the Step's Ack and two frames of tick " << at + 1;
    if (is_reply_to(*m, 4)) {
      ASSERT_TRUE(m->has_ack());
      acked = true;
    } else if (m->pose_frame().tick() == at + 1) {
      order.push_back(m->pose_frame().subscription_id());
    }
  }
  ASSERT_EQ(order.size(), 2u);
  EXPECT_EQ(order[0], ball.subscribed().subscription_id());
  EXPECT_EQ(order[1], all.subscribed().subscription_id());
}

TEST_F(ControlProtocolTest, TheTickRateChangesForSubscriptionsMadeAfter) {
  ClientMessage rate;
  rate.set_request_id(1);
  rate.mutable_set_tick_rate()->set_rate_hz(120);
  ASSERT_TRUE(call(rate).has_ack());
  EXPECT_DOUBLE_EQ(call(get_stats(2)).stats().tick_rate_hz(), 120);
  const ServerMessage subscribed = call(subscribe_to_fields(3, 30, tumble::v1::POSE_FIELDS_POSE));
  EXPECT_EQ(subscribed.subscribed().period_ticks(), 4u);
  EXPECT_DOUBLE_EQ(subscribed.subscribed().rate_hz(), 30);
  RawClient late(server_.port());
  const auto welcome = late.handshake();
  ASSERT_TRUE(welcome && welcome->has_welcome());
  EXPECT_DOUBLE_EQ(welcome->welcome().tick_rate_hz(), 120);
}

}  // namespace
}  // namespace tumble::test
