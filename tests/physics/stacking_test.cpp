// Stacks stand: a column of ten boxes for 30 s and a 210-box pyramid for
// 10 s, with sleeping off so the solver holds them every step, at the
// default number of substeps for the server's tick rate; and that default
// follows the step rate as world.h says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "scene_helpers.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::ground_plane;
using testing::kTick;
using testing::state_hash;

World awake_world() {
  World world;
  world.set_settings(testing::settings_without_sleep());
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
    for (std::size_t k = 0; k < boxes.size(); ++k)
      worst = std::max(worst, (world.position(boxes[k]) - start[k]).norm());
  }
  EXPECT_LT(worst, 0.05);
  RecordProperty("max_displacement_m", std::to_string(worst));
}

// A three-box column dropped 5 cm and a tilted box landing beside it, run
// for 1 s at step rate `rate` with `settings`; the hash of the end state.
std::uint64_t drop_scene_hash(double rate, const WorldSettings& settings) {
  World world;
  world.set_settings(settings);
  world.add_body(ground_plane());
  for (int k = 0; k < 3; ++k) world.add_body(box_body(Vec3(0.0, 0.55 + 1.0 * k, 0.0)));
  BodyDesc tilted = box_body(Vec3(2.0, 1.0, 0.0));
  tilted.orientation = Quat(Eigen::AngleAxisd(0.4, Vec3(1.0, 0.0, 1.0).normalized()));
  world.add_body(tilted);
  for (int i = 0; i < static_cast<int>(std::lround(rate)); ++i) world.step(1.0 / rate);
  return state_hash(world);
}

TEST(StackingTest, DefaultSubstepsFollowTheStepRate) {
  // The default (substeps 0, contact_hertz 0) must be exactly n substeps
  // with a push of an eighth of the substep rate: at least 240 substeps a
  // second and at least two a step.
  struct Case {
    double rate;  // steps a second
    int substeps;
  };
  for (const Case& c : {Case{30, 8}, Case{60, 4}, Case{120, 2}, Case{240, 2}, Case{1000, 2}}) {
    SCOPED_TRACE(c.rate);
    WorldSettings explicit_settings;
    explicit_settings.substeps = c.substeps;
    explicit_settings.contact_hertz = 0.125 * c.substeps * c.rate;
    const std::uint64_t by_default = drop_scene_hash(c.rate, WorldSettings{});
    EXPECT_EQ(by_default, drop_scene_hash(c.rate, explicit_settings));
    explicit_settings.substeps = c.substeps + 1;  // the scene tells the counts apart
    explicit_settings.contact_hertz = 0.125 * (c.substeps + 1) * c.rate;
    EXPECT_NE(by_default, drop_scene_hash(c.rate, explicit_settings));
  }
}

}  // namespace
}  // namespace tumble::physics
