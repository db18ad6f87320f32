// The solver's colouring and groups (contact_solver.h): a body in more
// contacts than there are colours still has each of them solved, and a
// kinematic body in motion is read by every group whose contacts touch it.
#include <gtest/gtest.h>

#include <vector>

#include "scene_helpers.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::ground_plane;
using testing::kTick;
using testing::state_hash;

// A slab on the ground with a 6 x 6 grid of cubes on it: the slab is in 37
// contacts, more than the solver's 16 colours, so most of its contacts with
// the cubes find no colour free. Each cube stands on the slab alone.
TEST(ContactColouringTest, ABodyInMoreContactsThanColoursHoldsEveryOne) {
  World world;
  world.set_settings(testing::settings_without_sleep());
  world.add_body(ground_plane());
  BodyDesc slab = box_body(Vec3(0.0, 0.25, 0.0));
  slab.shape = box_shape(Vec3(3.0, 0.25, 3.0));
  slab.mass_properties = box_mass_properties(50.0, slab.shape.half_extents);
  world.add_body(slab);
  std::vector<BodyId> cubes;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      cubes.push_back(world.add_body(box_body(Vec3(-2.5 + i, 0.5 + 0.2, -2.5 + j), 0.2)));
    }
  }
  for (int step = 0; step < 3 * 240; ++step) world.step(kTick);
  ASSERT_GT(world.last_step_stats().solved_contacts, 36u);
  for (BodyId cube : cubes) {
    // On the slab's top face (y = 0.5), within the soft contact's overlap.
    EXPECT_NEAR(world.position(cube).y(), 0.7, 0.005) << "cube " << cube;
    EXPECT_LT(world.linear_velocity(cube).norm(), 0.01) << "cube " << cube;
  }
}

// A kinematic platform moving at 0.5 m/s with 20 x 20 loose cubes on it, 400
// islands of one cube, 1600 points: several groups, each reading the
// platform. Friction carries every cube to the platform's speed, and two
// threads give the bits of one.
std::uint64_t carry_cubes(int threads, std::vector<Vec3>* velocities) {
  World world;
  world.set_thread_count(threads);
  BodyDesc platform = box_body(Vec3(0.0, -0.5, 0.0));
  platform.shape = box_shape(Vec3(15.0, 0.5, 15.0));
  platform.motion_type = MotionType::kinematic_body;
  platform.linear_velocity = Vec3(0.5, 0.0, 0.0);
  world.add_body(platform);
  std::vector<BodyId> cubes;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) cubes.push_back(world.add_body(box_body(Vec3(-9.5 + i, 0.25, -9.5 + j), 0.25)));
  }
  for (int step = 0; step < 240; ++step) world.step(kTick);
  EXPECT_GT(world.last_step_stats().solved_points, 1024u);
  velocities->clear();
  for (BodyId cube : cubes) velocities->push_back(world.linear_velocity(cube));
  return state_hash(world);
}

TEST(ContactColouringTest, AMovingKinematicBodyCarriesTheCubesOfEveryGroup) {
  std::vector<Vec3> one_thread, two_threads;
  const std::uint64_t one = carry_cubes(1, &one_thread);
  for (const Vec3& v : one_thread) {
    // At mu g = 4.9 m/s^2 a cube reaches 0.5 m/s in about 0.1 s.
    EXPECT_NEAR(v.x(), 0.5, 0.005);
    EXPECT_NEAR(v.z(), 0.0, 0.005);
  }
  EXPECT_EQ(carry_cubes(2, &two_threads), one);
}

}  // namespace
}  // namespace tumble::physics
