// Static and kinematic bodies: infinite mass; static ones never move,
// kinematic ones follow their velocity and push dynamic bodies aside.
#include <gtest/gtest.h>

#include "scene_helpers.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::ground_plane;
using testing::kTick;
using testing::sphere_body;

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

// A box rests on a kinematic slab that stands still, with sleeping off,
// until the solver keeps its plan from step to step (the same contact,
// the slab read as fixed). Sent upwards at 1 m/s, the slab lifts the box in
// the very next step: the contact is the same, but the slab now moves and
// the plan must give it a slot of its own.
TEST(MotionTypeTest, AStillKinematicSlabThatStartsMovingLiftsTheBoxOnItAtOnce) {
  World world;
  world.set_settings(testing::settings_without_sleep());
  world.set_gravity(Vec3(0.0, -kGravity, 0.0));
  BodyDesc slab = box_body(Vec3(0.0, -0.5, 0.0));
  slab.shape = box_shape(Vec3(2.0, 0.5, 2.0));
  slab.motion_type = MotionType::kinematic_body;
  const BodyId k = world.add_body(slab);
  const BodyId box = world.add_body(box_body(Vec3(0.0, 0.5, 0.0)));
  int steps = 0;
  while (!world.last_step_stats().plan_kept && steps < 240) {
    world.step(kTick);
    ++steps;
  }
  ASSERT_TRUE(world.last_step_stats().plan_kept) << "a box at rest on a still slab keeps its plan";
  world.set_state(k, world.position(k), world.orientation(k), Vec3(0.0, 1.0, 0.0), Vec3::Zero());
  world.step(kTick);
  EXPECT_FALSE(world.last_step_stats().plan_kept);
  EXPECT_NEAR(world.linear_velocity(box).y(), 1.0, 0.1);
}

// A kinematic sphere spinning in place between two sleeping spheres (their
// pairs are kept but the step boxes stay apart, so the contact pass looks
// at them only when a box changes): the sleepers stay asleep and untouched
// for seconds, and the moment the spinner is sent sideways it meets the
// one in its way.
TEST(MotionTypeTest, SpinningKinematicLeavesSleepersAloneUntilItMoves) {
  World world;
  world.add_body(ground_plane());
  BodyDesc spinner_desc = sphere_body(Vec3(0.0, 0.2, 0.0), 0.2);
  spinner_desc.motion_type = MotionType::kinematic_body;
  spinner_desc.angular_velocity = Vec3(0.0, 1.0, 0.0);
  const BodyId spinner = world.add_body(spinner_desc);
  const BodyId left = world.add_body(sphere_body(Vec3(-0.5, 0.2, 0.0), 0.2));
  const BodyId right = world.add_body(sphere_body(Vec3(0.5, 0.2, 0.0), 0.2));
  for (int i = 0; i < 3 * 240; ++i) world.step(kTick);
  ASSERT_FALSE(world.is_awake(left));
  ASSERT_FALSE(world.is_awake(right));
  const Vec3 right_at_rest = world.position(right);
  for (int i = 0; i < 2 * 240; ++i) world.step(kTick);
  EXPECT_FALSE(world.is_awake(right));
  EXPECT_EQ(world.position(right), right_at_rest);

  // 1 m/s towards the right sphere: the gap of 0.1 m closes in 0.1 s.
  world.set_state(spinner, world.position(spinner), world.orientation(spinner), Vec3(1.0, 0.0, 0.0),
                  Vec3(0.0, 1.0, 0.0));
  for (int i = 0; i < 60; ++i) world.step(kTick);  // 0.25 s
  EXPECT_TRUE(world.is_awake(right));
  EXPECT_GT(world.position(right).x(), right_at_rest.x() + 0.1);
  EXPECT_NEAR(world.position(left).x(), -0.5, 0.01);  // left behind (set_state woke it: it was near)
  EXPECT_GE(world.position(right).x() - world.position(spinner).x(), 0.4 - 0.01);  // not through it
}

// A kinematic box spinning in place: its corners sweep past the sphere
// beside it, so its step box changes every step and the pair is looked at
// every step; the sphere is struck and knocked away.
TEST(MotionTypeTest, SpinningKinematicBoxStrikesANeighbour) {
  World world;
  world.add_body(ground_plane());
  BodyDesc blade = box_body(Vec3(0.0, 0.3, 0.0), 0.3);
  blade.motion_type = MotionType::kinematic_body;
  const BodyId spinner = world.add_body(blade);
  const BodyId ball = world.add_body(sphere_body(Vec3(0.55, 0.2, 0.0), 0.2));
  for (int i = 0; i < 3 * 240; ++i) world.step(kTick);
  ASSERT_FALSE(world.is_awake(ball));
  // Face to face the gap is 0.05 m; a corner reaches 0.42 m from the axis.
  world.set_state(spinner, world.position(spinner), world.orientation(spinner), Vec3::Zero(), Vec3(0.0, 2.0, 0.0));
  for (int i = 0; i < 240; ++i) world.step(kTick);
  EXPECT_GT((world.position(ball) - Vec3(0.55, 0.2, 0.0)).norm(), 0.1);
}

}  // namespace
}  // namespace tumble::physics
