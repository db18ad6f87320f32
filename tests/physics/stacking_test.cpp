// Stacks stand: a column of ten boxes for 30 s and a 210-box pyramid for
// 10 s, with sleeping off so the solver holds them every step.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "physics/world.h"
#include "scene_helpers.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::ground_plane;
using testing::kTick;

World awake_world() {
  World world;
  WorldSettings settings;
  settings.sleep_enabled = false;
  world.set_settings(settings);
  world.add_body(ground_plane());
  return world;
}

TEST(StackingTest, TenBoxColumnStandsThirtySeconds) {
  World world = awake_world();
  std::vector<BodyId> boxes;
  for (int k = 0; k < 10; ++k) boxes.push_back(world.add_body(box_body(Vec3(0.0, 0.5 + k, 0.0))));
  const BodyId top = boxes.back();

  for (int i = 0; i < 240; ++i) world.step(kTick);  // settle
  const Vec3 settled = world.position(top);
  EXPECT_NEAR(settled.y(), 9.5, 0.01);
  double drift = 0;
  for (int i = 0; i < 30 * 240; ++i) {
    world.step(kTick);
    drift = std::max(drift, (world.position(top) - settled).norm());
  }
  EXPECT_LT(drift, 0.01);
  for (BodyId box : boxes) EXPECT_LT(std::abs(world.position(box).x()) + std::abs(world.position(box).z()), 0.01);
}

TEST(StackingTest, PyramidOfTwoHundredTenStandsTenSeconds) {
  World world = awake_world();
  // Rows of 20, 19, ..., 1 unit boxes, 5 cm apart, each row centred on the
  // one below.
  constexpr int kBase = 20;
  constexpr double kSpacing = 1.05;
  std::vector<BodyId> boxes;
  std::vector<Vec3> start;
  for (int row = 0; row < kBase; ++row) {
    const int count = kBase - row;
    for (int k = 0; k < count; ++k) {
      const Vec3 position((k - 0.5 * (count - 1)) * kSpacing, 0.5 + row, 0.0);
      boxes.push_back(world.add_body(box_body(position)));
      start.push_back(position);
    }
  }
  ASSERT_EQ(boxes.size(), 210u);
  double worst = 0;
  for (int i = 0; i < 10 * 240; ++i) {
    world.step(kTick);
    for (std::size_t k = 0; k < boxes.size(); ++k) worst = std::max(worst, (world.position(boxes[k]) - start[k]).norm());
  }
  EXPECT_LT(worst, 0.05);
  RecordProperty("max_displacement_m", std::to_string(worst));
}

}  // namespace
}  // namespace tumble::physics
