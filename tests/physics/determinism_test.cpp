// Same calls, same results: two fresh worlds fed the same sequence give
// bit-identical poses, whatever the number of threads that solve them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "rotation.h"
#include "scene_helpers.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::add_loose_pile;
using testing::box_body;
using testing::disturb_loose_pile;
using testing::ground_plane;
using testing::kLoosePileSteps;
using testing::kTick;
using testing::sphere_body;
using testing::state_hash;

// 100 bodies (boxes, and spheres every seventh) dropped in a loose block
// with varied orientations, then kLoosePileSteps of simulation, with a push
// and a removal on the way, solved on `threads` threads. Returns the hash
// after every second; most_islands is the most islands a step solved.
std::vector<std::uint64_t> run_pile(int threads = 1, std::size_t* most_islands = nullptr) {
  World world;
  world.set_thread_count(threads);
  world.add_body(ground_plane());
  const std::vector<BodyId> ids = add_loose_pile(world);
  std::vector<std::uint64_t> hashes;
  for (int i = 0; i < kLoosePileSteps; ++i) {
    disturb_loose_pile(world, ids, i);
    world.step(kTick);
    if (most_islands != nullptr) *most_islands = std::max(*most_islands, world.last_step_stats().islands);
    if ((i + 1) % 240 == 0) hashes.push_back(state_hash(world));
  }
  return hashes;
}

TEST(DeterminismTest, TwoRunsAreBitIdentical) {
  const std::vector<std::uint64_t> first = run_pile();
  const std::vector<std::uint64_t> second = run_pile();
  ASSERT_EQ(first.size(), static_cast<std::size_t>(kLoosePileSteps / 240));
  EXPECT_EQ(first, second);
  // The pile did move: the hashes change from second to second early on.
  EXPECT_NE(first[0], first[1]);
}

// Islands solved on helper threads give the bits of one thread: each island
// is solved the same way whichever thread takes it.
TEST(DeterminismTest, ThreadCountDoesNotChangeTheResults) {
  std::size_t most_islands = 0;
  const std::vector<std::uint64_t> one = run_pile(1, &most_islands);
  // The pile breaks into islands that the helpers can share.
  ASSERT_GT(most_islands, 4u);
  for (int threads : {2, 3, 8}) {
    EXPECT_EQ(run_pile(threads), one) << threads << " threads";
  }
}

// A ball thrown through a field of sleeping boxes: the narrowphase, run in
// tasks on every thread, finds it touching sleepers (whose islands wake
// during the pass) and boxes knocked off the ground (whose pairs are
// destroyed). Returns the hash every quarter second; woke_in_parallel says
// whether sleepers woke in a step whose pairs filled more than one task.
std::vector<std::uint64_t> run_throw(int threads, bool* woke_in_parallel = nullptr) {
  World world;
  world.set_thread_count(threads);
  world.add_body(ground_plane());
  for (int i = 0; i < 144; ++i) world.add_body(box_body(Vec3(0.6 * (i % 12), 0.25, 0.6 * (i / 12)), 0.25));
  for (int i = 0; i < 3 * 240 && world.sleeping_body_count() < 144; ++i) world.step(kTick);
  EXPECT_EQ(world.sleeping_body_count(), 144u) << "the field did not fall asleep";
  BodyDesc ball = sphere_body(Vec3(-1.0, 0.5, -0.7), 0.4, 40.0);
  ball.linear_velocity = Vec3(8.0, 1.0, 8.0);
  world.add_body(ball);
  std::vector<std::uint64_t> hashes;
  for (int i = 0; i < 3 * 240; ++i) {
    const std::size_t sleeping = world.sleeping_body_count();
    world.step(kTick);
    // 64 pairs a task (world_contacts.cpp).
    if (woke_in_parallel != nullptr && world.sleeping_body_count() < sleeping &&
        world.last_step_stats().narrowphase_pairs > 64) {
      *woke_in_parallel = true;
    }
    if ((i + 1) % 60 == 0) hashes.push_back(state_hash(world));
  }
  return hashes;
}

// Waking islands and destroying pairs wait until every task is done and
// then happen in slot order, so neither depends on which thread found them.
TEST(DeterminismTest, WhatTheNarrowphaseWakesAndDestroysDoesNotDependOnTheThreads) {
  bool woke_in_parallel = false;
  const std::vector<std::uint64_t> one = run_throw(1, &woke_in_parallel);
  ASSERT_TRUE(woke_in_parallel);
  EXPECT_NE(one.front(), one.back());
  for (int threads : {2, 4}) {
    EXPECT_EQ(run_throw(threads), one) << threads << " threads";
  }
}

// Chains of boxes on ball and hinge joints swinging into a floor and each
// other: the joints are solved in their islands' tasks, so the bits do not
// depend on the thread count either. Returns the hash every half second.
std::vector<std::uint64_t> run_chains(int threads, std::size_t* most_islands = nullptr) {
  World world;
  world.set_thread_count(threads);
  world.add_body(ground_plane());
  for (int chain = 0; chain < 8; ++chain) {
    BodyId previous = kWorldBodyId;
    for (int link = 0; link < 10; ++link) {
      const Vec3 center(0.6 * chain, 3.0, 0.3 * link + 0.15);
      BodyDesc desc = box_body(center, 0.1);
      const BodyId body = world.add_body(desc);
      JointDesc joint;
      joint.type = link % 2 == 0 ? JointType::ball : JointType::hinge;
      joint.body_a = previous;
      joint.body_b = body;
      const Vec3 anchor = center - Vec3(0, 0, 0.15);
      world.set_joint_frames(joint, anchor, anchor, Vec3::UnitX());
      world.add_joint(joint);
      previous = body;
    }
  }
  std::vector<std::uint64_t> hashes;
  for (int i = 0; i < 3 * 240; ++i) {
    world.step(kTick);
    if (most_islands != nullptr) *most_islands = std::max(*most_islands, world.last_step_stats().islands);
    if ((i + 1) % 120 == 0) hashes.push_back(state_hash(world));
  }
  return hashes;
}

TEST(DeterminismTest, JointsGiveTheSameBitsOnAnyThreadCount) {
  std::size_t most_islands = 0;
  const std::vector<std::uint64_t> one = run_chains(1, &most_islands);
  ASSERT_GE(most_islands, 8u);  // a chain an island at least
  EXPECT_NE(one.front(), one.back());
  for (int threads : {2, 3}) {
    EXPECT_EQ(run_chains(threads), one) << threads << " threads";
  }
}

// The count may change between steps.
TEST(DeterminismTest, ChangingTheThreadCountMidRunChangesNothing) {
  World reference, changing;
  for (World* world : {&reference, &changing}) {
    world->add_body(ground_plane());
    for (int i = 0; i < 40; ++i)
      world->add_body(box_body(Vec3(1.5 * (i % 8), 0.6 + 0.2 * (i % 3), 1.5 * (i / 8)), 0.5));
  }
  for (int i = 0; i < 480; ++i) {
    if (i % 60 == 0) changing.set_thread_count(1 + (i / 60) % 3);
    reference.step(kTick);
    changing.step(kTick);
  }
  EXPECT_EQ(state_hash(changing), state_hash(reference));
  EXPECT_EQ(changing.thread_count(), 2);
}

}  // namespace
}  // namespace tumble::physics
