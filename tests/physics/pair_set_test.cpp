// The contacts' pair set (pair_set.h): after every insert and erase of a
// long random run, each pair in a reference map is found with its value in
// either order and no other pair is, also while the entries wrap around
// the end of the table and after it has grown many times.
#include "pair_set.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <random>
#include <utility>

namespace tumble::physics {
namespace {

using Pair = std::pair<std::uint32_t, std::uint32_t>;

Pair ordered(std::uint32_t a, std::uint32_t b) { return a < b ? Pair{a, b} : Pair{b, a}; }

// Inserts a pair of `bodies` bodies not in the set, or erases one that is,
// `steps` times at random, and after each compares every pair with a map.
void check_random_run(std::uint32_t bodies, std::uint32_t steps, std::uint32_t seed) {
  PairSet set;
  std::map<Pair, std::uint32_t> reference;
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::uint32_t> body(0, bodies - 1);
  for (std::uint32_t step = 0; step < steps; ++step) {
    const std::uint32_t a = body(random), b = body(random);
    if (a == b) continue;
    const auto it = reference.find(ordered(a, b));
    if (it == reference.end()) {
      set.insert(a, b, step);
      reference.emplace(ordered(a, b), step);
    } else {
      set.erase(b, a);
      reference.erase(it);
    }
    ASSERT_EQ(set.size(), reference.size());
    for (std::uint32_t x = 0; x < bodies; ++x) {
      for (std::uint32_t y = x + 1; y < bodies; ++y) {
        const auto found = reference.find({x, y});
        const std::uint32_t expected = found == reference.end() ? PairSet::kNotFound : found->second;
        ASSERT_EQ(set.find(x, y), expected) << "pair " << x << ", " << y << " at step " << step;
        ASSERT_EQ(set.find(y, x), expected) << "pair " << y << ", " << x << " at step " << step;
      }
    }
  }
}

TEST(PairSet, FindsWhatWasInsertedAndNothingErased) {
  // Few bodies, so the run erases and inserts the same pairs again and
  // again in a small table: its probe runs often wrap around its end.
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    check_random_run(7, 2000, seed);
    if (HasFatalFailure()) return;
  }
  check_random_run(24, 20000, 7);
}

TEST(PairSet, GrowsAndKeepsEveryPair) {
  PairSet set;
  EXPECT_EQ(set.find(1, 2), PairSet::kNotFound);
  // Body 0 against many, and large indices: keys that differ in one half only.
  for (std::uint32_t k = 1; k <= 5000; ++k) {
    set.insert(0, k, k);
    set.insert(0xfffffffe - k, 0xfffffffe, 2 * k);
  }
  EXPECT_EQ(set.size(), 10000u);
  for (std::uint32_t k = 1; k <= 5000; ++k) {
    ASSERT_EQ(set.find(k, 0), k);
    ASSERT_EQ(set.find(0xfffffffe, 0xfffffffe - k), 2 * k);
  }
  EXPECT_EQ(set.find(1, 2), PairSet::kNotFound);
  for (std::uint32_t k = 1; k <= 5000; k += 2) set.erase(0, k);
  for (std::uint32_t k = 1; k <= 5000; ++k) {
    ASSERT_EQ(set.find(0, k), k % 2 == 1 ? PairSet::kNotFound : k);
  }
}

}  // namespace
}  // namespace tumble::physics
