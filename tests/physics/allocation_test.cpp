// World::step does not allocate once warmed up (world.h: "step() does not
// allocate once the arrays have grown to the scene"). This binary replaces
// the global operator new and delete to count allocations
// (counting_allocator.h), which is why it is an executable of its own. A pile of boxes, spheres, capsules and a hull
// on a plane and a static box falls, settles and sleeps; a kick and a ball
// dropped on it wake it again. After two such cycles of warm-up, a third
// one of 600 steps (sleeping, waking, settling, sleeping again) must not
// allocate at all.
#include <gtest/gtest.h>

#include <cstddef>
#include <new>
#include <vector>

#include "counting_allocator.h"
#include "scene_helpers.h"
#include "tumble/physics/convex_hull.h"
#include "tumble/physics/mass_properties.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::AllocationCounter;
using testing::box_body;
using testing::ground_plane;
using testing::kTick;
using testing::sphere_body;

TEST(AllocationTest, CounterSeesAllocations) {
  // The replacement is in effect: a vector's buffer and a direct call of
  // the aligned operator new are counted. (The vector is static, so its
  // buffer escapes and the allocation cannot be elided.)
  static std::vector<int> numbers;
  std::size_t seen = 0;
  {
    AllocationCounter counter;
    numbers.resize(100);
    void* raw = ::operator new (256, std::align_val_t{64});
    ::operator delete (raw, std::align_val_t{64});
    seen = counter.count();
  }
  numbers = std::vector<int>();
  EXPECT_EQ(seen, 2u);
}

// The pile: 3 x 3 x 2 unit boxes, a row of spheres and of capsules beside
// it, an octahedron hull on top, a static box to one side, on the plane
// y = 0, and a chain of four boxes on ball joints hanging from the world.
struct PileScene {
  World world;
  BodyId kicked = kInvalidBodyId;  // a box of the pile
  BodyId ball = kInvalidBodyId;    // dropped on the pile to wake it

  PileScene() {
    world.add_body(ground_plane());
    for (int layer = 0; layer < 2; ++layer) {
      for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
          const BodyId id = world.add_body(box_body(Vec3(1.05 * i, 0.5 + layer, 1.05 * k)));
          if (layer == 1 && i == 1 && k == 1) kicked = id;
        }
      }
    }
    for (int i = 0; i < 3; ++i) world.add_body(sphere_body(Vec3(-1.5, 0.3 + 0.7 * i, 1.05 * i), 0.3));
    for (int i = 0; i < 3; ++i) {
      BodyDesc capsule;
      capsule.shape = capsule_shape(0.2, 0.4);
      capsule.mass_properties = capsule_mass_properties(1.0, 0.2, 0.4);
      capsule.position = Vec3(1.05 * i, 0.2, -1.2);
      capsule.orientation = Quat(Eigen::AngleAxisd(1.5707963267948966, Vec3::UnitZ()));  // lying along x
      world.add_body(capsule);
    }
    const std::vector<Vec3> octahedron = {Vec3(0.4, 0, 0),  Vec3(-0.4, 0, 0), Vec3(0, 0.4, 0),
                                          Vec3(0, -0.4, 0), Vec3(0, 0, 0.4),  Vec3(0, 0, -0.4)};
    BodyDesc hull;
    hull.shape = convex_hull_shape(build_convex_hull(octahedron));
    hull.mass_properties = convex_hull_mass_properties(*hull.shape.hull, 1.0);
    hull.position = Vec3(1.05, 2.5, 1.05);
    world.add_body(hull);
    BodyDesc wall = box_body(Vec3(4.0, 1.0, 1.0));
    wall.shape = box_shape(Vec3(0.5, 1.0, 2.0));
    wall.motion_type = MotionType::static_body;
    world.add_body(wall);
    ball = world.add_body(sphere_body(Vec3(-4.0, 0.25, -3.0), 0.25, 2.0));
    // A short chain hanging from the world beside the pile, its end on the
    // ground, and the kicked box hinged to its neighbour.
    BodyId previous = kWorldBodyId;
    for (int i = 0; i < 4; ++i) {
      const BodyId link = world.add_body(box_body(Vec3(-3.0, 1.75 - 0.5 * i, 0.0), 0.2));
      JointDesc joint;
      joint.type = JointType::ball;
      joint.body_a = previous;
      joint.body_b = link;
      const Vec3 anchor(-3.0, 2.0 - 0.5 * i, 0.0);
      world.set_joint_frames(joint, anchor, anchor, Vec3::UnitX());
      world.add_joint(joint);
      previous = link;
    }
  }

  // One cycle: a kick on the middle top box, and the ball lifted to fall on
  // the pile's corner; then 600 steps. Counts how often the pile was
  // seen fully asleep and how often woken.
  void cycle(int* sleeping_steps, int* awake_steps) {
    world.apply_impulse(kicked, Vec3(0.4, 0.0, 0.3));
    world.set_state(ball, Vec3(2.1, 3.5, 2.1), Quat::Identity(), Vec3::Zero(), Vec3::Zero());
    for (int i = 0; i < 600; ++i) {
      world.step(kTick);
      if (world.is_awake(kicked)) {
        ++*awake_steps;
      } else {
        ++*sleeping_steps;
      }
    }
  }
};

// Warms the pile up on `threads` threads (the drop, and one wake cycle),
// then counts the allocations of one more cycle.
void expect_a_warm_cycle_allocates_nothing(int threads) {
  PileScene scene;
  scene.world.set_thread_count(threads);
  int sleeping = 0, awake = 0;
  for (int i = 0; i < 600; ++i) scene.world.step(kTick);
  scene.cycle(&sleeping, &awake);
  ASSERT_GT(sleeping, 0) << "the pile never fell asleep in the warm-up";

  sleeping = awake = 0;
  std::size_t allocations = 0;
  {
    AllocationCounter counter;
    scene.cycle(&sleeping, &awake);
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0u);
  // The measured steps did go through waking and sleeping.
  EXPECT_GT(awake, 0);
  EXPECT_GT(sleeping, 0);
  EXPECT_FALSE(scene.world.is_awake(scene.kicked));
  EXPECT_GT(scene.world.sleeping_body_count(), 20u);
}

TEST(AllocationTest, SteppingAWarmPileAllocatesNothing) { expect_a_warm_cycle_allocates_nothing(1); }

// The helpers take islands of the pile and of the ball without allocating
// either.
TEST(AllocationTest, SteppingAWarmPileOnThreeThreadsAllocatesNothing) { expect_a_warm_cycle_allocates_nothing(3); }

}  // namespace
}  // namespace tumble::physics
