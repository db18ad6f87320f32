// Islands and sleeping: resting islands fall asleep, cost nothing while
// asleep (a 100-box pile included), and wake as a whole when disturbed; a
// box balanced just past its edge topples instead of sleeping there; bodies
// near each other but not touching sleep apart, and one about to strike a
// sleeping body wakes it first; settled bodies sleep beside one still
// settling, which wakes them when it is pushed or struck.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "scene_helpers.h"
#include "tumble/physics/mass_properties.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::ground_plane;
using testing::kTick;
using testing::sphere_body;

std::vector<BodyId> add_column(World& world, double x, int height) {
  std::vector<BodyId> boxes;
  for (int k = 0; k < height; ++k) boxes.push_back(world.add_body(box_body(Vec3(x, 0.5 + k, 0.0))));
  return boxes;
}

bool all_asleep(const World& world, const std::vector<BodyId>& ids) {
  for (BodyId id : ids) {
    if (world.is_awake(id)) return false;
  }
  return true;
}

bool all_awake(const World& world, const std::vector<BodyId>& ids) {
  for (BodyId id : ids) {
    if (!world.is_awake(id)) return false;
  }
  return true;
}

// Stops the body where it is, awake, and makes it as if it had been still
// there for `seconds`: its sleep count set, the window starting here.
void hold_still(World& world, BodyId id, double seconds) {
  const Vec3 position = world.position(id);
  const Quat orientation = world.orientation(id);
  world.restore_state(id, position, orientation, Vec3::Zero(), Vec3::Zero(), true,
                      SleepProgress{seconds, position, orientation});
}

// Steps until every listed body sleeps; returns the time taken (s) or a
// negative value if that takes longer than limit seconds.
double time_to_sleep(World& world, const std::vector<BodyId>& ids, double limit) {
  for (int i = 1; i <= static_cast<int>(limit / kTick); ++i) {
    world.step(kTick);
    if (all_asleep(world, ids)) return i * kTick;
  }
  return -1;
}

// A box of the given half extents (1 kg) turned by `degrees` about z and
// placed with its lowest edge `drop` metres above the ground, stepped for
// 10 s: returns the height of its centre then, and whether it sleeps.
struct Tipped {
  double height;
  bool asleep;
};
Tipped tip(const Vec3& half, double degrees, double drop) {
  World world;
  world.add_body(ground_plane());
  BodyDesc desc;
  desc.shape = box_shape(half);
  desc.mass_properties = box_mass_properties(1.0, half);
  desc.orientation = Quat(Eigen::AngleAxisd(degrees * std::numbers::pi / 180, Vec3::UnitZ()));
  // The lowest of the box's edges along z, below its centre.
  double lowest = 0;
  for (const double sx : {-1.0, 1.0}) {
    for (const double sy : {-1.0, 1.0}) {
      lowest = std::min(lowest, (desc.orientation * Vec3(sx * half.x(), sy * half.y(), 0)).y());
    }
  }
  desc.position = Vec3(0, drop - lowest, 0);
  const BodyId box = world.add_body(desc);
  for (int i = 0; i < static_cast<int>(10.0 / kTick); ++i) world.step(kTick);
  return {world.position(box).y(), !world.is_awake(box)};
}

// A unit box landing on an edge just past balance (at 45.1 degrees its
// centre is 1.2 mm beyond the edge) tips more slowly than the sleep speed
// for most of a second after the landing; it must still end flat.
TEST(SleepingTest, ABoxLandingJustPastItsEdgeTopplesFlat) {
  for (const double degrees : {45.1, 45.5, 46.0}) {
    const Tipped box = tip(Vec3::Constant(0.5), degrees, 0.01);
    EXPECT_NEAR(box.height, 0.5, 0.005) << degrees << " degrees";
    EXPECT_TRUE(box.asleep) << degrees << " degrees";
  }
}

