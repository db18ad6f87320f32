// Bodies coming to rest on the ground: a box landing on an edge falls flat,
// a sphere dropped from 100 m neither tunnels nor sinks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scene_helpers.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::ground_plane;
using testing::kTick;
using testing::sphere_body;

TEST(RestingContactTest, BoxDroppedOnEdgeRestsFlat) {
  World world;
  world.add_body(ground_plane());
  // On its edge: turned 45 degrees about z, so one edge points down. The
  // balanced edge is an unstable equilibrium; a slow spin about z tips it.
  BodyDesc desc = box_body(Vec3(0.0, 2.0, 0.0));
  desc.orientation = Quat(Eigen::AngleAxisd(std::numbers::pi / 4, Vec3::UnitZ()));
  desc.angular_velocity = Vec3(0.0, 0.0, 0.5);
  const BodyId box = world.add_body(desc);
  for (int i = 0; i < 4 * 240; ++i) world.step(kTick);

  // Flat: the centre at the half extent, one face axis vertical.
  EXPECT_NEAR(world.position(box).y(), 0.5, 0.005);
  const Mat3 r = world.orientation(box).toRotationMatrix();
  const double up_alignment = r.transpose().col(1).cwiseAbs().maxCoeff();  // |cos| of the most vertical axis
  EXPECT_GT(up_alignment, std::cos(0.01));
  EXPECT_LT(world.linear_velocity(box).norm(), 0.01);
}

TEST(RestingContactTest, SphereFromHundredMetresDoesNotTunnel) {
  World world;
  world.add_body(ground_plane());
  const double radius = 0.5;
  const BodyId ball = world.add_body(sphere_body(Vec3(0.0, 100.0, 0.0), radius));
  // It hits at sqrt(2 g h) = 44 m/s, moving 0.18 m per tick: more than a
  // third of its radius, so only contacts ahead of time catch it.
  double lowest = 1e9;
  double fastest = 0;
  for (int i = 0; i < 8 * 240; ++i) {
    world.step(kTick);
    lowest = std::min(lowest, world.position(ball).y());
    fastest = std::max(fastest, -world.linear_velocity(ball).y());
  }
  EXPECT_GT(fastest, 40.0);
  EXPECT_GE(lowest, 0.0);  // the centre never went below the ground
  EXPECT_GE(lowest, radius - 0.005);
  EXPECT_NEAR(world.position(ball).y(), radius, 0.005);
  EXPECT_LT(world.linear_velocity(ball).norm(), 0.01);
}

// The same fall for a unit box onto the top of a fixed ball of radius 2:
// the ball comes first in the contact (a sphere before a box), so the
// solver's rows have their fixed side first, and the box must still be
// stopped in the step it arrives, within a centimetre of the top.
TEST(RestingContactTest, BoxFromHundredMetresOntoAFixedBallDoesNotTunnel) {
  World world;
  BodyDesc ball = sphere_body(Vec3::Zero(), 2.0);
  ball.motion_type = MotionType::static_body;
  world.add_body(ball);
  const BodyId box = world.add_body(box_body(Vec3(0.0, 100.0, 0.0)));
  double lowest = 1e9;
  double fastest = 0;
  for (int i = 0; i < 5 * 240; ++i) {
    world.step(kTick);
    const Vec3 at = world.position(box);
    // Balanced on the top until it slides off; only then may it go lower.
    if (std::hypot(at.x(), at.z()) < 0.05) lowest = std::min(lowest, at.y());
    fastest = std::max(fastest, -world.linear_velocity(box).y());
  }
  EXPECT_GT(fastest, 40.0);
  EXPECT_GE(lowest, 2.5 - 0.01);
}

