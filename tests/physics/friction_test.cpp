// Coulomb friction on a 30 degree slope: static friction holds a box when
// mu > tan(30 deg) = 0.577, and a sliding box accelerates at
// a = g (sin t - mu cos t).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "scene_helpers.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::kGravity;
using testing::kTick;

constexpr double kSlope = std::numbers::pi / 6;

enum class SlopeKind { static_box, rotated_plane };

struct Slope {
  World world;
  BodyId box = kInvalidBodyId;
  Vec3 down_slope;  // unit, along the surface
};

// A slope tilted about z with friction mu on both surfaces (so the
// combined sqrt(mu mu) is mu), and a unit box resting on it at rest.
void build_slope(Slope& s, double mu, SlopeKind kind) {
  const Quat tilt(Eigen::AngleAxisd(kSlope, Vec3::UnitZ()));
  const Vec3 up = tilt * Vec3::UnitY();
  s.down_slope = tilt * Vec3(-1.0, 0.0, 0.0);
  BodyDesc slope;
  slope.orientation = tilt;
  slope.friction = mu;
  if (kind == SlopeKind::rotated_plane) {
    slope.shape = plane_shape(Vec3::UnitY(), 0.0);
  } else {
    slope.shape = box_shape(Vec3(20.0, 1.0, 5.0));
    slope.motion_type = MotionType::static_body;
    slope.position = -1.0 * up;  // top face through the origin
  }
  s.world.add_body(slope);
  BodyDesc desc = box_body(0.5 * up);
  desc.orientation = tilt;
  desc.friction = mu;
  s.box = s.world.add_body(desc);
}

class FrictionTest : public ::testing::TestWithParam<SlopeKind> {};

TEST_P(FrictionTest, StaticFrictionHolds) {
  Slope s;
  build_slope(s, 0.7, GetParam());
  const Vec3 start = s.world.position(s.box);
  for (int i = 0; i < 2 * 240; ++i) s.world.step(kTick);
  EXPECT_LT((s.world.position(s.box) - start).norm(), 0.01);
}

TEST_P(FrictionTest, SlidingAcceleration) {
  Slope s;
  const double mu = 0.3;
  build_slope(s, mu, GetParam());
  // Let it get going, then measure dv/dt along the slope over one second.
  for (int i = 0; i < 60; ++i) s.world.step(kTick);
  const double v0 = s.world.linear_velocity(s.box).dot(s.down_slope);
  for (int i = 0; i < 240; ++i) s.world.step(kTick);
  const double v1 = s.world.linear_velocity(s.box).dot(s.down_slope);
  const double measured = (v1 - v0) / (240 * kTick);
  const double expected = kGravity * (std::sin(kSlope) - mu * std::cos(kSlope));
  EXPECT_NEAR(measured, expected, 0.05 * expected);
  RecordProperty("acceleration_error", std::to_string((measured - expected) / expected));
  // It slides on its face: no tumbling, no lift-off.
  EXPECT_LT(s.world.angular_velocity(s.box).norm(), 0.01);
  EXPECT_LT(std::abs(s.world.linear_velocity(s.box).dot(s.world.orientation(s.box) * Vec3::UnitY())), 0.01);
}

INSTANTIATE_TEST_SUITE_P(Slopes, FrictionTest, ::testing::Values(SlopeKind::static_box, SlopeKind::rotated_plane),
                         [](const ::testing::TestParamInfo<SlopeKind>& param_info) {
                           return param_info.param == SlopeKind::static_box ? "StaticBox" : "RotatedPlane";
                         });

// A box sliding on its face over fixed supports decelerates at mu g and
// stops after v0^2 / (2 mu g). A fixed support adds no terms to the
// contact rows, whichever side of the contact it is: static spheres come
// first in collide order (the box is the contact's second body), a static
// box second (the box is the first), and a kinematic box standing still
// is as fixed as a static one.
enum class Support { static_spheres, static_box, still_kinematic_box };

class SlidingTest : public ::testing::TestWithParam<Support> {};