// A tall thin box (0.1 x 1 x 0.1 m) released at rest on one bottom edge,
// 5.8 degrees from upright (the balance is at 5.71: its centre is 0.8 mm
// beyond the edge), topples; at 5.5 degrees it falls back upright.
TEST(SleepingTest, AThinBoxReleasedJustPastBalanceEndsLyingDown) {
  const Vec3 half(0.05, 0.5, 0.05);
  const Tipped toppled = tip(half, 5.8, 0.0);
  EXPECT_NEAR(toppled.height, 0.05, 0.005);
  EXPECT_TRUE(toppled.asleep);
  EXPECT_NEAR(tip(half, 5.5, 0.0).height, 0.5, 0.005);
}

// Two boxes on the ground a centimetre apart, within the contact margin:
// the pair has speculative points but does not touch. One slides past the
// other on frictionless feet at twice the sleep speed; the other, at rest,
// falls asleep on its own instead of waiting for it.
TEST(SleepingTest, ABoxAtRestBesideOneSlidingPastSleepsOnItsOwn) {
  World world;
  world.add_body(ground_plane());
  const BodyId resting = world.add_body(box_body(Vec3(0, 0.5, 0)));
  BodyDesc desc = box_body(Vec3(1.01, 0.5, -0.4));
  desc.friction = 0;  // sqrt(0 * 0.5): no friction with the ground
  desc.linear_velocity = Vec3(0, 0, 0.1);
  const BodyId sliding = world.add_body(desc);
  for (int i = 0; i < static_cast<int>(2.0 / kTick); ++i) world.step(kTick);
  EXPECT_FALSE(world.is_awake(resting));
  EXPECT_TRUE(world.is_awake(sliding));
  EXPECT_NEAR(world.linear_velocity(sliding).z(), 0.1, 1e-6);
  EXPECT_NEAR(world.position(sliding).x(), 1.01, 1e-6);
  // Four points on the ground each, and the pair's own: it is near enough
  // to have points all along.
  EXPECT_GT(world.contact_point_count(), 8u);
}

// A box slides at 3 m/s towards a sleeping one a centimetre away: it can
// close the gap within the step, so the sleeping box wakes before the
// solve and is knocked along, not met as a wall of infinite mass.
TEST(SleepingTest, ASleepingBoxIsKnockedByOneThatReachesItWithinAStep) {
  World world;
  world.add_body(ground_plane());
  const BodyId struck = world.add_body(box_body(Vec3(0, 0.5, 0)));
  ASSERT_GT(time_to_sleep(world, {struck}, 3.0), 0);
  BodyDesc desc = box_body(Vec3(-1.01, 0.5, 0));
  desc.friction = 0;
  desc.linear_velocity = Vec3(3, 0, 0);
  const BodyId striker = world.add_body(desc);
  world.step(kTick);
  EXPECT_TRUE(world.is_awake(struck));
  for (int i = 0; i < static_cast<int>(1.0 / kTick); ++i) world.step(kTick);
  // An inelastic hit of equal masses leaves both at 1.5 m/s; friction then
  // stops the struck box within (1.5 m/s)^2 / (2 * 0.5 g) = 0.23 m while
  // the frictionless striker keeps pushing it.
  EXPECT_GT(world.position(struck).x(), 0.2);
  EXPECT_GT(world.position(striker).x(), -0.81);
}

// A frictionless ball grazes a sleeping box at 4 m/s, 2 mm from its
// side: the touch wakes the box but does not move it. The box keeps its
// progress towards sleep and sleeps again as soon as the ball has gone,
// a quarter of a second later, not time_to_sleep after the touch.
TEST(SleepingTest, ABoxGrazedInItsSleepSleepsAgainOnceLeftAlone) {
  World world;
  world.add_body(ground_plane());
  const BodyId grazed = world.add_body(box_body(Vec3(0, 0.5, 0)));
  ASSERT_GT(time_to_sleep(world, {grazed}, 3.0), 0);
  BodyDesc desc = sphere_body(Vec3(0.602, 0.1, -1.5), 0.1);
  desc.friction = 0;
  desc.linear_velocity = Vec3(0, 0, 4);
  world.add_body(desc);
  int woken = -1, asleep_again = -1;
  for (int i = 0; i < static_cast<int>(2.0 / kTick) && asleep_again < 0; ++i) {
    world.step(kTick);
    if (woken < 0 && world.is_awake(grazed)) woken = i;
    if (woken >= 0 && !world.is_awake(grazed)) asleep_again = i;
  }
  ASSERT_GE(woken, 0);
  ASSERT_GE(asleep_again, 0);
  const double awake_for = (asleep_again - woken) * kTick;
  EXPECT_LT(awake_for, 0.4);
  EXPECT_NEAR(world.position(grazed).x(), 0.0, 1e-3);
}