// A box thrown down and sideways onto a fixed slab, in two worlds that
// differ only in the order the two were added: added after the box, the
// slab is the first body of their contact, added before, the second. The
// solver leaves the fixed side out of the rows either way, and the box
// must move the same in both, landing, sliding and coming to rest. Not to
// the last bit: the friction rows' directions differ (the basis made for
// -n is not the one made for n), and the two paths part by 0.3 mm; a
// moving side's impulse left out of the normal rows parts them by 25 cm.
TEST(RestingContactTest, ABoxMovesTheSameWhicheverSideOfItsContactTheFixedSlabIs) {
  BodyDesc slab = box_body(Vec3(0.0, -0.5, 0.0));
  slab.shape = box_shape(Vec3(5.0, 0.5, 5.0));
  slab.motion_type = MotionType::static_body;
  BodyDesc thrown = box_body(Vec3(0.0, 0.54, 0.0));
  thrown.orientation = Quat(Eigen::AngleAxisd(0.05, Vec3(1.0, 0.0, 1.0).normalized()));
  thrown.linear_velocity = Vec3(1.0, -2.0, 0.5);
  thrown.angular_velocity = Vec3(0.0, 3.0, 0.0);
  World slab_first, slab_last;
  slab_first.add_body(slab);
  const BodyId first = slab_first.add_body(thrown);
  const BodyId last = slab_last.add_body(thrown);
  slab_last.add_body(slab);
  double largest = 0;
  for (int i = 0; i < 2 * 240; ++i) {
    slab_first.step(kTick);
    slab_last.step(kTick);
    largest = std::max(largest, (slab_first.position(first) - slab_last.position(last)).norm());
  }
  EXPECT_LT(largest, 1e-3);
  // It landed and slid: it is off the start, and at rest on the slab.
  EXPECT_GT(slab_first.position(first).x(), 0.05);
  EXPECT_NEAR(slab_first.position(first).y(), 0.5, 0.005);
  EXPECT_LT(slab_first.linear_velocity(first).norm(), 0.01);
}

TEST(RestingContactTest, CapsuleLiesOnItsSide) {
  World world;
  world.add_body(ground_plane());
  BodyDesc desc;
  desc.shape = capsule_shape(0.25, 0.5);
  desc.mass_properties = capsule_mass_properties(1.0, 0.25, 0.5);
  desc.position = Vec3(0.0, 1.0, 0.0);
  // Tilted a little from lying along x, so it lands on one end first.
  desc.orientation = Quat(Eigen::AngleAxisd(std::numbers::pi / 2 - 0.2, Vec3::UnitZ()));
  const BodyId capsule = world.add_body(desc);
  for (int i = 0; i < 4 * 240; ++i) world.step(kTick);
  EXPECT_NEAR(world.position(capsule).y(), 0.25, 0.005);
  // The axis (body y) lies horizontal.
  EXPECT_LT(std::abs((world.orientation(capsule) * Vec3::UnitY()).y()), 0.01);
}

TEST(RestingContactTest, BoxRestsOnStaticBox) {
  World world;
  BodyDesc table = box_body(Vec3(0.0, -1.0, 0.0));
  table.shape = box_shape(Vec3(5.0, 1.0, 5.0));
  table.motion_type = MotionType::static_body;
  world.add_body(table);
  const BodyId box = world.add_body(box_body(Vec3(0.3, 1.0, -0.2)));
  for (int i = 0; i < 3 * 240; ++i) world.step(kTick);
  EXPECT_NEAR(world.position(box).y(), 0.5, 0.005);
  EXPECT_NEAR(world.position(box).x(), 0.3, 1e-3);
  EXPECT_NEAR(world.position(box).z(), -0.2, 1e-3);
}

// A box resting on a box resting on the ground: once still, neither
// manifold is computed again, the one against the plane included; each is
// re-evaluated from its anchors (Contact's cache). A push that moves the
// stack more than the cache's millimetre computes them afresh.
TEST(RestingContactTest, RestingStackReusesItsManifolds) {
  World world;
  world.set_settings(testing::settings_without_sleep());
  world.add_body(ground_plane());
  const BodyId bottom = world.add_body(box_body(Vec3(0.0, 0.5, 0.0)));
  world.add_body(box_body(Vec3(0.0, 1.5, 0.0)));
  for (int i = 0; i < 240; ++i) world.step(kTick);
  for (int i = 0; i < 24; ++i) {
    world.step(kTick);
    EXPECT_EQ(world.last_step_stats().narrowphase_pairs, 2u);
    EXPECT_EQ(world.last_step_stats().manifolds_computed, 0u);
    EXPECT_EQ(world.last_step_stats().solved_points, 8u);
  }
  EXPECT_NEAR(world.position(bottom).y(), 0.5, 0.005);
  world.apply_impulse(bottom, Vec3(3.0, 0.0, 0.0));
  world.step(kTick);
  EXPECT_GE(world.last_step_stats().manifolds_computed, 1u);
}

}  // namespace
}  // namespace tumble::physics