TEST_P(SlidingTest, BoxOnFixedSupportsDeceleratesAtMuG) {
  const double mu = 0.4;
  const double v0 = 2.0;
  World world;
  world.set_gravity(Vec3(0.0, -kGravity, 0.0));
  double top = 0;  // height of the supports' top
  if (GetParam() == Support::static_spheres) {
    // Four spheres of radius 0.5 whose tops stay under the box all the way,
    // its centre within them.
    for (double x : {-1.0, 1.0}) {
      for (double z : {-0.5, 0.5}) {
        BodyDesc sphere = testing::sphere_body(Vec3(x, 0.0, z));
        sphere.motion_type = MotionType::static_body;
        sphere.friction = mu;
        world.add_body(sphere);
      }
    }
    top = 0.5;
  } else {
    BodyDesc slab = box_body(Vec3(0.0, -0.5, 0.0));
    slab.shape = box_shape(Vec3(5.0, 0.5, 5.0));
    slab.motion_type = GetParam() == Support::static_box ? MotionType::static_body : MotionType::kinematic_body;
    slab.friction = mu;
    world.add_body(slab);
  }
  BodyDesc desc = box_body(Vec3(0.0, top + 0.25, 0.0));
  desc.shape = box_shape(Vec3(2.0, 0.25, 1.0));
  desc.mass_properties = box_mass_properties(1.0, desc.shape.half_extents);
  desc.friction = mu;
  desc.linear_velocity = Vec3(v0, 0.0, 0.0);
  const BodyId box = world.add_body(desc);

  // dv/dt over 0.3 s, after the first contact has settled.
  for (int i = 0; i < 12; ++i) world.step(kTick);
  const double start_v = world.linear_velocity(box).x();
  for (int i = 0; i < 72; ++i) world.step(kTick);
  const double measured = (world.linear_velocity(box).x() - start_v) / (72 * kTick);
  EXPECT_NEAR(measured, -mu * kGravity, 0.05 * mu * kGravity);
  for (int i = 0; i < 240; ++i) world.step(kTick);
  EXPECT_LT(world.linear_velocity(box).norm(), 0.01);
  const double distance = v0 * v0 / (2 * mu * kGravity);
  EXPECT_NEAR(world.position(box).x(), distance, 0.05 * distance);
  EXPECT_NEAR(world.position(box).y(), top + 0.25, 0.005);
  EXPECT_NEAR(world.position(box).z(), 0.0, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Supports, SlidingTest,
                         ::testing::Values(Support::static_spheres, Support::static_box, Support::still_kinematic_box),
                         [](const ::testing::TestParamInfo<Support>& param_info) {
                           switch (param_info.param) {
                             case Support::static_spheres:
                               return "StaticSpheres";
                             case Support::static_box:
                               return "StaticBox";
                             case Support::still_kinematic_box:
                               return "StillKinematicBox";
                           }
                           return "";
                         });

// A box that slides at 4 m/s and falls at 3 m/s starts the step 8 mm
// above the ground: its points are apart (speculative) when the step
// starts, and it lands within the step. The landing's normal impulse,
// about m (3 m/s + g dt), brings friction mu times that: the slide loses
// about mu 3 m/s in that very step, not one step later.
TEST(LandingFriction, ABoxThatLandsWithinTheStepSlowsInThatStep) {
  const double mu = 0.5;
  const double slide = 4.0, fall = 3.0;
  World world;
  world.set_gravity(Vec3(0.0, -kGravity, 0.0));
  BodyDesc ground = testing::ground_plane();
  ground.friction = mu;
  world.add_body(ground);
  BodyDesc desc = box_body(Vec3(0.0, 0.5 + 0.008, 0.0));
  desc.friction = mu;
  desc.linear_velocity = Vec3(slide, -fall, 0.0);
  const BodyId box = world.add_body(desc);

  world.step(kTick);
  EXPECT_GT(world.linear_velocity(box).y(), -0.5) << "it has landed";
  const double lost = slide - world.linear_velocity(box).x();
  const double expected = mu * (fall + kGravity * kTick);
  EXPECT_GT(lost, 0.8 * expected);
  EXPECT_LT(lost, 1.2 * expected);
}

}  // namespace
}  // namespace tumble::physics