// A box creeps on frictionless feet at 0.01 m/s, a fifth of the sleep
// speed, beside a long bar sliding at twice the sleep speed that it
// touches: the bar holds their group awake. The box stays ready to sleep
// all along (10 mm in its count's first second, 5 mm in each half second
// after, within the 12.5 mm allowed), however far it creeps in all; once
// the bar stops, the pair sleeps time_to_sleep later.
TEST(SleepingTest, ABodyHeldAwakeByItsGroupStaysReadyWhileItCreeps) {
  World world;
  world.add_body(ground_plane());
  BodyDesc desc = box_body(Vec3(0, 0.5, 0));
  desc.friction = 0;
  desc.linear_velocity = Vec3(0, 0, 0.01);
  const BodyId creeping = world.add_body(desc);
  BodyDesc bar;
  bar.shape = box_shape(Vec3(0.5, 0.5, 20));
  bar.mass_properties = box_mass_properties(1.0, Vec3(0.5, 0.5, 20));
  bar.position = Vec3(1.0, 0.5, 0);
  bar.friction = 0;
  bar.linear_velocity = Vec3(0, 0, 0.1);
  const BodyId sliding = world.add_body(bar);
  const double still_for = WorldSettings{}.time_to_sleep;
  bool ready = false;
  for (int i = 0; i < static_cast<int>(4.0 / kTick); ++i) {
    world.step(kTick);
    ASSERT_TRUE(world.is_awake(creeping));
    const double counted = world.sleep_progress(creeping).time;
    if (ready) {
      ASSERT_GE(counted, still_for) << "at " << i * kTick << " s, " << world.position(creeping).z() << " m";
    }
    ready = ready || counted >= still_for;
  }
  EXPECT_GT(world.position(creeping).z(), 0.035);
  world.set_state(sliding, world.position(sliding), world.orientation(sliding), Vec3::Zero(), Vec3::Zero());
  const double slept_after = time_to_sleep(world, {creeping, sliding}, 2.0);
  EXPECT_GT(slept_after, 0);
  EXPECT_LT(slept_after, still_for + 0.05);
}

// A box dropped 5 cm onto the ground 2 mm from the side of a sleeping one:
// it comes to touch, and wakes it. Once it has landed, it is slow but has
// yet to stay still for time_to_sleep; the box beside it, which the landing
// did not move, sleeps again at once instead of waiting for it.
struct Settling {
  World world;
  BodyId resting = kInvalidBodyId;   // the box that slept first
  BodyId settling = kInvalidBodyId;  // the box dropped beside it, awake
  int resting_slept = -1;            // ticks after the drop
  int settling_slept = -1;
};

// Drops the box and steps until the resting box sleeps again, the dropped
// one still settling.
void drop_beside(Settling& s) {
  s.world.add_body(ground_plane());
  s.resting = s.world.add_body(box_body(Vec3(0, 0.5, 0)));
  ASSERT_GT(time_to_sleep(s.world, {s.resting}, 3.0), 0);
  s.settling = s.world.add_body(box_body(Vec3(1.002, 0.55, 0)));
  bool woken = false;
  for (int i = 1; i <= static_cast<int>(3.0 / kTick) && s.resting_slept < 0; ++i) {
    s.world.step(kTick);
    woken = woken || s.world.is_awake(s.resting);
    if (woken && !s.world.is_awake(s.resting)) s.resting_slept = i;
  }
  ASSERT_GE(s.resting_slept, 0);
  ASSERT_TRUE(s.world.is_awake(s.settling));
}

