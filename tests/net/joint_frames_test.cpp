// Joint states in pose frames on a real socket: a subscription with joints
// gets every joint's state in each frame, in every encoding and whatever
// its bodies, the same values ListJoints gives for that tick; a Step's
// frame carries them when asked; a subscription without joints has none.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "raw_client.h"
#include "replies.h"
#include "test_server.h"

namespace tumble::test {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// A plank on a hinge from the world, level, so it swings down; a bob on a
// rope, pushed sideways; a ball that no joint holds.
const char* kScene = R"({"bodies": [
    {"name": "plank", "shape": {"box": {"half_extents": [0.5, 0.05, 0.05]}}, "mass": 2, "position": [0.5, 2, 0]},
    {"name": "bob", "shape": {"sphere": {"radius": 0.1}}, "mass": 1, "position": [3, 1, 0],
     "linear_velocity": [1, 0, 0]},
    {"name": "ball", "shape": {"sphere": {"radius": 0.2}}, "mass": 1, "position": [10, 0, 0]}],
  "joints": [
    {"name": "hinge", "type": "hinge", "body_a": "world", "body_b": "plank", "anchor": [0, 2, 0], "axis": [0, 0, 1]},
    {"name": "rope", "type": "distance", "body_a": "world", "body_b": "bob", "anchor_a": [3, 2, 0],
     "anchor_b": [3, 1, 0]}]})";

ClientMessage subscribe_to_joints(std::uint64_t id, tumble::v1::PoseEncoding encoding, bool joints,
                                  const char* body = nullptr) {
  ClientMessage m;
  m.set_request_id(id);
  m.mutable_subscribe()->set_encoding(encoding);
  m.mutable_subscribe()->set_joints(joints);
  if (body != nullptr) m.mutable_subscribe()->add_bodies()->set_name(body);
  return m;  // rate 0: a frame every tick
}

class JointFramesTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(client_.handshake()); }

  // Sends `message` and returns its reply, skipping what comes before it.
  ServerMessage call(const ClientMessage& message) {
    EXPECT_TRUE(client_.send(message));
    const std::uint64_t id = message.request_id();
    auto reply = client_.read_until([&](const ServerMessage& m) { return is_reply_to(m, id); });
    EXPECT_TRUE(reply.has_value()) << "no reply to request " << id;
    return reply.value_or(ServerMessage{});
  }

  std::uint32_t subscribed(const ClientMessage& request) {
    const ServerMessage reply = call(request);
    EXPECT_TRUE(reply.has_subscribed()) << reply.DebugString();
    return reply.subscribed().subscription_id();
  }

  TestServer server_{kScene};
  RawClient client_{server_.port()};
};

// Whether `frame` carries exactly the joints of `list`, with their states
// as float32.
void expect_joints_of(const tumble::v1::PoseFrame& frame, const tumble::v1::JointList& list, const char* what) {
  ASSERT_EQ(frame.joint_ids_size(), list.joints_size()) << what;
  ASSERT_EQ(frame.joint_positions_size(), list.joints_size()) << what;
  ASSERT_EQ(frame.joint_speeds_size(), list.joints_size()) << what;
  ASSERT_EQ(frame.joint_motor_impulses_size(), list.joints_size()) << what;
  for (int i = 0; i < list.joints_size(); ++i) {
    const tumble::v1::JointInfo& joint = list.joints(i);
    EXPECT_EQ(frame.joint_ids(i), joint.id()) << what;
    EXPECT_EQ(frame.joint_positions(i), static_cast<float>(joint.state().position())) << what << " joint " << i;
    EXPECT_EQ(frame.joint_speeds(i), static_cast<float>(joint.state().speed())) << what << " joint " << i;
    EXPECT_EQ(frame.joint_motor_impulses(i), static_cast<float>(joint.state().motor_impulse())) << what;
  }
}

