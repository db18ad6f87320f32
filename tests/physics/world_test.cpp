// Body bookkeeping: ids, dense order, removal, and state accessors.
#include "tumble/physics/world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "rotation.h"
#include "scene_helpers.h"
#include "tumble/physics/mass_properties.h"

namespace tumble::physics {
namespace {

BodyDesc sphere_at(const Vec3& position, const Vec3& velocity) {
  BodyDesc desc;
  desc.shape.type = ShapeType::sphere;
  desc.shape.radius = 0.25;
  desc.mass_properties = sphere_mass_properties(1.5, 0.25);
  desc.position = position;
  desc.linear_velocity = velocity;
  return desc;
}

TEST(WorldTest, EmptyWorldSteps) {
  World world;
  EXPECT_EQ(world.body_count(), 0u);
  world.step(1.0 / 60.0);
  world.step(0.0);
  EXPECT_EQ(world.body_count(), 0u);
  EXPECT_FALSE(world.contains(0));
  EXPECT_FALSE(world.contains(kInvalidBodyId));
  EXPECT_FALSE(world.remove_body(0));
}

TEST(WorldTest, IdsAndDenseOrder) {
  World world;
  std::vector<BodyId> ids;
  for (int i = 0; i < 4; ++i) ids.push_back(world.add_body(sphere_at(Vec3(i, 0, 0), Vec3::Zero())));
  ASSERT_EQ(world.body_count(), 4u);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    EXPECT_TRUE(world.contains(ids[i]));
    EXPECT_EQ(world.body_id_at(i), ids[i]);
    EXPECT_NE(ids[i], kInvalidBodyId);
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(ids[i], ids[j]);
  }
  EXPECT_EQ(world.shape(ids[2]).type, ShapeType::sphere);
  EXPECT_DOUBLE_EQ(world.shape(ids[2]).radius, 0.25);
  EXPECT_DOUBLE_EQ(world.mass(ids[2]), 1.5);
}

TEST(WorldTest, RemoveKeepsOtherBodiesIntact) {
  World world;
  world.set_gravity(Vec3::Zero());
  std::vector<BodyId> ids;
  for (int i = 0; i < 5; ++i) {
    ids.push_back(world.add_body(sphere_at(Vec3(i, 2.0 * i, -i), Vec3(0.5 * i, 1.0, -0.25 * i))));
  }
  world.step(0.1);

  std::vector<Vec3> positions;
  std::vector<Vec3> velocities;
  for (BodyId id : ids) {
    positions.push_back(world.position(id));
    velocities.push_back(world.linear_velocity(id));
  }

  EXPECT_TRUE(world.remove_body(ids[1]));   // from the middle: the last body moves into its slot
  EXPECT_FALSE(world.remove_body(ids[1]));  // already gone
  EXPECT_FALSE(world.contains(ids[1]));
  EXPECT_TRUE(world.remove_body(ids[4]));  // the last one
  ASSERT_EQ(world.body_count(), 3u);

  // Survivors keep their ids and state.
  for (std::size_t k : {0u, 2u, 3u}) {
    EXPECT_TRUE(world.contains(ids[k]));
    EXPECT_EQ(world.position(ids[k]), positions[k]);
    EXPECT_EQ(world.linear_velocity(ids[k]), velocities[k]);
  }
  // Every dense index names a live body, each once.
  std::vector<BodyId> dense;
  for (std::size_t i = 0; i < world.body_count(); ++i) dense.push_back(world.body_id_at(i));
  EXPECT_EQ(dense, (std::vector<BodyId>{ids[0], ids[3], ids[2]}));

  // Ids are not reused. (The new sphere sits clear of the others: bodies
  // collide.)
  const Vec3 fresh_position(0.0, -10.0, 0.0);
  const BodyId fresh = world.add_body(sphere_at(fresh_position, Vec3::Zero()));
  for (BodyId id : ids) EXPECT_NE(fresh, id);
  EXPECT_EQ(world.body_id_at(world.body_count() - 1), fresh);

  // Survivors still move with their own velocity.
  const double dt = 0.5;
  world.step(dt);
  for (std::size_t k : {0u, 2u, 3u}) {
    EXPECT_LT((world.position(ids[k]) - (positions[k] + velocities[k] * dt)).norm(), 1e-14);
  }
  EXPECT_EQ(world.position(fresh), fresh_position);
}

TEST(WorldTest, CopyPosesMatchesTheAccessorsBodyForBody) {
  // Every kind of body: awake tumbling boxes, a sleeping one, a moving and
  // a still kinematic body, a static body and the ground plane.
  World world;
  world.add_body(testing::ground_plane());
  BodyDesc tumbling = testing::box_body(Vec3(0, 3, 0));
  tumbling.orientation = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  tumbling.angular_velocity = Vec3(0.5, -2, 1);
  const BodyId spinner = world.add_body(tumbling);
  world.add_body(testing::box_body(Vec3(5, 0.5, 0)));  // resting on the ground: falls asleep
  BodyDesc kinematic = testing::box_body(Vec3(-5, 2, 0));
  kinematic.motion_type = MotionType::kinematic_body;
  kinematic.linear_velocity = Vec3(0.25, 0, 0);
  kinematic.angular_velocity = Vec3(0, 1, 0);
  world.add_body(kinematic);
  kinematic.position = Vec3(-9, 2, 0);
  kinematic.linear_velocity = Vec3::Zero();
  kinematic.angular_velocity = Vec3::Zero();
  world.add_body(kinematic);
  BodyDesc fixed = testing::box_body(Vec3(9, 1, 0));
  fixed.motion_type = MotionType::static_body;
  world.add_body(fixed);
  for (int i = 0; i < 240; ++i) world.step(1.0 / 240.0);
  world.remove_body(spinner);  // the dense order is no longer that of creation
  for (int i = 0; i < 120; ++i) world.step(1.0 / 240.0);
  world.add_body(tumbling);
  world.step(1.0 / 240.0);

  const std::size_t n = world.body_count();
  ASSERT_EQ(n, 6u);
  EXPECT_EQ(world.sleeping_body_count(), 1u);
  std::vector<BodyId> ids(n);
  std::vector<double> x(3 * n), q(4 * n), v(3 * n), w(3 * n);
  world.copy_poses(ids.data(), x.data(), q.data(), v.data(), w.data());
  for (std::size_t i = 0; i < n; ++i) {
    const BodyId id = ids[i];
    ASSERT_EQ(id, world.body_id_at(i));
    const Quat& orientation = world.orientation(id);
    EXPECT_EQ(q[4 * i], orientation.w()) << "body " << id;
    EXPECT_EQ(q[4 * i + 1], orientation.x()) << "body " << id;
    EXPECT_EQ(q[4 * i + 2], orientation.y()) << "body " << id;
    EXPECT_EQ(q[4 * i + 3], orientation.z()) << "body " << id;
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = 3 * i + static_cast<std::size_t>(k);
      EXPECT_EQ(x[at], world.position(id)[k]) << "body " << id;
      EXPECT_EQ(v[at], world.linear_velocity(id)[k]) << "body " << id;
      EXPECT_EQ(w[at], world.angular_velocity(id)[k]) << "body " << id;
    }
  }
  EXPECT_NE(world.angular_velocity(world.body_id_at(5)), Vec3::Zero()) << "the new box tumbles";
}