// After a disturbance of the settling box: steps once, checks that the
// sleeping box woke within that step, and returns where it is half a second
// later.
double resting_x_after_disturbance(Settling& s) {
  s.world.step(kTick);
  EXPECT_TRUE(s.world.is_awake(s.resting));
  for (int i = 0; i < static_cast<int>(0.5 / kTick); ++i) s.world.step(kTick);
  return s.world.position(s.resting).x();
}

TEST(SleepingTest, ABoxSleepsBesideOneStillSettling) {
  Settling s;
  ASSERT_NO_FATAL_FAILURE(drop_beside(s));
  for (int i = s.resting_slept + 1; i <= static_cast<int>(3.0 / kTick) && s.settling_slept < 0; ++i) {
    s.world.step(kTick);
    if (!s.world.is_awake(s.settling)) s.settling_slept = i;
  }
  ASSERT_GE(s.settling_slept, 0);
  EXPECT_FALSE(s.world.is_awake(s.resting));
  // The drop takes 0.1 s; the dropped box then needs time_to_sleep.
  EXPECT_LT(s.resting_slept * kTick, 0.2);
  EXPECT_GT((s.settling_slept - s.resting_slept) * kTick, 0.3);
  EXPECT_NEAR(s.world.position(s.resting).x(), 0.0, 1e-3);
  EXPECT_NEAR(s.world.position(s.settling).y(), 0.5, 2e-3);
}

// A push on the settling box towards the sleeping one wakes that one
// before the step: the push carries both, not the settling box alone into a
// wall of infinite mass.
TEST(SleepingTest, APushOnASettlingBoxMovesTheBoxAsleepAgainstIt) {
  Settling s;
  ASSERT_NO_FATAL_FAILURE(drop_beside(s));
  s.world.apply_impulse(s.settling, Vec3(-4, 0, 0));
  // Equal masses: about 2 m/s each after the push, which friction (0.5 g)
  // stops within 0.4 m.
  EXPECT_LT(resting_x_after_disturbance(s), -0.2);
}

// A frictionless box slides at 2 m/s towards the settling box, which the
// sleeping one leans against, from a centimetre away: it can strike within
// the step. The settling box is slow, yet what it touches stirs, so the
// sleeping box wakes before that step, not after it (a wall of infinite
// mass for one step), and takes its share of the blow.
TEST(SleepingTest, ABlowThroughASettlingBoxWakesTheBoxAsleepBehindIt) {
  Settling s;
  ASSERT_NO_FATAL_FAILURE(drop_beside(s));
  BodyDesc desc = box_body(Vec3(2.012, 0.5, 0));
  desc.friction = 0;
  desc.linear_velocity = Vec3(-2, 0, 0);
  s.world.add_body(desc);
  EXPECT_LT(resting_x_after_disturbance(s), -0.05);
}

// The blow through a settling box again, where the settling box's group
// also holds a ready box that waits for it (a small one on top of it), so that the
// step before the blow the sleep pass judged their group: what it noted
// then must not stand for whether anything stirs now.
TEST(SleepingTest, ABlowThroughASettlingBoxWithABoxOnItWakesTheBoxAsleepBehindIt) {
  World world;
  world.add_body(ground_plane());
  const BodyId settling = world.add_body(box_body(Vec3(1.002, 0.5, 0)));
  const BodyId resting = world.add_body(box_body(Vec3(0, 0.5, 0)));
  const BodyId top = world.add_body(box_body(Vec3(1.2, 1.25, 0), 0.25));
  for (int i = 0; i < static_cast<int>(1.0 / kTick); ++i) world.step(kTick);
  // Still for 0.1 s, for time_to_sleep and more, and for time_to_sleep.
  const double still_for[] = {0.1, 0.6, 0.6};
  const BodyId bodies[] = {settling, resting, top};
  for (int k = 0; k < 3; ++k) hold_still(world, bodies[k], still_for[k]);
  world.step(kTick);
  ASSERT_FALSE(world.is_awake(resting));
  ASSERT_TRUE(world.is_awake(settling));
  ASSERT_TRUE(world.is_awake(top));
  BodyDesc desc = box_body(Vec3(2.014, 0.5, 0));
  desc.friction = 0;
  desc.linear_velocity = Vec3(-2, 0, 0);
  world.add_body(desc);
  world.step(kTick);
  EXPECT_TRUE(world.is_awake(resting));
}

