// Pose encodings over a real socket: QUANTIZED and DELTA frames decode to
// the bodies FULL frames show, within the grids, in the sizes promised.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "raw_client.h"
#include "test_server.h"
#include "wire/quantized_poses.h"

namespace tumble::test {
namespace {

using tumble::v1::ClientMessage;
using tumble::v1::ServerMessage;

// 901 spheres in zero gravity, 30 x 30 on a 0.5 m grid plus one more on the
// next row, none touching; with a mover, body 901 drifts along x.
std::string grid_scene(bool with_mover) {
  std::string scene = R"({"gravity": [0, 0, 0], "bodies": [)";
  for (int i = 0; i < 901; ++i) {
    if (i > 0) scene += ",";
    scene += R"({"shape": {"sphere": {"radius": 0.2}}, "mass": 1, "position": [)" + std::to_string(0.5 * (i % 30)) +
             ", " + std::to_string(0.5 * (i / 30)) + ", 1.25]}";
  }
  if (with_mover) {
    scene += R"(, {"name": "mover", "shape": {"sphere": {"radius": 0.2}}, "mass": 1, "position": [-3, -3, 0],
                  "linear_velocity": [1, 0, 0]})";
  }
  return scene + "]}";
}

ClientMessage subscribe_encoded(std::uint64_t id, tumble::v1::PoseEncoding encoding, tumble::v1::PoseFields fields,
                                double rate_hz = 30) {
  ClientMessage m;
  m.set_request_id(id);
  m.mutable_subscribe()->set_rate_hz(rate_hz);
  m.mutable_subscribe()->set_fields(fields);
  m.mutable_subscribe()->set_encoding(encoding);
  return m;
}

// Subscribes and returns the Subscribed reply.
tumble::v1::Subscribed subscribed(RawClient& client, const ClientMessage& request) {
  EXPECT_TRUE(client.send(request));
  const auto reply = client.read_until([](const ServerMessage& m) { return m.has_subscribed() || m.has_error(); });
  EXPECT_TRUE(reply && reply->has_subscribed()) << (reply ? reply->DebugString() : "no reply");
  return reply ? reply->subscribed() : tumble::v1::Subscribed{};
}

std::optional<tumble::v1::PoseFrame> next_frame(RawClient& client) {
  const auto message = client.read_until([](const ServerMessage& m) { return m.has_pose_frame(); });
  if (!message) return std::nullopt;
  return message->pose_frame();
}

// Bytes the frame took on the wire, length prefix included.
double wire_bytes(const tumble::v1::PoseFrame& frame) {
  ServerMessage message;
  *message.mutable_pose_frame() = frame;
  return static_cast<double>(wire::encode_frame(message).size());
}

TEST(PoseEncoding, QuantizedPoseOnlyFramesTakeAtMostTenBytesPerBody) {
  TestServer server(grid_scene(false));
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  const auto reply =
      subscribed(client, subscribe_encoded(1, tumble::v1::POSE_ENCODING_QUANTIZED, tumble::v1::POSE_FIELDS_POSE));
  EXPECT_EQ(reply.encoding(), tumble::v1::POSE_ENCODING_QUANTIZED);
  EXPECT_DOUBLE_EQ(reply.position_step(), 1.0 / 1024);
  for (int i = 0; i < 3; ++i) {
    const auto frame = next_frame(client);
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->encoding(), tumble::v1::POSE_ENCODING_QUANTIZED);
    EXPECT_EQ(frame->ids_size(), 0);
    EXPECT_EQ(frame->positions_size(), 0);
    const auto poses = wire::decode_quantized_poses(frame->packed());
    ASSERT_TRUE(poses);
    ASSERT_EQ(poses->bodies.size(), 901u);
    EXPECT_FALSE(poses->velocities);
    const double per_body = wire_bytes(*frame) / 901;
    EXPECT_LE(per_body, 10.0);
    RecordProperty("bytes_per_body", std::to_string(per_body));
    for (std::size_t i_body = 0; i_body < poses->bodies.size(); ++i_body) {
      const auto& body = poses->bodies[i_body];
      EXPECT_EQ(body.id, i_body);  // ids count from 0 in scene order
      const auto x = wire::position_of(body);
      EXPECT_NEAR(x[0], 0.5 * static_cast<double>(i_body % 30), wire::kPositionStep / 2);
      EXPECT_NEAR(x[1], 0.5 * static_cast<double>(i_body / 30), wire::kPositionStep / 2);
      EXPECT_NEAR(x[2], 1.25, wire::kPositionStep / 2);
      EXPECT_NEAR(wire::orientation_of(body)[0], 1, 1e-6);
    }
  }
}

