#include "requests.h"

#include <gtest/gtest.h>

namespace tumble::cli {
namespace {

tumble::v1::BodyRef named(const char* name) {
  tumble::v1::BodyRef ref;
  ref.set_name(name);
  return ref;
}

TEST(MakeApplyForce, PointInBodyFrameWithTicks) {
  ForceCommand command;
  command.body = named("crate");
  command.force = {1, -2, 3.5};
  command.at = Vector3{0, 0.5, 0};
  command.local = true;
  command.duration.ticks = 12;
  const tumble::v1::ApplyForce request = make_apply_force(command);
  EXPECT_EQ(request.body().name(), "crate");
  EXPECT_EQ(request.force().x(), 1);
  EXPECT_EQ(request.force().y(), -2);
  EXPECT_EQ(request.force().z(), 3.5);
  ASSERT_TRUE(request.has_point());
  EXPECT_EQ(request.point().y(), 0.5);
  EXPECT_EQ(request.point_frame(), tumble::v1::FRAME_BODY);
  EXPECT_EQ(request.duration_case(), tumble::v1::ApplyForce::kTicks);
  EXPECT_EQ(request.ticks(), 12u);
}

TEST(MakeApplyForce, WorldPointAndSeconds) {
  ForceCommand command;
  command.body = named("crate");
  command.at = Vector3{1, 2, 3};
  command.duration.seconds = 0.25;
  const tumble::v1::ApplyForce request = make_apply_force(command);
  EXPECT_EQ(request.point_frame(), tumble::v1::FRAME_WORLD);
  EXPECT_EQ(request.point().z(), 3);
  EXPECT_EQ(request.duration_case(), tumble::v1::ApplyForce::kSeconds);
  EXPECT_EQ(request.seconds(), 0.25);
}

TEST(MakeApplyForce, NoPointNoDuration) {
  ForceCommand command;
  command.body = named("crate");
  const tumble::v1::ApplyForce request = make_apply_force(command);
  EXPECT_TRUE(request.has_force());  // the server requires the field, zero or not
  EXPECT_FALSE(request.has_point());
  EXPECT_EQ(request.duration_case(), tumble::v1::ApplyForce::DURATION_NOT_SET);
}

TEST(MakeApplyTorque, CarriesTorqueAndDuration) {
  TorqueCommand command;
  command.body.set_id(4);
  command.torque = {0, 0, 2};
  command.duration.seconds = 1.5;
  const tumble::v1::ApplyTorque request = make_apply_torque(command);
  EXPECT_EQ(request.body().id(), 4u);
  EXPECT_EQ(request.torque().z(), 2);
  EXPECT_EQ(request.seconds(), 1.5);
}

TEST(MakeApplyImpulse, PointFrameFollowsLocal) {
  ImpulseCommand command;
  command.body = named("ball");
  command.impulse = {0, 5, 0};
  command.at = Vector3{0.1, 0, 0};
  command.local = true;
  tumble::v1::ApplyImpulse request = make_apply_impulse(command);
  EXPECT_EQ(request.impulse().y(), 5);
  EXPECT_EQ(request.point_frame(), tumble::v1::FRAME_BODY);
  EXPECT_EQ(request.point().x(), 0.1);

  command.at.reset();
  command.local = false;
  request = make_apply_impulse(command);
  EXPECT_FALSE(request.has_point());
}

TEST(MakeSubscribe, BodiesAndRate) {
  SubscribeCommand command;
  command.bodies.push_back(named("crate"));
  command.bodies.emplace_back().set_id(9);
  command.rate_hz = 60;
  const tumble::v1::Subscribe request = make_subscribe(command);
  ASSERT_EQ(request.bodies_size(), 2);
  EXPECT_EQ(request.bodies(0).name(), "crate");
  EXPECT_EQ(request.bodies(1).id(), 9u);
  EXPECT_EQ(request.rate_hz(), 60);
}

}  // namespace
}  // namespace tumble::cli