// Two boxes stacked and at rest, both awake: the top one has been still for
// time_to_sleep, the bottom one only for 0.1 s. The top one rests on nothing
// but a body that may yet move, so it waits: the two sleep together once
// the bottom one is ready, 0.4 s later.
TEST(SleepingTest, ABoxOnASettlingBoxWaitsForIt) {
  World world;
  world.add_body(ground_plane());
  const std::vector<BodyId> stack = add_column(world, 0.0, 2);
  for (int i = 0; i < static_cast<int>(1.0 / kTick); ++i) world.step(kTick);
  hold_still(world, stack[0], 0.1);
  hold_still(world, stack[1], 0.6);
  world.step(kTick);
  EXPECT_TRUE(world.is_awake(stack[1]));
  const double slept_after = time_to_sleep(world, stack, 1.0);
  EXPECT_GT(slept_after, 0.35);
  EXPECT_LT(slept_after, 0.45);
}

// Two boxes side by side on the ground, joined by a ball joint at the
// middle of the faces they share: the right one has been still for
// time_to_sleep, the left one only for 0.1 s. A joint holds the two
// together, so the ready box waits, though it rests on the ground.
TEST(SleepingTest, ABoxJointedToASettlingBoxWaitsForIt) {
  World world;
  world.add_body(ground_plane());
  const BodyId left = world.add_body(box_body(Vec3(0, 0.5, 0)));
  const BodyId right = world.add_body(box_body(Vec3(1.0, 0.5, 0)));
  JointDesc joint;
  joint.body_a = left;
  joint.body_b = right;
  joint.local_anchor_a = Vec3(0.5, 0, 0);
  joint.local_anchor_b = Vec3(-0.5, 0, 0);
  world.add_joint(joint);
  for (int i = 0; i < static_cast<int>(1.0 / kTick); ++i) world.step(kTick);
  hold_still(world, left, 0.1);
  hold_still(world, right, 0.6);
  world.step(kTick);
  EXPECT_TRUE(world.is_awake(right));
  const double slept_after = time_to_sleep(world, {left, right}, 1.0);
  EXPECT_GT(slept_after, 0.35);
  EXPECT_LT(slept_after, 0.45);
}

