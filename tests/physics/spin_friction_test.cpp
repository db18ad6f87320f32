// Torsional friction (WorldSettings::spin_friction): a ball spinning in
// place about the normal of its one contact point slows at the rate its
// torque limit gives, friction * spin_friction * m g over I = 2/5 m r^2,
// and stops; without it the ball spins on. A box flat on the ground, whose
// contact has four points, is untouched by the setting.
#include <gtest/gtest.h>

#include "scene_helpers.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::kGravity;
using testing::kTick;

constexpr double kBallRadius = 0.1;  // m
constexpr double kBallMass = 1.0;    // kg
constexpr double kBallSpin = 10.0;   // rad/s about +y

// A ball of kBallRadius resting on the ground plane, spinning about y; friction
// 0.5 on both (the mixed coefficient is 0.5).
struct SpinningBall {
  World world;
  BodyId ball = kInvalidBodyId;

  explicit SpinningBall(double spin_friction) {
    WorldSettings settings = testing::settings_without_sleep();
    settings.spin_friction = spin_friction;
    world.set_settings(settings);
    world.add_body(testing::ground_plane());
    BodyDesc desc = testing::sphere_body(Vec3(0, kBallRadius, 0), kBallRadius, kBallMass);
    desc.angular_velocity = Vec3(0, kBallSpin, 0);
    ball = world.add_body(desc);
  }

  void run(double seconds) {
    for (int i = 0; i < static_cast<int>(std::lround(seconds / kTick)); ++i) world.step(kTick);
  }
};

TEST(SpinFrictionTest, ABallSpinningInPlaceSlowsAtTheTorsionalRateAndStops) {
  const double spin_friction = 0.005;
  SpinningBall b(spin_friction);
  const double inertia = 0.4 * kBallMass * kBallRadius * kBallRadius;
  const double deceleration = 0.5 * spin_friction * kBallMass * kGravity / inertia;  // rad/s^2, about 6.1
  b.run(0.5);
  EXPECT_NEAR(b.world.angular_velocity(b.ball).y(), kBallSpin - 0.5 * deceleration, 0.02 * kBallSpin);
  // It stops at kBallSpin / deceleration, about 1.6 s, and stays stopped where it was.
  b.run(1.5);
  EXPECT_NEAR(b.world.angular_velocity(b.ball).norm(), 0.0, 1e-3);
  EXPECT_NEAR(b.world.position(b.ball).x(), 0.0, 1e-4);
  EXPECT_NEAR(b.world.position(b.ball).z(), 0.0, 1e-4);
}

TEST(SpinFrictionTest, WithoutItABallSpinsOn) {
  SpinningBall b(0.0);
  b.run(2.0);
  EXPECT_NEAR(b.world.angular_velocity(b.ball).y(), kBallSpin, 1e-3 * kBallSpin);
}

TEST(SpinFrictionTest, AContactOfFourPointsIsUntouchedBySpinFriction) {
  auto spun_box = [](double spin_friction) {
    World world;
    WorldSettings settings = testing::settings_without_sleep();
    settings.spin_friction = spin_friction;
    world.set_settings(settings);
    world.add_body(testing::ground_plane());
    BodyDesc desc = testing::box_body(Vec3(0, 0.5, 0));
    desc.angular_velocity = Vec3(0, 10, 0);  // its corners stop it in about 0.5 s
    const BodyId box = world.add_body(desc);
    for (int i = 0; i < 60; ++i) world.step(kTick);
    return world.angular_velocity(box);
  };
  const Vec3 with = spun_box(0.005), without = spun_box(0.0);
  EXPECT_GT(with.y(), 0.1) << "still turning: its points' friction has not stopped it yet";
  EXPECT_EQ(with, without);
}

}  // namespace
}  // namespace tumble::physics