TEST_F(JointFramesTest, EveryEncodingCarriesEveryJointsStateAtItsTick) {
  ClientMessage pause;
  pause.set_request_id(1);
  pause.mutable_pause();
  ASSERT_TRUE(call(pause).has_ack());
  // The FULL stream follows the ball alone: the joints come all the same.
  const std::uint32_t full = subscribed(subscribe_to_joints(2, tumble::v1::POSE_ENCODING_FULL, true, "ball"));
  const std::uint32_t quantized = subscribed(subscribe_to_joints(3, tumble::v1::POSE_ENCODING_QUANTIZED, true));
  const std::uint32_t delta = subscribed(subscribe_to_joints(4, tumble::v1::POSE_ENCODING_DELTA, true));
  const std::uint32_t without = subscribed(subscribe_to_joints(5, tumble::v1::POSE_ENCODING_FULL, false));

  // Steps `ticks` and reads the stepped ticks' frames and the Step's Ack,
  // in whatever order they come, until every stream's frame of the last
  // tick is in; returns the Ack.
  std::map<std::uint32_t, std::map<std::uint64_t, tumble::v1::PoseFrame>> frames;
  const auto step = [&](std::uint64_t request_id, std::uint32_t ticks) -> std::optional<ServerMessage> {
    ClientMessage request;
    request.set_request_id(request_id);
    request.mutable_step()->set_ticks(ticks);
    request.mutable_step()->set_reply_frame(true);
    request.mutable_step()->set_frame_joints(true);
    if (!client_.send(request)) return std::nullopt;
    std::optional<ServerMessage> ack;
    const auto has_last = [&](std::uint32_t id) { return ack && frames[id].count(ack->ack().applied_tick()) > 0; };
    while (!(has_last(full) && has_last(quantized) && has_last(delta) && has_last(without))) {
      const auto m =
          client_.read_until([&](const ServerMessage& r) { return r.has_pose_frame() || is_reply_to(r, request_id); });
      if (!m) return std::nullopt;
      if (m->has_pose_frame()) {
        frames[m->pose_frame().subscription_id()][m->pose_frame().tick()] = m->pose_frame();
      } else {
        if (!m->has_ack()) return std::nullopt;
        ack = *m;
      }
    }
    return ack;
  };
  // One tick first, so that the DELTA stream has sent its key frame: a
  // publication takes the newest snapshot, so on a busy machine the 30
  // ticks below may come as a single frame, which would be the stream's
  // first and a key frame.
  ASSERT_TRUE(step(6, 1)) << "the first Step's Ack and every stream's frame of its tick";
  const std::optional<ServerMessage> ack = step(8, 30);
  ASSERT_TRUE(ack) << "the Step's Ack and every stream's frame of its last tick";
  const std::uint64_t tick = ack->ack().applied_tick();

  ClientMessage list_joints;
  list_joints.set_request_id(7);
  list_joints.mutable_list_joints();
  const ServerMessage listed = call(list_joints);
  ASSERT_TRUE(listed.has_joint_list());
  const tumble::v1::JointList& list = listed.joint_list();
  ASSERT_EQ(list.tick(), tick) << "paused: the list shows the Step's last tick";
  ASSERT_EQ(list.joints_size(), 2);
  EXPECT_GT(std::abs(list.joints(0).state().speed()), 0.5) << "the plank swings: the values say something";

  expect_joints_of(frames[full][tick], list, "FULL, one body");
  EXPECT_EQ(frames[full][tick].ids_size(), 1);
  expect_joints_of(frames[quantized][tick], list, "QUANTIZED");
  EXPECT_FALSE(frames[delta][tick].key_frame()) << "a change frame, after the key frame at the start";
  expect_joints_of(frames[delta][tick], list, "DELTA change");
  expect_joints_of(ack->ack().frame(), list, "the Step's frame");
  EXPECT_EQ(frames[without][tick].joint_ids_size(), 0);
  EXPECT_EQ(frames[without][tick].joint_positions_size(), 0);
}

}  // namespace
}  // namespace tumble::test