// physics_compare's landing: 30 x 30 cubes of 0.3 m, 0.4 m apart, tilted
// by 0.3 to 1 rad about axes that turn from cube to cube and dropped from
// 0.4, 0.95 or 1.5 m, and a 1 m cube of 10 kg dropped from 2.3 m onto the
// middle, stepped at 60 Hz. They tumble into each other in heaps that come
// to rest a centimetre or so apart; each heap sleeps once it has settled,
// not when the last of its neighbours has, and within a heap the settled
// cubes sleep while the last ones settle. With every contact that has
// points joining a group, 215 cubes sleep by 1.5 s and 408 by 2 s; with
// each group sleeping whole, 360 and 684.
TEST(SleepingTest, TheLandingSleepsHeapByHeap) {
  constexpr double kStep = 1.0 / 60;
  constexpr int kSide = 30;
  World world;
  world.add_body(ground_plane());
  std::vector<BodyId> cubes;
  for (int i = 0; i < kSide * kSide; ++i) {
    const int column = i % kSide, row = i / kSide;
    BodyDesc desc = box_body(Vec3(0.4 * column, 0.4 + 0.55 * ((column + row) % 3), 0.4 * row), 0.15);
    const double angle = 0.3 + 0.7 * ((i * 37) % 100) / 100.0;
    const Vec3 axis(std::cos(i * 2.39996), 0.5, std::sin(i * 2.39996));
    desc.orientation = Quat(Eigen::AngleAxisd(angle, axis.normalized()));
    cubes.push_back(world.add_body(desc));
  }
  const BodyId big = world.add_body(box_body(Vec3(0.2 * (kSide - 1), 2.3, 0.2 * (kSide - 1)), 0.5, 10.0));
  std::size_t asleep_at_1_5 = 0, asleep_at_2 = 0;
  for (int i = 1; i <= static_cast<int>(3.0 / kStep); ++i) {
    world.step(kStep);
    if (i == 90) asleep_at_1_5 = world.sleeping_body_count();
    if (i == 120) asleep_at_2 = world.sleeping_body_count();
  }
  EXPECT_GE(asleep_at_1_5, 600u) << "at 1.5 s";
  EXPECT_GE(asleep_at_2, 800u) << "at 2 s";
  EXPECT_EQ(world.awake_body_count(), 0u) << "at 3 s";
  // At rest on the ground or on each other, none through the ground.
  for (BodyId cube : cubes) EXPECT_GT(world.position(cube).y(), 0.13);
  EXPECT_GT(world.position(big).y(), 0.48);
}

TEST(SleepingTest, SettledStackFallsAsleep) {
  World world;
  world.add_body(ground_plane());
  const std::vector<BodyId> column = add_column(world, 0.0, 5);
  EXPECT_TRUE(all_awake(world, column));
  const double t = time_to_sleep(world, column, 5.0);
  EXPECT_GT(t, 0.4);  // not before time_to_sleep has passed
  EXPECT_LT(t, 3.0);
  EXPECT_EQ(world.sleeping_body_count(), 5u);
  EXPECT_EQ(world.awake_body_count(), 0u);
  // Asleep it stays exactly where it settled.
  const Vec3 top = world.position(column.back());
  for (int i = 0; i < 240; ++i) world.step(kTick);
  EXPECT_EQ(world.position(column.back()), top);
  EXPECT_NEAR(top.y(), 4.5, 0.01);
}

TEST(SleepingTest, SleepingPileCostsNothing) {
  World world;
  world.add_body(ground_plane());
  std::vector<BodyId> all;
  for (int c = 0; c < 4; ++c) {
    for (BodyId id : add_column(world, 3.0 * c, 4)) all.push_back(id);
  }
  world.step(kTick);
  const StepStats awake = world.last_step_stats();
  EXPECT_EQ(awake.integrated_bodies, 16u);
  EXPECT_GT(awake.narrowphase_pairs, 0u);
  EXPECT_GT(awake.solved_contacts, 0u);

  ASSERT_GT(time_to_sleep(world, all, 5.0), 0.0);
  world.step(kTick);
  const StepStats asleep = world.last_step_stats();
  EXPECT_EQ(asleep.integrated_bodies, 0u);
  EXPECT_EQ(asleep.narrowphase_pairs, 0u);
  EXPECT_EQ(asleep.solved_contacts, 0u);
  EXPECT_EQ(asleep.moved_proxies, 0u);
  // The contacts persist, so waking up starts warm.
  EXPECT_GT(world.contact_count(), 0u);
}

