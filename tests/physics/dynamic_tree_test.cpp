// Broadphase tree (dynamic_tree.h): a query returns exactly the leaves whose
// boxes overlap the query box, compared with a brute-force scan over 500
// random boxes through rounds of inserts, moves and removes; and the tree
// stays as shallow as an AVL tree, also when boxes arrive in sorted order.
#include "dynamic_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

namespace tumble::physics {
namespace {

// The greatest height of a binary tree with `leaves` leaves in which the
// children of every node differ in height by at most one (AVL balance): the
// fewest leaves for height h is the Fibonacci number F(h + 2) (F(1) = F(2) =
// 1), so the height is the largest h with F(h + 2) <= leaves.
int avl_height_bound(std::size_t leaves) {
  std::size_t f1 = 1, f2 = 2;  // F(2), F(3): the fewest leaves for heights 0 and 1
  int h = 0;
  while (f2 <= leaves) {
    const std::size_t next = f1 + f2;
    f1 = f2;
    f2 = next;
    ++h;
  }
  return h;
}

TEST(DynamicTreeTest, AvlBoundIsFibonacci) {
  EXPECT_EQ(avl_height_bound(1), 0);
  EXPECT_EQ(avl_height_bound(2), 1);
  EXPECT_EQ(avl_height_bound(3), 2);
  EXPECT_EQ(avl_height_bound(4), 2);
  EXPECT_EQ(avl_height_bound(5), 3);     // F(5) = 5
  EXPECT_EQ(avl_height_bound(500), 12);  // F(14) = 377 <= 500 < F(15) = 610
}

Aabb random_box(std::mt19937& rng, double world, double max_half) {
  std::uniform_real_distribution<double> position(-world, world);
  std::uniform_real_distribution<double> half(0.05, max_half);
  const Vec3 centre(position(rng), position(rng), position(rng));
  const Vec3 extent(half(rng), half(rng), half(rng));
  return Aabb{centre - extent, centre + extent};
}

// The live leaves, by user value, with their proxy and box.
struct Leaf {
  std::int32_t proxy;
  Aabb box;
};

void expect_queries_match_brute_force(const DynamicTree& tree, const std::map<std::uint32_t, Leaf>& leaves,
                                      std::mt19937& rng, int round) {
  ASSERT_EQ(tree.leaf_count(), leaves.size());
  for (const auto& [user, leaf] : leaves) {
    ASSERT_EQ(tree.user(leaf.proxy), user);
    ASSERT_EQ(tree.fat_aabb(leaf.proxy).min, leaf.box.min);
    ASSERT_EQ(tree.fat_aabb(leaf.proxy).max, leaf.box.max);
  }
  for (int q = 0; q < 40; ++q) {
    const Aabb query = random_box(rng, 50.0, q % 4 == 0 ? 20.0 : 5.0);
    std::vector<std::uint32_t> found;
    tree.query(query, [&](std::uint32_t user) { found.push_back(user); });
    std::vector<std::uint32_t> expected;
    for (const auto& [user, leaf] : leaves) {
      if (leaf.box.overlaps(query)) expected.push_back(user);
    }
    std::sort(found.begin(), found.end());  // each once: duplicates would survive the sort
    ASSERT_EQ(found, expected) << "round " << round << ", query " << q;
  }
}

TEST(DynamicTreeTest, QueriesMatchBruteForceThroughInsertsMovesAndRemoves) {
  std::mt19937 rng(2718);
  DynamicTree tree;
  std::map<std::uint32_t, Leaf> leaves;
  std::uint32_t next_user = 0;
  auto insert = [&] {
    const Aabb box = random_box(rng, 50.0, 3.0);
    leaves[next_user] = Leaf{tree.create_proxy(box, next_user), box};
    ++next_user;
  };
  auto pick = [&]() -> std::map<std::uint32_t, Leaf>::iterator {
    auto it = leaves.begin();
    std::advance(it, static_cast<long>(rng() % leaves.size()));
    return it;
  };
  for (int i = 0; i < 500; ++i) insert();
  expect_queries_match_brute_force(tree, leaves, rng, -1);
  EXPECT_LE(tree.height(), avl_height_bound(tree.leaf_count()));

  for (int round = 0; round < 30; ++round) {
    // Moves: most small (a body drifting out of its fat box), some across
    // the world.
    for (int k = 0; k < 100; ++k) {
      Leaf& leaf = pick()->second;
      if (k % 5 == 0) {
        leaf.box = random_box(rng, 50.0, 3.0);
      } else {
        std::uniform_real_distribution<double> step(-1.0, 1.0);
        const Vec3 shift(step(rng), step(rng), step(rng));
        leaf.box = Aabb{leaf.box.min + shift, leaf.box.max + shift};
      }
      tree.move_proxy(leaf.proxy, leaf.box);
    }
    for (int k = 0; k < 25; ++k) {
      const auto it = pick();
      tree.destroy_proxy(it->second.proxy);
      leaves.erase(it);
    }
    for (int k = 0; k < 25; ++k) insert();
    expect_queries_match_brute_force(tree, leaves, rng, round);
    EXPECT_LE(tree.height(), avl_height_bound(tree.leaf_count())) << "round " << round;
  }
  EXPECT_EQ(tree.leaf_count(), 500u);

  // Emptied, the tree reports nothing and height -1.
  for (const auto& [user, leaf] : leaves) tree.destroy_proxy(leaf.proxy);
  EXPECT_EQ(tree.leaf_count(), 0u);
  EXPECT_EQ(tree.height(), -1);
  int visits = 0;
  tree.query(Aabb{Vec3::Constant(-100), Vec3::Constant(100)}, [&](std::uint32_t) { ++visits; });
  EXPECT_EQ(visits, 0);
}

TEST(DynamicTreeTest, SortedInsertionStaysBalanced) {
  // Boxes in a row inserted left to right: without rotations each new leaf
  // would pair with the last one and the tree would grow a spine of height
  // n - 1.
  DynamicTree tree;
  std::map<std::uint32_t, Leaf> leaves;
  for (std::uint32_t i = 0; i < 2048; ++i) {
    const Aabb box{Vec3(i, 0.0, 0.0), Vec3(i + 0.5, 1.0, 1.0)};
    leaves[i] = Leaf{tree.create_proxy(box, i), box};
  }
  EXPECT_LE(tree.height(), avl_height_bound(2048));
  EXPECT_GE(tree.height(), 11);  // a binary tree of 2048 leaves cannot be shallower
  // Removing every other one keeps it correct and balanced.
  for (std::uint32_t i = 0; i < 2048; i += 2) {
    tree.destroy_proxy(leaves[i].proxy);
    leaves.erase(i);
  }
  EXPECT_LE(tree.height(), avl_height_bound(1024));
  std::mt19937 rng(5);
  for (int q = 0; q < 50; ++q) {
    std::uniform_real_distribution<double> x(-10.0, 2060.0);
    const double lo = x(rng);
    const Aabb query{Vec3(lo, 0.5, 0.5), Vec3(lo + 7.3, 0.6, 0.6)};
    std::vector<std::uint32_t> found;
    tree.query(query, [&](std::uint32_t user) { found.push_back(user); });
    std::sort(found.begin(), found.end());
    std::vector<std::uint32_t> expected;
    for (const auto& [user, leaf] : leaves) {
      if (leaf.box.overlaps(query)) expected.push_back(user);
    }
    EXPECT_EQ(found, expected);
  }
}

TEST(DynamicTreeTest, TouchingBoxesOverlap) {
  // Aabb::overlaps counts shared faces as overlap, so two resting bodies
  // whose boxes just touch are paired.
  DynamicTree tree;
  tree.create_proxy(Aabb{Vec3(0, 0, 0), Vec3(1, 1, 1)}, 7);
  int visits = 0;
  tree.query(Aabb{Vec3(1, 0, 0), Vec3(2, 1, 1)}, [&](std::uint32_t user) { visits += user == 7 ? 1 : 100; });
  EXPECT_EQ(visits, 1);
  tree.query(Aabb{Vec3(1.0 + 1e-12, 0, 0), Vec3(2, 1, 1)}, [&](std::uint32_t) { visits += 100; });
  EXPECT_EQ(visits, 1);
}

}  // namespace
}  // namespace tumble::physics
