// Union-find over a forest kept as a parent array (parent[x] == x at a
// root), shared by the solver's islands (contact_islands.h) and the sleep
// pass's groups (island.cpp). Path halving on find; a union makes the
// smaller root the root of both, so the forest's shape depends only on the
// order of the unions. Not thread-safe; allocates nothing.
#pragma once

#include <cstdint>
#include <span>

namespace tumble::physics {

// The root of x's tree, halving the path on the way.
inline std::uint32_t find_root(std::span<std::uint32_t> parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// Joins the trees of a and b.
inline void unite(std::span<std::uint32_t> parent, std::uint32_t a, std::uint32_t b) {
  const std::uint32_t root_a = find_root(parent, a), root_b = find_root(parent, b);
  if (root_a < root_b) parent[root_b] = root_a;
  if (root_b < root_a) parent[root_a] = root_b;
}

}  // namespace tumble::physics