TEST(WorldTest, RemoveAllThenAdd) {
  World world;
  const BodyId a = world.add_body(sphere_at(Vec3::Zero(), Vec3::Zero()));
  EXPECT_TRUE(world.remove_body(a));
  EXPECT_EQ(world.body_count(), 0u);
  world.step(0.01);
  const BodyId b = world.add_body(sphere_at(Vec3::Ones(), Vec3::Zero()));
  EXPECT_NE(a, b);
  EXPECT_FALSE(world.contains(a));
  EXPECT_EQ(world.position(b), Vec3::Ones());
}

TEST(WorldTest, StateRoundTripAndKineticEnergy) {
  World world;
  BodyDesc desc;
  desc.shape.type = ShapeType::box;
  desc.shape.half_extents = Vec3(0.1, 0.3, 0.6);
  desc.mass_properties = box_mass_properties(2.0, desc.shape.half_extents);
  desc.orientation = Quat(2.0, 0.0, 0.0, 0.0);  // not unit: normalised on creation
  const BodyId id = world.add_body(desc);
  EXPECT_NEAR(world.orientation(id).norm(), 1.0, 1e-15);

  const Vec3 x(1.0, 2.0, 3.0);
  const Quat q = quat_from_rotation_vector(Vec3(0.4, -0.2, 0.9));
  const Vec3 v(0.5, -1.0, 2.0);
  const Vec3 w(3.0, -1.0, 0.5);
  world.set_state(id, x, q, v, w);
  EXPECT_EQ(world.position(id), x);
  EXPECT_TRUE(world.orientation(id).isApprox(q, 1e-15));
  EXPECT_LT((world.linear_velocity(id) - v).norm(), 1e-14);
  EXPECT_LT((world.angular_velocity(id) - w).norm(), 1e-13);
  EXPECT_LT((world.linear_momentum(id) - 2.0 * v).norm(), 1e-14);

  // I_world = R I_body R^T; L = I_world w.
  const Mat3 r = q.toRotationMatrix();
  const Mat3 i_world = r * desc.mass_properties.inertia * r.transpose();
  EXPECT_TRUE(world.inertia_world(id).isApprox(i_world, 1e-14));
  EXPECT_LT((world.angular_momentum(id) - i_world * w).norm(), 1e-14);
  EXPECT_EQ(world.inertia_body(id), desc.mass_properties.inertia);

  // 1/2 M v.v + 1/2 w^T I w.
  const double expected = 0.5 * 2.0 * v.squaredNorm() + 0.5 * w.dot(i_world * w);
  EXPECT_NEAR(world.kinetic_energy(id), expected, 1e-13 * expected);
}

