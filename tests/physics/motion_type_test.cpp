// Static and kinematic bodies: infinite mass; static ones never move,
// kinematic ones follow their velocity and push dynamic bodies aside.
#include <gtest/gtest.h>

#include "physics/world.h"
#include "scene_helpers.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::ground_plane;
using testing::kTick;

TEST(MotionTypeTest, StaticBodiesNeverMove) {
  World world;
  world.add_body(ground_plane());
  BodyDesc desc = box_body(Vec3(0.0, 1.0, 0.0));
  desc.motion_type = MotionType::static_body;
  desc.orientation = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY()));
  const BodyId pillar = world.add_body(desc);
  const Vec3 x = world.position(pillar);
  const Quat q = world.orientation(pillar);
  // Rain boxes on it and push it.
  for (int i = 0; i < 5; ++i) world.add_body(box_body(Vec3(0.2 * i - 0.4, 3.0 + 1.1 * i, 0.1 * i)));
  world.apply_impulse(pillar, Vec3(100.0, 0.0, 0.0));
  world.add_force(pillar, Vec3(0.0, 1000.0, 0.0));
  for (int i = 0; i < 3 * 240; ++i) world.step(kTick);
  EXPECT_EQ(world.position(pillar), x);
  EXPECT_EQ(world.orientation(pillar).coeffs(), q.coeffs());
  EXPECT_EQ(world.linear_velocity(pillar), Vec3::Zero());
  EXPECT_EQ(world.mass(pillar), 0.0);
  EXPECT_FALSE(world.is_awake(pillar));
}

TEST(MotionTypeTest, PlanesAreStatic) {
  World world;
  BodyDesc desc = ground_plane();
  desc.motion_type = MotionType::dynamic_body;
  const BodyId plane = world.add_body(desc);
  EXPECT_EQ(world.motion_type(plane), MotionType::static_body);
  world.step(kTick);
  EXPECT_EQ(world.position(plane), Vec3::Zero());
}

TEST(MotionTypeTest, KinematicBodyPushesDynamicBox) {
  World world;
  world.add_body(ground_plane());
  BodyDesc pusher = box_body(Vec3(-3.0, 0.5, 0.0));
  pusher.motion_type = MotionType::kinematic_body;
  pusher.linear_velocity = Vec3(1.0, 0.0, 0.0);
  const BodyId k = world.add_body(pusher);
  const BodyId box = world.add_body(box_body(Vec3(0.0, 0.5, 0.0)));
  EXPECT_TRUE(world.is_awake(k));

  const int steps = 5 * 240;
  for (int i = 0; i < steps; ++i) world.step(kTick);
  // The pusher went exactly where its velocity took it, gravity and the box
  // notwithstanding.
  EXPECT_NEAR(world.position(k).x(), -3.0 + steps * kTick * 1.0, 1e-9);
  EXPECT_NEAR(world.position(k).y(), 0.5, 1e-12);
  EXPECT_EQ(world.linear_velocity(k), Vec3(1.0, 0.0, 0.0));
  // The box was pushed along at the pusher's speed, face to face.
  EXPECT_NEAR(world.linear_velocity(box).x(), 1.0, 0.01);
  EXPECT_NEAR(world.position(box).x() - world.position(k).x(), 1.0, 0.01);
  EXPECT_NEAR(world.position(box).y(), 0.5, 0.01);
}

TEST(MotionTypeTest, KinematicIgnoresForcesAndCanStop) {
  World world;
  BodyDesc desc = box_body(Vec3(0.0, 5.0, 0.0));
  desc.motion_type = MotionType::kinematic_body;
  desc.angular_velocity = Vec3(0.0, 1.0, 0.0);
  const BodyId k = world.add_body(desc);
  world.add_force(k, Vec3(0.0, 100.0, 0.0));
  world.apply_impulse(k, Vec3(10.0, 0.0, 0.0));
  for (int i = 0; i < 240; ++i) world.step(kTick);
  EXPECT_EQ(world.position(k), Vec3(0.0, 5.0, 0.0));  // no gravity, no force
  EXPECT_NEAR(world.angular_velocity(k).y(), 1.0, 1e-15);
  world.set_state(k, world.position(k), world.orientation(k), Vec3::Zero(), Vec3::Zero());
  EXPECT_FALSE(world.is_awake(k));
  EXPECT_EQ(world.mass(k), 0.0);
  EXPECT_EQ(world.kinetic_energy(k), 0.0);
}

}  // namespace
}  // namespace tumble::physics
