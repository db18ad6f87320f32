// Restoring a world body by body (what a saved state file does): ids, the
// next id, momenta and sleep state come back exactly, and a restored pile
// that was asleep stays asleep.
#include <gtest/gtest.h>

#include <vector>

#include "scene_helpers.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::ground_plane;
using testing::kTick;

// Everything a state file keeps of one body.
struct SavedBody {
  BodyId id;
  BodyDesc desc;
  Vec3 linear_momentum;
  Vec3 angular_momentum;
  bool awake;
  SleepProgress sleep;
};

std::vector<SavedBody> save(const World& world, const std::vector<BodyDesc>& descs_by_id) {
  std::vector<SavedBody> saved;
  for (std::size_t i = 0; i < world.body_count(); ++i) {
    const BodyId id = world.body_id_at(i);
    BodyDesc desc = descs_by_id[id];
    desc.position = world.position(id);
    desc.orientation = world.orientation(id);
    saved.push_back({id, desc, world.linear_momentum(id), world.angular_momentum(id), world.is_awake(id),
                     world.sleep_progress(id)});
  }
  return saved;
}

World restore(const std::vector<SavedBody>& saved, BodyId next_id) {
  World world;
  for (const SavedBody& body : saved) {
    EXPECT_EQ(world.add_body_with_id(body.desc, body.id), body.id);
    world.restore_state(body.id, body.desc.position, body.desc.orientation, body.linear_momentum, body.angular_momentum,
                        body.awake, body.sleep);
  }
  world.set_next_body_id(next_id);
  return world;
}

TEST(RestoreTest, IdsMomentaAndSleepComeBackExactly) {
  World world;
  std::vector<BodyDesc> descs;
  descs.push_back(ground_plane());
  world.add_body(descs.back());
  // A resting column of three boxes, and a fourth box thrown sideways.
  for (int k = 0; k < 3; ++k) {
    descs.push_back(box_body(Vec3(0, 0.5 + k, 0)));
    world.add_body(descs.back());
  }
  descs.push_back(box_body(Vec3(5, 30, 0)));
  descs.back().linear_velocity = Vec3(1, 2, 0.5);
  descs.back().angular_velocity = Vec3(0.3, -1, 2);
  const BodyId thrown = world.add_body(descs.back());
  // Gaps in the ids, and a removed last id: both must survive the restore.
  descs.push_back(box_body(Vec3(-5, 0.5, 0)));
  const BodyId removed_middle = world.add_body(descs.back());
  descs.push_back(box_body(Vec3(-8, 0.5, 0)));
  world.add_body(descs.back());
  descs.push_back(box_body(Vec3(-11, 0.5, 0)));
  const BodyId removed_last = world.add_body(descs.back());
  ASSERT_TRUE(world.remove_body(removed_middle));
  ASSERT_TRUE(world.remove_body(removed_last));

  for (int i = 0; i < 2 * 240; ++i) world.step(kTick);
  ASSERT_FALSE(world.is_awake(world.body_id_at(1)));  // the column sleeps
  ASSERT_TRUE(world.is_awake(thrown));                // the thrown box still flies

  const std::vector<SavedBody> saved = save(world, descs);
  World copy = restore(saved, world.next_body_id());
  ASSERT_EQ(copy.body_count(), world.body_count());
  EXPECT_EQ(copy.next_body_id(), removed_last + 1);
  EXPECT_FALSE(copy.contains(removed_middle));
  EXPECT_FALSE(copy.contains(removed_last));
  for (std::size_t i = 0; i < world.body_count(); ++i) {
    const BodyId id = world.body_id_at(i);
    EXPECT_EQ(copy.body_id_at(i), id);
    // Bit-identical: compared with ==, not within a tolerance.
    EXPECT_EQ(copy.position(id), world.position(id)) << id;
    EXPECT_EQ(copy.orientation(id).coeffs(), world.orientation(id).coeffs()) << id;
    EXPECT_EQ(copy.linear_momentum(id), world.linear_momentum(id)) << id;
    EXPECT_EQ(copy.angular_momentum(id), world.angular_momentum(id)) << id;
    EXPECT_EQ(copy.is_awake(id), world.is_awake(id)) << id;
    const SleepProgress a = copy.sleep_progress(id), b = world.sleep_progress(id);
    EXPECT_EQ(a.time, b.time) << id;
    EXPECT_EQ(a.rest_position, b.rest_position) << id;
    EXPECT_EQ(a.rest_orientation.coeffs(), b.rest_orientation.coeffs()) << id;
    EXPECT_EQ(a.last_speed, b.last_speed) << id;
    EXPECT_EQ(a.rise_start_speed, b.rise_start_speed) << id;
    EXPECT_EQ(a.rising_steps, b.rising_steps) << id;
  }
  // New bodies get fresh ids, never a removed one.
  EXPECT_EQ(copy.add_body(box_body(Vec3(20, 0.5, 0))), removed_last + 1);

  // A free body with no contacts moves the same in both worlds.
  for (int i = 0; i < 10; ++i) {
    world.step(kTick);
    copy.step(kTick);
  }
  EXPECT_EQ(copy.position(thrown), world.position(thrown));
  EXPECT_EQ(copy.orientation(thrown).coeffs(), world.orientation(thrown).coeffs());
  // The restored column is still asleep and where it was.
  for (int k = 1; k <= 3; ++k) {
    EXPECT_FALSE(copy.is_awake(static_cast<BodyId>(k)));
    EXPECT_EQ(copy.position(static_cast<BodyId>(k)), world.position(static_cast<BodyId>(k)));
  }
}

TEST(RestoreTest, WakingARestoredSleepingColumnWakesItAll) {
  World world;
  world.add_body(ground_plane());
  for (int k = 0; k < 3; ++k) world.add_body(box_body(Vec3(0, 0.5 + k, 0)));
  for (int i = 0; i < 2 * 240; ++i) world.step(kTick);
  ASSERT_EQ(world.sleeping_body_count(), 3u);

  World copy;
  copy.add_body(ground_plane());
  for (BodyId id = 1; id <= 3; ++id) {
    BodyDesc desc = box_body(world.position(id));
    desc.orientation = world.orientation(id);
    copy.add_body_with_id(desc, id);
    copy.restore_state(id, world.position(id), world.orientation(id), world.linear_momentum(id),
                       world.angular_momentum(id), false, SleepProgress{});
  }
  EXPECT_EQ(copy.sleeping_body_count(), 3u);
  // Knock the bottom box out sideways: the boxes above it must fall.
  copy.apply_impulse(1, Vec3(20, 0, 0));
  for (int i = 0; i < 240; ++i) copy.step(kTick);
  EXPECT_LT(copy.position(3).y(), 2.4);
}

}  // namespace
}  // namespace tumble::physics