TEST(PoseEncoding, QuantizedFramesMatchFullFramesWithVelocities) {
  TestServer server(grid_scene(true));
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  // Every tick, both encodings: frames of the same tick can be compared.
  const auto full = subscribed(
      client, subscribe_encoded(1, tumble::v1::POSE_ENCODING_FULL, tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY, 10));
  const auto quantized = subscribed(
      client, subscribe_encoded(2, tumble::v1::POSE_ENCODING_QUANTIZED, tumble::v1::POSE_FIELDS_POSE_AND_VELOCITY, 10));
  ASSERT_NE(full.subscription_id(), quantized.subscription_id());
  std::map<std::uint64_t, tumble::v1::PoseFrame> full_frames;
  std::map<std::uint64_t, tumble::v1::PoseFrame> quantized_frames;
  int compared = 0;
  while (compared < 3) {
    const auto frame = next_frame(client);
    ASSERT_TRUE(frame);
    (frame->subscription_id() == full.subscription_id() ? full_frames : quantized_frames)[frame->tick()] = *frame;
    const auto f = full_frames.find(frame->tick());
    const auto q = quantized_frames.find(frame->tick());
    if (f == full_frames.end() || q == quantized_frames.end()) continue;
    const auto poses = wire::decode_quantized_poses(q->second.packed());
    ASSERT_TRUE(poses);
    ASSERT_TRUE(poses->velocities);
    ASSERT_EQ(static_cast<int>(poses->bodies.size()), f->second.ids_size());
    for (int i = 0; i < f->second.ids_size(); ++i) {
      const auto& body = poses->bodies[static_cast<std::size_t>(i)];
      EXPECT_EQ(body.id, f->second.ids(i));
      const auto x = wire::position_of(body);
      const auto v = wire::linear_velocity_of(body);
      for (int a = 0; a < 3; ++a) {
        // The FULL side is float32: allow its rounding on top of the grid's.
        EXPECT_NEAR(x[static_cast<std::size_t>(a)], f->second.positions(3 * i + a), wire::kPositionStep / 2 + 1e-6);
        EXPECT_NEAR(v[static_cast<std::size_t>(a)], f->second.linear_velocities(3 * i + a),
                    wire::kLinearVelocityStep / 2 + 1e-6);
      }
    }
    full_frames.erase(f);
    quantized_frames.erase(q);
    ++compared;
  }
}

TEST(PoseEncoding, DeltaSendsAKeyFrameThenOnlyTheBodiesThatMove) {
  TestServer server(grid_scene(true));
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  const auto reply =
      subscribed(client, subscribe_encoded(1, tumble::v1::POSE_ENCODING_DELTA, tumble::v1::POSE_FIELDS_POSE));
  EXPECT_EQ(reply.encoding(), tumble::v1::POSE_ENCODING_DELTA);
  const auto key = next_frame(client);
  ASSERT_TRUE(key);
  EXPECT_TRUE(key->key_frame());
  EXPECT_EQ(wire::decode_quantized_poses(key->packed())->bodies.size(), 902u);
  for (int i = 0; i < 5; ++i) {
    const auto frame = next_frame(client);
    ASSERT_TRUE(frame);
    EXPECT_FALSE(frame->key_frame());
    const auto poses = wire::decode_quantized_poses(frame->packed());
    ASSERT_TRUE(poses);
    ASSERT_EQ(poses->bodies.size(), 1u);  // the mover alone
    EXPECT_EQ(poses->bodies[0].id, 901u);
    EXPECT_NEAR(wire::position_of(poses->bodies[0])[0], -3 + frame->sim_time(), 0.01);
    EXPECT_EQ(frame->removed_ids_size(), 0);
  }
}

