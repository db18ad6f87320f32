// DynamicTree: a bounding volume hierarchy of "fat" AABBs, changed one leaf
// at a time. A leaf is inserted next to the sibling that grows the tree's
// total surface area least (the surface area heuristic, descending greedily
// from the root), and each node on the way back up is rebalanced by an AVL
// rotation (the design of Box2D's b2DynamicTree; Catto, "Dynamic Bounding
// Volume Hierarchies", GDC 2019).
//
// A body's leaf holds its AABB enlarged by a margin, so small motions stay
// inside it and do not touch the tree at all.
//
// Nodes live in one array with a free list; proxy ids are node indices and
// stay valid until destroyed. The tree's shape depends only on the sequence
// of calls. Not thread-safe. Queries do not allocate once the stack has
// grown to the tree's height.
#pragma once

#include <cstdint>
#include <vector>

#include "aabb.h"

namespace tumble::physics {

class DynamicTree {
 public:
  static constexpr std::int32_t kNull = -1;

  // Adds a leaf with the given fat box and user value; returns its proxy id.
  std::int32_t create_proxy(const Aabb& fat, std::uint32_t user);
  void destroy_proxy(std::int32_t proxy);
  // Replaces a leaf's box (remove and reinsert).
  void move_proxy(std::int32_t proxy, const Aabb& fat);

  const Aabb& fat_aabb(std::int32_t proxy) const { return nodes_[static_cast<std::size_t>(proxy)].box; }
  std::uint32_t user(std::int32_t proxy) const { return nodes_[static_cast<std::size_t>(proxy)].user; }
  void set_user(std::int32_t proxy, std::uint32_t user) { nodes_[static_cast<std::size_t>(proxy)].user = user; }

  // Calls visit(user) for every leaf whose box overlaps box, in a fixed
  // order (depth first, child1 before child2).
  template <typename Visit>
  void query(const Aabb& box, Visit&& visit) const;

  // Height of the root (a single leaf has height 0; an empty tree -1).
  int height() const { return root_ == kNull ? -1 : nodes_[static_cast<std::size_t>(root_)].height; }
  std::size_t leaf_count() const { return leaf_count_; }

 private:
  struct Node {
    Aabb box;
    std::int32_t parent = kNull;  // also the free-list link of a free node
    std::int32_t child1 = kNull;  // kNull for leaves
    std::int32_t child2 = kNull;
    std::int32_t height = 0;  // 0 for leaves, -1 for free nodes
    std::uint32_t user = 0;
    bool is_leaf() const { return child1 == kNull; }
  };

  Node& node(std::int32_t i) { return nodes_[static_cast<std::size_t>(i)]; }
  const Node& node(std::int32_t i) const { return nodes_[static_cast<std::size_t>(i)]; }

  std::int32_t allocate_node();
  void free_node(std::int32_t i);
  void insert_leaf(std::int32_t leaf);
  void remove_leaf(std::int32_t leaf);
  // Refits boxes and heights from node i to the root, rotating as it goes.
  void refit_upwards(std::int32_t i);
  std::int32_t balance(std::int32_t a);

  std::vector<Node> nodes_;
  std::int32_t root_ = kNull;
  std::int32_t free_list_ = kNull;
  std::size_t leaf_count_ = 0;
  mutable std::vector<std::int32_t> stack_;
};

template <typename Visit>
void DynamicTree::query(const Aabb& box, Visit&& visit) const {
  if (root_ == kNull) return;
  stack_.clear();
  stack_.push_back(root_);
  while (!stack_.empty()) {
    const std::int32_t i = stack_.back();
    stack_.pop_back();
    const Node& n = node(i);
    if (!n.box.overlaps(box)) continue;
    if (n.is_leaf()) {
      visit(n.user);
    } else {
      // Pushed in reverse so child1 is visited first.
      stack_.push_back(n.child2);
      stack_.push_back(n.child1);
    }
  }
}

}  // namespace tumble::physics