TEST(SleepingTest, SleepingHundredBoxPileCostsNothing) {
  // 100 unit boxes: a 5 x 5 block of columns four high, neighbours touching
  // side to side, so the pile is one island.
  World world;
  world.add_body(ground_plane());
  std::vector<BodyId> pile;
  std::vector<Vec3> start;
  for (int i = 0; i < 5; ++i) {
    for (int k = 0; k < 5; ++k) {
      for (int layer = 0; layer < 4; ++layer) {
        start.emplace_back(i, 0.5 + layer, k);
        pile.push_back(world.add_body(box_body(start.back())));
      }
    }
  }
  ASSERT_EQ(pile.size(), 100u);
  world.step(kTick);
  EXPECT_EQ(world.last_step_stats().integrated_bodies, 100u);
  EXPECT_GE(world.last_step_stats().narrowphase_pairs, 100u);

  ASSERT_GT(time_to_sleep(world, pile, 5.0), 0.0);
  EXPECT_EQ(world.sleeping_body_count(), 100u);
  for (int i = 0; i < 10; ++i) {
    world.step(kTick);
    const StepStats& asleep = world.last_step_stats();
    EXPECT_EQ(asleep.integrated_bodies, 0u);
    EXPECT_EQ(asleep.narrowphase_pairs, 0u);
    EXPECT_EQ(asleep.manifolds_computed, 0u);
    EXPECT_EQ(asleep.solved_contacts, 0u);
    EXPECT_EQ(asleep.moved_proxies, 0u);
  }
  // It went to sleep standing: every box within 2 cm of where it started.
  for (std::size_t n = 0; n < pile.size(); ++n) EXPECT_LT((world.position(pile[n]) - start[n]).norm(), 0.02);
}

TEST(SleepingTest, ImpulseWakesTheWholeIslandOnly) {
  World world;
  world.add_body(ground_plane());
  const std::vector<BodyId> left = add_column(world, 0.0, 4);
  const std::vector<BodyId> right = add_column(world, 5.0, 4);
  std::vector<BodyId> both = left;
  both.insert(both.end(), right.begin(), right.end());
  ASSERT_GT(time_to_sleep(world, both, 5.0), 0.0);

  // A push on the top box of the left column wakes that column (one island
  // through its touching contacts) but not the other, which touches the
  // left one only through the static ground.
  world.apply_impulse(left.back(), Vec3(0.01, 0.0, 0.0));
  EXPECT_TRUE(all_awake(world, left));
  EXPECT_TRUE(all_asleep(world, right));
  world.step(kTick);
  EXPECT_GT(world.linear_velocity(left.back()).x(), 0.0);
  EXPECT_TRUE(all_asleep(world, right));

  // And it settles and sleeps again.
  EXPECT_GT(time_to_sleep(world, left, 5.0), 0.0);
}

TEST(SleepingTest, ForcesAndStateChangesWake) {
  World world;
  world.add_body(ground_plane());
  const BodyId box = world.add_body(box_body(Vec3(0.0, 0.5, 0.0)));
  ASSERT_GT(time_to_sleep(world, {box}, 5.0), 0.0);
  world.add_force(box, Vec3(0.0, 1.0, 0.0));
  EXPECT_TRUE(world.is_awake(box));
  ASSERT_GT(time_to_sleep(world, {box}, 5.0), 0.0);
  world.add_torque(box, Vec3(0.0, 0.1, 0.0));
  EXPECT_TRUE(world.is_awake(box));
  ASSERT_GT(time_to_sleep(world, {box}, 5.0), 0.0);
  world.set_state(box, Vec3(0.0, 0.5, 0.0), Quat::Identity(), Vec3::Zero(), Vec3::Zero());
  EXPECT_TRUE(world.is_awake(box));
  ASSERT_GT(time_to_sleep(world, {box}, 5.0), 0.0);
  world.wake(box);
  EXPECT_TRUE(world.is_awake(box));
}

TEST(SleepingTest, FallingBodyWakesSleepingOne) {
  World world;
  world.add_body(ground_plane());
  const BodyId box = world.add_body(box_body(Vec3(0.0, 0.5, 0.0)));
  ASSERT_GT(time_to_sleep(world, {box}, 5.0), 0.0);
  BodyDesc ball = sphere_body(Vec3(0.4, 3.0, 0.0), 0.25, 5.0);  // heavy, off centre
  world.add_body(ball);
  bool woke = false;
  for (int i = 0; i < 240 && !woke; ++i) {
    world.step(kTick);
    woke = world.is_awake(box);
  }
  EXPECT_TRUE(woke);
}

