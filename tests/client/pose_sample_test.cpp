#include "tumble_client/pose_sample.h"

#include <gtest/gtest.h>

namespace tumble::client {
namespace {

// Two bodies: ids 4 and 9, every float distinct.
tumble::v1::PoseFrame two_body_frame() {
  tumble::v1::PoseFrame frame;
  frame.set_subscription_id(3);
  frame.set_tick(1234);
  frame.set_sim_time(5.1416);
  for (std::uint32_t id : {4u, 9u}) frame.add_ids(id);
  for (float v : {1.f, 2.f, 3.f, -1.f, -2.f, -3.f}) frame.add_positions(v);
  for (float v : {0.5f, 0.1f, 0.2f, 0.3f, 1.f, 0.f, 0.f, 0.f}) frame.add_orientations(v);
  for (float v : {0.25f, 0.f, -0.5f, 7.f, 8.f, 9.f}) frame.add_linear_velocities(v);
  for (float v : {0.f, 1.5f, 0.f, -0.125f, 0.f, 0.f}) frame.add_angular_velocities(v);
  return frame;
}

TEST(UnpackPoseFrame, SplitsPackedArraysPerBody) {
  auto sample = unpack_pose_frame(two_body_frame());
  ASSERT_TRUE(sample.ok()) << sample.failure().message;
  EXPECT_EQ(sample->subscription_id, 3u);
  EXPECT_EQ(sample->tick, 1234u);
  EXPECT_EQ(sample->sim_time, 5.1416);
  ASSERT_EQ(sample->bodies.size(), 2u);

  const BodyPose& first = sample->bodies[0];
  EXPECT_EQ(first.id, 4u);
  EXPECT_EQ(first.position, (std::array<float, 3>{1, 2, 3}));
  EXPECT_EQ(first.orientation, (std::array<float, 4>{0.5f, 0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(first.linear_velocity, (std::array<float, 3>{0.25f, 0, -0.5f}));
  EXPECT_EQ(first.angular_velocity, (std::array<float, 3>{0, 1.5f, 0}));

  const BodyPose& second = sample->bodies[1];
  EXPECT_EQ(second.id, 9u);
  EXPECT_EQ(second.position, (std::array<float, 3>{-1, -2, -3}));
  EXPECT_EQ(second.orientation, (std::array<float, 4>{1, 0, 0, 0}));
  EXPECT_EQ(second.linear_velocity, (std::array<float, 3>{7, 8, 9}));
  EXPECT_EQ(second.angular_velocity, (std::array<float, 3>{-0.125f, 0, 0}));
}

TEST(UnpackPoseFrame, EmptyFrameHasNoBodies) {
  tumble::v1::PoseFrame frame;
  frame.set_tick(5);
  auto sample = unpack_pose_frame(frame);
  ASSERT_TRUE(sample.ok());
  EXPECT_TRUE(sample->bodies.empty());
}

TEST(UnpackPoseFrame, RejectsArraysOfTheWrongLength) {
  tumble::v1::PoseFrame frame = two_body_frame();
  frame.mutable_orientations()->RemoveLast();
  auto sample = unpack_pose_frame(frame);
  ASSERT_FALSE(sample.ok());
  EXPECT_EQ(sample.failure().kind, FailureKind::protocol);
  EXPECT_NE(sample.failure().message.find("orientations"), std::string::npos) << sample.failure().message;

  frame = two_body_frame();
  frame.add_angular_velocities(1);
  EXPECT_FALSE(unpack_pose_frame(frame).ok());

  frame = two_body_frame();
  frame.add_ids(11);
  EXPECT_FALSE(unpack_pose_frame(frame).ok());
}

TEST(UnpackPoseFrame, JointsComeWithTheirStatesAndMustMatchTheirIds) {
  tumble::v1::PoseFrame frame = two_body_frame();
  for (std::uint32_t id : {2u, 5u}) {
    frame.add_joint_ids(id);
    frame.add_joint_positions(0.5f * static_cast<float>(id));
    frame.add_joint_speeds(-1.0f);
    frame.add_joint_motor_impulses(0.25f);
  }
  auto sample = unpack_pose_frame(frame);
  ASSERT_TRUE(sample.ok()) << sample.failure().message;
  ASSERT_EQ(sample->joints.size(), 2u);
  EXPECT_EQ(sample->joints[1].id, 5u);
  EXPECT_EQ(sample->joints[1].position, 2.5f);
  EXPECT_EQ(sample->joints[0].speed, -1.0f);
  EXPECT_EQ(sample->joints[0].motor_impulse, 0.25f);
  EXPECT_EQ(sample->bodies.size(), 2u);

  frame.mutable_joint_speeds()->RemoveLast();
  sample = unpack_pose_frame(frame);
  ASSERT_FALSE(sample.ok());
  EXPECT_EQ(sample.failure().kind, FailureKind::protocol);
  EXPECT_NE(sample.failure().message.find("joint"), std::string::npos) << sample.failure().message;
}

TEST(UnpackPoseFrame, APoseOnlyFrameHasNoVelocities) {
  tumble::v1::PoseFrame frame = two_body_frame();
  frame.clear_linear_velocities();
  frame.clear_angular_velocities();
  auto sample = unpack_pose_frame(frame);
  ASSERT_TRUE(sample.ok()) << sample.failure().message;
  EXPECT_FALSE(sample->has_velocities);
  ASSERT_EQ(sample->bodies.size(), 2u);
  EXPECT_EQ(sample->bodies[1].position, (std::array<float, 3>{-1, -2, -3}));
  EXPECT_EQ(sample->bodies[1].linear_velocity, (std::array<float, 3>{0, 0, 0}));
  EXPECT_TRUE(unpack_pose_frame(two_body_frame())->has_velocities);

  frame.add_linear_velocities(1);  // one velocity array present and short: broken
  for (int i = 0; i < 5; ++i) frame.add_linear_velocities(1);
  EXPECT_FALSE(unpack_pose_frame(frame).ok()) << "linear velocities without angular ones";
}

}  // namespace
}  // namespace tumble::client
