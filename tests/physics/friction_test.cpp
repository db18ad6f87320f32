// Coulomb friction on a 30 degree slope: static friction holds a box when
// mu > tan(30 deg) = 0.577, and a sliding box accelerates at
// a = g (sin t - mu cos t).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "physics/world.h"
#include "scene_helpers.h"

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

}  // namespace
}  // namespace tumble::physics
