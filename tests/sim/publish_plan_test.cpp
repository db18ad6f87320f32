// PublishPlan against worked examples: which ticks publish, which bodies a
// snapshot holds, what goes early and when a copy of every body is taken.
#include "sim/publish_plan.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

namespace tumble::sim {
namespace {

using Due = PublishPlan::Due;
using Ids = std::vector<physics::BodyId>;

// A world of 100 bodies, where none of these examples names half of them.
constexpr std::size_t kWorld = 100;

PublishInterest some(std::uint32_t period_ticks, Ids bodies) { return {period_ticks, false, std::move(bodies)}; }
PublishInterest every(std::uint32_t period_ticks) { return {period_ticks, true, {}}; }

TEST(PublishPlan, PublishesOnTheTicksItsPeriodsDivide) {
  PublishPlan plan;
  plan.set_interests({some(2, {1}), some(3, {5})}, 64);
  EXPECT_EQ(plan.plan(0, kWorld, false), Due::wanted_bodies) << "0 is a multiple of every period";
  EXPECT_EQ(plan.plan(1, kWorld, false), Due::nothing);
  EXPECT_EQ(plan.plan(5, kWorld, false), Due::nothing);
  EXPECT_EQ(plan.plan(7, kWorld, false), Due::nothing);

  ASSERT_EQ(plan.plan(2, kWorld, false), Due::wanted_bodies);
  EXPECT_EQ(plan.collect_wanted(), (Ids{1}));
  ASSERT_EQ(plan.plan(9, kWorld, false), Due::wanted_bodies);
  EXPECT_EQ(plan.collect_wanted(), (Ids{5}));
  ASSERT_EQ(plan.plan(12, kWorld, false), Due::wanted_bodies);
  EXPECT_EQ(plan.collect_wanted(), (Ids{1, 5}));
  EXPECT_TRUE(plan.early().empty()) << "only small interests are due: one snapshot holds them all";

  plan.set_interests({}, 64);
  EXPECT_EQ(plan.plan(12, kWorld, false), Due::nothing) << "the new interests replace the old";
}

TEST(PublishPlan, WantsTheSortedUnionOfTheDueInterestsBodies) {
  PublishPlan plan;
  // Both large (more than 2 bodies), overlapping; the third is not due at 6.
  plan.set_interests({some(2, {1, 3, 5, 7}), some(3, {3, 4, 7, 9}), some(4, {0, 2})}, 2);
  ASSERT_EQ(plan.plan(6, kWorld, false), Due::wanted_bodies);
  EXPECT_EQ(plan.collect_wanted(), (Ids{1, 3, 4, 5, 7, 9}));
  // Collected afresh for every tick, not added to the last tick's set.
  ASSERT_EQ(plan.plan(4, kWorld, false), Due::wanted_bodies);
  EXPECT_EQ(plan.collect_wanted(), (Ids{0, 1, 2, 3, 5, 7}));
  ASSERT_EQ(plan.plan(3, kWorld, false), Due::wanted_bodies);
  EXPECT_EQ(plan.collect_wanted(), (Ids{3, 4, 7, 9}));
}

TEST(PublishPlan, SmallInterestsGoEarlyBesideLargeOnes) {
  PublishPlan plan;
  // Drawn at 2 bodies: {8, 9} and {6} are small, {1, 2, 3} is large.
  plan.set_interests({some(1, {8, 9}), some(2, {1, 2, 3}), some(1, {6, 9})}, 2);
  ASSERT_EQ(plan.plan(1, kWorld, false), Due::wanted_bodies);
  EXPECT_TRUE(plan.early().empty()) << "nothing large is due at an odd tick";
  EXPECT_EQ(plan.collect_wanted(), (Ids{6, 8, 9}));

  ASSERT_EQ(plan.plan(2, kWorld, false), Due::wanted_bodies);
  EXPECT_EQ(plan.early(), (Ids{6, 8, 9}));
  EXPECT_EQ(plan.collect_wanted(), (Ids{1, 2, 3, 6, 8, 9})) << "the large snapshot holds the small ones' bodies too";

  // At the line itself an interest is small; one body more and it is large.
  plan.set_interests({some(1, {8, 9}), some(1, {1, 2, 3})}, 3);
  ASSERT_EQ(plan.plan(1, kWorld, false), Due::wanted_bodies);
  EXPECT_TRUE(plan.early().empty()) << "3 bodies with the line at 3: small, like {8, 9}";
  plan.set_interests({some(1, {8, 9}), some(1, {1, 2, 3})}, 1);
  ASSERT_EQ(plan.plan(1, kWorld, false), Due::wanted_bodies);
  EXPECT_TRUE(plan.early().empty()) << "2 bodies with the line at 1: both large";
  EXPECT_EQ(plan.collect_wanted(), (Ids{1, 2, 3, 8, 9}));
}

TEST(PublishPlan, EveryBodyWhenASnapshotIsRequestedOrAnAllBodiesInterestIsDue) {
  PublishPlan plan;
  EXPECT_EQ(plan.plan(1, kWorld, true), Due::every_body) << "requested, without any interest";
  EXPECT_EQ(plan.plan(1, kWorld, false), Due::nothing);

  plan.set_interests({every(3), some(1, {4})}, 64);
  ASSERT_EQ(plan.plan(2, kWorld, false), Due::wanted_bodies);
  EXPECT_EQ(plan.collect_wanted(), (Ids{4}));
  EXPECT_TRUE(plan.early().empty());
  ASSERT_EQ(plan.plan(3, kWorld, false), Due::every_body);
  EXPECT_EQ(plan.early(), (Ids{4})) << "the small interest goes ahead of the copy of every body";
  ASSERT_EQ(plan.plan(4, kWorld, true), Due::every_body);
  EXPECT_EQ(plan.early(), (Ids{4}));

  // An all_bodies interest wants every body, whatever its `bodies` hold, and never goes early.
  plan.set_interests({PublishInterest{1, true, {4}}}, 64);
  ASSERT_EQ(plan.plan(1, kWorld, false), Due::every_body);
  EXPECT_TRUE(plan.early().empty());
}

TEST(PublishPlan, CopiesEveryBodyWhenALargeSetIsMostOfTheWorld) {
  PublishPlan plan;
  plan.set_interests({}, 2);
  EXPECT_TRUE(plan.copies_every_body(3, 6)) << "half of the world";
  EXPECT_FALSE(plan.copies_every_body(3, 7)) << "less than half";
  EXPECT_TRUE(plan.copies_every_body(7, 7));
  EXPECT_FALSE(plan.copies_every_body(2, 2)) << "a set that goes early keeps its filter, even in a tiny world";

  // A large interest of half the world: every body, and the small one still goes first.
  plan.set_interests({some(1, {0}), some(2, {1, 2, 3})}, 2);
  ASSERT_EQ(plan.plan(2, 6, false), Due::every_body);
  EXPECT_EQ(plan.early(), (Ids{0}));
  ASSERT_EQ(plan.plan(2, 7, false), Due::wanted_bodies) << "a world of 7: the three are fewer than half";
  EXPECT_EQ(plan.early(), (Ids{0}));
  EXPECT_EQ(plan.collect_wanted(), (Ids{0, 1, 2, 3}));
}

}  // namespace
}  // namespace tumble::sim
