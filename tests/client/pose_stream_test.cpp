// PoseStream: QUANTIZED frames decoded alone, DELTA frames completed from
// the key frame and the changes since.
#include <gtest/gtest.h>

#include "tumble_client/pose_stream.h"
#include "wire/quantized_poses.h"

namespace tumble::client {
namespace {

wire::QuantizedBody body_at(std::uint32_t id, double x) {
  const double position[3] = {x, 0, 0};
  const double orientation[4] = {1, 0, 0, 0};
  return wire::quantize_body(id, position, orientation, nullptr, nullptr);
}

tumble::v1::PoseFrame frame_of(tumble::v1::PoseEncoding encoding, std::uint64_t tick,
                               const std::vector<wire::QuantizedBody>& bodies, bool key = false,
                               std::vector<std::uint32_t> removed = {}) {
  tumble::v1::PoseFrame frame;
  frame.set_subscription_id(4);
  frame.set_tick(tick);
  frame.set_encoding(encoding);
  frame.set_packed(wire::encode_quantized_poses(bodies, false));
  frame.set_key_frame(key);
  for (std::uint32_t id : removed) frame.add_removed_ids(id);
  return frame;
}

std::vector<std::pair<std::uint32_t, float>> xs(const PoseSample& sample) {
  std::vector<std::pair<std::uint32_t, float>> out;
  for (const BodyPose& body : sample.bodies) out.emplace_back(body.id, body.position[0]);
  return out;
}

using Xs = std::vector<std::pair<std::uint32_t, float>>;

TEST(PoseStream, QuantizedFramesStandAlone) {
  PoseStream stream;
  const auto sample =
      stream.decode(frame_of(tumble::v1::POSE_ENCODING_QUANTIZED, 8, {body_at(1, 0.5), body_at(2, -1)}));
  ASSERT_TRUE(sample) << sample.failure().message;
  EXPECT_EQ(sample->tick, 8u);
  EXPECT_EQ(sample->subscription_id, 4u);
  EXPECT_FALSE(sample->has_velocities);
  EXPECT_EQ(xs(*sample), (Xs{{1, 0.5f}, {2, -1.0f}}));
  EXPECT_FLOAT_EQ(sample->bodies[0].orientation[0], 1.0f);
}

TEST(PoseStream, DeltaFramesAreCompletedFromTheKeyFrame) {
  PoseStream stream;
  const auto delta = tumble::v1::POSE_ENCODING_DELTA;
  EXPECT_FALSE(stream.decode(frame_of(delta, 1, {body_at(1, 0)})));  // a change before any key frame
  ASSERT_TRUE(stream.decode(frame_of(delta, 2, {body_at(1, 0), body_at(2, 1), body_at(3, 2)}, true)));
  const auto changed = stream.decode(frame_of(delta, 3, {body_at(2, 1.5), body_at(5, 4)}, false, {3}));
  ASSERT_TRUE(changed);
  EXPECT_EQ(xs(*changed), (Xs{{1, 0.0f}, {2, 1.5f}, {5, 4.0f}}));
  const auto idle = stream.decode(frame_of(delta, 4, {}));
  ASSERT_TRUE(idle);
  EXPECT_EQ(idle->tick, 4u);
  EXPECT_EQ(xs(*idle), (Xs{{1, 0.0f}, {2, 1.5f}, {5, 4.0f}}));
  // A key frame replaces everything.
  const auto key = stream.decode(frame_of(delta, 5, {body_at(9, 3)}, true));
  ASSERT_TRUE(key);
  EXPECT_EQ(xs(*key), (Xs{{9, 3.0f}}));
}

TEST(PoseStream, ApplyCountsTheBodiesEachFrameStandsFor) {
  PoseStream stream;
  const auto delta = tumble::v1::POSE_ENCODING_DELTA;
  EXPECT_FALSE(stream.apply(frame_of(delta, 1, {body_at(1, 0)})));  // a change before any key frame
  const auto key = stream.apply(frame_of(delta, 2, {body_at(1, 0), body_at(2, 1), body_at(3, 2)}, true));
  ASSERT_TRUE(key);
  EXPECT_EQ(*key, 3u);
  // Body 2 moved, 5 joined, 3 left: three bodies, and decode agrees on which.
  const auto changed = stream.apply(frame_of(delta, 3, {body_at(2, 1.5), body_at(5, 4)}, false, {3}));
  ASSERT_TRUE(changed);
  EXPECT_EQ(*changed, 3u);
  const auto idle = stream.decode(frame_of(delta, 4, {}));
  ASSERT_TRUE(idle);
  EXPECT_EQ(xs(*idle), (Xs{{1, 0.0f}, {2, 1.5f}, {5, 4.0f}}));

  const auto quantized = stream.apply(frame_of(tumble::v1::POSE_ENCODING_QUANTIZED, 5, {body_at(7, 1), body_at(8, 2)}));
  ASSERT_TRUE(quantized);
  EXPECT_EQ(*quantized, 2u);
  auto broken = frame_of(tumble::v1::POSE_ENCODING_QUANTIZED, 6, {body_at(1, 0)});
  broken.set_packed(broken.packed().substr(0, 5));
  ASSERT_FALSE(stream.apply(broken));
  EXPECT_EQ(stream.apply(broken).failure().kind, FailureKind::protocol);

  tumble::v1::PoseFrame full;
  full.add_ids(4);
  for (int k = 0; k < 3; ++k) full.add_positions(0);
  for (int k = 0; k < 4; ++k) full.add_orientations(k == 0 ? 1 : 0);
  const auto counted = stream.apply(full);
  ASSERT_TRUE(counted);
  EXPECT_EQ(*counted, 1u);
  full.add_positions(0);  // 4 positions for one id
  EXPECT_FALSE(stream.apply(full));
}

TEST(PoseStream, MalformedPackedBytesAreAProtocolFailure) {
  PoseStream stream;
  auto frame = frame_of(tumble::v1::POSE_ENCODING_QUANTIZED, 1, {body_at(1, 0)});
  frame.set_packed(frame.packed().substr(0, 5));
  const auto sample = stream.decode(frame);
  ASSERT_FALSE(sample);
  EXPECT_EQ(sample.failure().kind, FailureKind::protocol);
  EXPECT_FALSE(unpack_pose_frame(frame_of(tumble::v1::POSE_ENCODING_DELTA, 1, {}, true)));
}

}  // namespace
}  // namespace tumble::client