TEST(SleepingTest, FreeBodiesDoNotSleep) {
  World world;
  world.set_gravity(Vec3::Zero());
  BodyDesc drifting = box_body(Vec3::Zero());
  drifting.linear_velocity = Vec3(0.001, 0.0, 0.0);  // slower than the sleep speed
  const BodyId box = world.add_body(drifting);
  for (int i = 0; i < 3 * 240; ++i) world.step(kTick);
  EXPECT_TRUE(world.is_awake(box));
  EXPECT_NEAR(world.position(box).x(), 0.003, 1e-12);
}

// A kinematic body in motion carries the island it touches: a box riding a
// platform that creeps slower than the sleep speed is slow enough to sleep,
// yet stays awake and rides along; once the platform stops, the box sleeps.
TEST(SleepingTest, MovingKinematicBodyKeepsItsIslandAwake) {
  World world;
  BodyDesc platform_desc = box_body(Vec3(0.0, -0.5, 0.0));
  platform_desc.shape = box_shape(Vec3(5.0, 0.5, 5.0));
  platform_desc.motion_type = MotionType::kinematic_body;
  platform_desc.linear_velocity = Vec3(0.02, 0.0, 0.0);  // below the sleep speed
  const BodyId platform = world.add_body(platform_desc);
  const BodyId box = world.add_body(box_body(Vec3(0.0, 0.5, 0.0)));
  ASSERT_LT(0.02, world.settings().sleep_speed * 0.5);
  for (int i = 0; i < 4 * 240; ++i) {
    world.step(kTick);
    ASSERT_TRUE(world.is_awake(box)) << "step " << i;
  }
  // 4 s at the platform's 0.02 m/s: friction holds the box to it.
  EXPECT_NEAR(world.position(box).x(), 0.08, 0.005);

  world.set_state(platform, world.position(platform), world.orientation(platform), Vec3::Zero(), Vec3::Zero());
  for (int i = 0; i < 240 && world.is_awake(box); ++i) world.step(kTick);
  EXPECT_FALSE(world.is_awake(box));
}

// The solver's islands are the same: bodies joined by touching contacts,
// never through a static body. Three columns of three boxes are three
// islands; a dynamic plank across two joins them; a static plank across two
// does not.
TEST(SleepingTest, SolverIslandsJoinThroughDynamicBodiesOnly) {
  World world;
  world.set_settings(testing::settings_without_sleep());
  world.add_body(ground_plane());
  for (double x : {0.0, 3.0, 6.0}) {
    for (int k = 0; k < 3; ++k) world.add_body(box_body(Vec3(x, 0.5 + k, 0.0)));
  }
  for (int i = 0; i < 5; ++i) world.step(kTick);
  EXPECT_EQ(world.last_step_stats().islands, 3u);
  EXPECT_EQ(world.last_step_stats().solved_contacts, 9u);

  // x from 0.1 to 2.9: on the tops of columns 0 and 1.
  BodyDesc plank = box_body(Vec3(1.5, 3.25, 0.0));
  plank.shape = box_shape(Vec3(1.4, 0.25, 0.5));
  plank.mass_properties = box_mass_properties(1.0, plank.shape.half_extents);
  world.add_body(plank);
  // x from 3.1 to 5.9: on the tops of columns 1 and 2.
  BodyDesc bridge = plank;
  bridge.position = Vec3(4.5, 3.25, 0.0);
  bridge.motion_type = MotionType::static_body;
  world.add_body(bridge);
  for (int i = 0; i < 5; ++i) world.step(kTick);
  // The plank rests on columns 0 and 1; the static bridge touches the tops
  // of columns 1 and 2 and joins nothing.
  EXPECT_EQ(world.last_step_stats().islands, 2u);
  EXPECT_EQ(world.last_step_stats().solved_contacts, 13u);
}

}  // namespace
}  // namespace tumble::physics