TEST(PoseEncoding, DeltaOfAnIdleWorldSendsNoBodyDataAfterTheKeyFrame) {
  TestServer server(grid_scene(false));
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  const auto reply =
      subscribed(client, subscribe_encoded(1, tumble::v1::POSE_ENCODING_DELTA, tumble::v1::POSE_FIELDS_POSE));
  const auto key = next_frame(client);
  ASSERT_TRUE(key && key->key_frame());
  EXPECT_LE(wire_bytes(*key) / 901, 10.0);
  RecordProperty("key_frame_bytes_per_body", std::to_string(wire_bytes(*key) / 901));
  for (int i = 0; i < 5; ++i) {
    const auto frame = next_frame(client);
    ASSERT_TRUE(frame);
    EXPECT_FALSE(frame->key_frame());
    EXPECT_TRUE(wire::decode_quantized_poses(frame->packed())->bodies.empty());
    EXPECT_EQ(frame->removed_ids_size(), 0);
    EXPECT_LE(wire_bytes(*frame), 32.0);  // tick, time and an empty list
    RecordProperty("idle_frame_bytes", std::to_string(wire_bytes(*frame)));
  }

  // A key frame on request, answered by an Ack; then changes again.
  ClientMessage request;
  request.set_request_id(2);
  request.mutable_key_frame_request()->set_subscription_id(reply.subscription_id());
  ASSERT_TRUE(client.send(request));
  const auto ack = client.read_until([](const ServerMessage& m) { return m.has_ack() || m.has_error(); });
  ASSERT_TRUE(ack && ack->has_ack()) << (ack ? ack->DebugString() : "none");
  const auto again =
      client.read_until([](const ServerMessage& m) { return m.has_pose_frame() && m.pose_frame().key_frame(); });
  ASSERT_TRUE(again);
  EXPECT_EQ(wire::decode_quantized_poses(again->pose_frame().packed())->bodies.size(), 901u);
  const auto after = next_frame(client);
  ASSERT_TRUE(after);
  EXPECT_FALSE(after->key_frame());
}

TEST(PoseEncoding, DeltaReportsRemovedBodiesAndKeyFramesNeedASubscription) {
  TestServer server(grid_scene(false));
  RawClient client(server.port());
  ASSERT_TRUE(client.handshake());
  const auto reply =
      subscribed(client, subscribe_encoded(1, tumble::v1::POSE_ENCODING_DELTA, tumble::v1::POSE_FIELDS_POSE));
  ASSERT_TRUE(next_frame(client));

  ClientMessage remove;
  remove.set_request_id(2);
  remove.mutable_remove_body()->mutable_body()->set_id(7);
  ASSERT_TRUE(client.send(remove));
  const auto removed = client.read_until(
      [](const ServerMessage& m) { return m.has_pose_frame() && m.pose_frame().removed_ids_size() > 0; });
  ASSERT_TRUE(removed);
  ASSERT_EQ(removed->pose_frame().removed_ids_size(), 1);
  EXPECT_EQ(removed->pose_frame().removed_ids(0), 7u);

  ClientMessage request;
  request.set_request_id(3);
  request.mutable_key_frame_request()->set_subscription_id(reply.subscription_id() + 100);
  ASSERT_TRUE(client.send(request));
  const auto error = client.read_until([](const ServerMessage& m) { return m.has_error(); });
  ASSERT_TRUE(error);
  EXPECT_EQ(error->error().code(), tumble::v1::UNKNOWN_SUBSCRIPTION);
  EXPECT_EQ(error->error().request_id(), 3u);
}

}  // namespace
}  // namespace tumble::test