TEST(WorldTest, ForceAtPointAccumulatesTorque) {
  World world;
  const BodyId id = world.add_body(sphere_at(Vec3(1.0, 0.0, 0.0), Vec3::Zero()));
  world.add_force_at_point(id, Vec3(0.0, 2.0, 0.0), Vec3(1.0, 0.0, 1.0));  // r - x = +z
  world.add_force(id, Vec3(1.0, 0.0, 0.0));
  world.add_torque(id, Vec3(0.0, 0.0, 5.0));
  EXPECT_EQ(world.accumulated_force(id), Vec3(1.0, 2.0, 0.0));
  // z x 2y = -2x.
  EXPECT_EQ(world.accumulated_torque(id), Vec3(-2.0, 0.0, 5.0));
}

// The divergence guard: after a step, a moving body beyond
// max_state_magnitude or not finite is listed; the others never are.
// A pair lives while the bodies' fat boxes (their boxes grown by the
// broadphase margin, 0.1 m) overlap: a box drifting away from a still one
// loses the pair once the gap outgrows both margins, though the still box's
// fat box never moves; a box teleported away loses it at the next step.
TEST(WorldTest, APairLivesWhileTheFatBoxesOverlap) {
  World world;
  world.set_settings(testing::settings_without_sleep());
  world.set_gravity(Vec3::Zero());
  world.add_body(testing::box_body(Vec3(0, 0, 0)));
  BodyDesc drifting = testing::box_body(Vec3(1.05, 0, 0));
  drifting.linear_velocity = Vec3(0.5, 0, 0);
  const BodyId away = world.add_body(drifting);
  const BodyId teleported = world.add_body(testing::box_body(Vec3(-1.05, 0, 0)));
  world.step(testing::kTick);
  EXPECT_EQ(world.last_step_stats().pairs, 2u);
  // 0.5 m/s for 1 s: 0.55 m apart, more than two margins and the lead of
  // the drifting box's fat box (two steps of its motion).
  for (int i = 0; i < static_cast<int>(1.0 / testing::kTick); ++i) world.step(testing::kTick);
  EXPECT_GT(world.position(away).x(), 1.5);
  EXPECT_EQ(world.last_step_stats().pairs, 1u);
  world.set_state(teleported, Vec3(0, 0, 10), Quat::Identity(), Vec3::Zero(), Vec3::Zero());
  world.step(testing::kTick);
  EXPECT_EQ(world.last_step_stats().pairs, 0u);
}

