// Restitution: a ball dropped from h bounces to e^2 h, and two equal
// spheres colliding head-on elastically exchange velocities.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "scene_helpers.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::ground_plane;
using testing::kTick;
using testing::sphere_body;

// Height of the bottom of the ball at the top of its first bounce.
double first_bounce_height(double restitution, double drop_height) {
  World world;
  world.add_body(ground_plane());
  const double radius = 0.5;
  BodyDesc desc = sphere_body(Vec3(0.0, drop_height + radius, 0.0), radius);
  desc.restitution = restitution;
  const BodyId ball = world.add_body(desc);
  bool rising = false;
  double apex = 0;
  for (int i = 0; i < 5 * 240; ++i) {
    world.step(kTick);
    const double vy = world.linear_velocity(ball).y();
    if (vy > 0) rising = true;
    if (rising) apex = std::max(apex, world.position(ball).y() - radius);
    if (rising && vy < 0) break;
  }
  return apex;
}

class BounceTest : public ::testing::TestWithParam<double> {};

TEST_P(BounceTest, BouncesToRestitutionSquaredTimesHeight) {
  const double e = GetParam();
  const double h = 2.0;
  const double apex = first_bounce_height(e, h);
  EXPECT_NEAR(apex, e * e * h, 0.05 * e * e * h);
  RecordProperty("bounce_ratio", std::to_string(apex / (e * e * h)));
}

INSTANTIATE_TEST_SUITE_P(Restitution, BounceTest, ::testing::Values(0.8, 0.5));

TEST(RestitutionTest, NoRestitutionNoBounce) { EXPECT_LT(first_bounce_height(0.0, 2.0), 0.005); }

TEST(RestitutionTest, HeadOnElasticSpheresExchangeVelocities) {
  World world;
  world.set_gravity(Vec3::Zero());
  BodyDesc left = sphere_body(Vec3(-2.0, 0.0, 0.0));
  left.linear_velocity = Vec3(3.0, 0.0, 0.0);
  left.restitution = 1.0;
  BodyDesc right = sphere_body(Vec3(2.0, 0.0, 0.0));
  right.linear_velocity = Vec3(-1.0, 0.0, 0.0);
  right.restitution = 1.0;
  const BodyId a = world.add_body(left);
  const BodyId b = world.add_body(right);
  const Vec3 momentum = world.linear_momentum(a) + world.linear_momentum(b);

  for (int i = 0; i < 2 * 240; ++i) {
    world.step(kTick);
    const Vec3 now = world.linear_momentum(a) + world.linear_momentum(b);
    ASSERT_LE((now - momentum).norm(), 1e-6 * momentum.norm()) << "step " << i;
  }
  // Equal masses, e = 1: the velocities swap.
  EXPECT_NEAR(world.linear_velocity(a).x(), -1.0, 1e-3);
  EXPECT_NEAR(world.linear_velocity(b).x(), 3.0, 1e-3);
  EXPECT_LT(world.linear_velocity(a).tail<2>().norm() + world.linear_velocity(b).tail<2>().norm(), 1e-9);
  EXPECT_LT(world.angular_velocity(a).norm() + world.angular_velocity(b).norm(), 1e-9);
}

}  // namespace
}  // namespace tumble::physics