TEST(WorldTest, DivergedBodiesAreListedAfterTheStepThatMadeThem) {
  World world;
  world.set_gravity(Vec3::Zero());
  WorldSettings settings;
  settings.max_state_magnitude = 100;
  world.set_settings(settings);
  const BodyId calm = world.add_body(sphere_at({0, 0, 0}, {1, 0, 0}));
  const BodyId runaway = world.add_body(sphere_at({0, 10, 0}, {0, 0, 0}));
  const BodyId spinner = world.add_body(sphere_at({0, 20, 0}, {0, 0, 0}));
  const BodyId poisoned = world.add_body(sphere_at({0, 30, 0}, {0, 0, 0}));
  const BodyId far = world.add_body(sphere_at({98.5, 40, 0}, {60, 0, 0}));
  world.step(0.01);
  EXPECT_TRUE(world.diverged_bodies().empty());

  // 1.5 kg: 3000 N for 0.1 s make 200 m/s, beyond the bound of 100 m/s.
  world.add_force(runaway, {3000, 0, 0});
  // I = 2/5 m r^2 = 0.0375 kg m^2; L = r x J = (0, -10, 0), so w = 267 rad/s.
  world.apply_impulse_at_point(spinner, {0, 0, 10}, Vec3(1, 20, 0));
  world.add_force(poisoned, {std::nan(""), 0, 0});
  world.step(0.1);  // far: 98.5 + 60 * 0.11 = 105.1 m, beyond 100 m
  const std::vector<BodyId> listed(world.diverged_bodies().begin(), world.diverged_bodies().end());
  EXPECT_EQ(listed, (std::vector<BodyId>{runaway, spinner, poisoned, far})) << "in dense order";
  EXPECT_FALSE(std::isfinite(world.position(poisoned).x()));
  EXPECT_TRUE(std::isfinite(world.position(calm).x()));

  // Removed, they are listed until the next step, which lists only what it made.
  for (const BodyId id : listed) world.remove_body(id);
  world.step(0.01);
  EXPECT_TRUE(world.diverged_bodies().empty());
  EXPECT_EQ(world.body_count(), 1u);
}

TEST(WorldTest, AnInfiniteBoundStillCatchesWhatIsNotFinite) {
  World world;
  WorldSettings settings;
  settings.max_state_magnitude = std::numeric_limits<double>::infinity();
  world.set_settings(settings);
  // Alone: a body that can reach 1e298 m in a step has a contact with everything.
  const BodyId fast = world.add_body(sphere_at({0, 0, 0}, {1e300, 0, 0}));
  world.step(1.0 / 60.0);
  EXPECT_TRUE(world.diverged_bodies().empty());
  world.remove_body(fast);
  const BodyId overflowing = world.add_body(sphere_at({0, 10, 0}, {0, 0, 0}));
  world.add_force(overflowing, {std::numeric_limits<double>::infinity(), 0, 0});
  world.step(1.0 / 60.0);
  ASSERT_EQ(world.diverged_bodies().size(), 1u);
  EXPECT_EQ(world.diverged_bodies()[0], overflowing);
}

}  // namespace
}  // namespace tumble::physics
