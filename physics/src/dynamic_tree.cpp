#include "dynamic_tree.h"

#include <algorithm>
#include <cassert>

namespace tumble::physics {

std::int32_t DynamicTree::allocate_node() {
  if (free_list_ == kNull) {
    nodes_.emplace_back();
    return static_cast<std::int32_t>(nodes_.size() - 1);
  }
  const std::int32_t i = free_list_;
  free_list_ = node(i).parent;
  node(i) = Node{};
  return i;
}

void DynamicTree::free_node(std::int32_t i) {
  node(i).parent = free_list_;
  node(i).height = -1;
  free_list_ = i;
}

std::int32_t DynamicTree::create_proxy(const Aabb& fat, std::uint32_t user) {
  const std::int32_t leaf = allocate_node();
  node(leaf).box = fat;
  node(leaf).user = user;
  node(leaf).height = 0;
  insert_leaf(leaf);
  ++leaf_count_;
  return leaf;
}

void DynamicTree::destroy_proxy(std::int32_t proxy) {
  assert(node(proxy).is_leaf());
  remove_leaf(proxy);
  free_node(proxy);
  --leaf_count_;
}

void DynamicTree::move_proxy(std::int32_t proxy, const Aabb& fat) {
  remove_leaf(proxy);
  node(proxy).box = fat;
  insert_leaf(proxy);
}

void DynamicTree::insert_leaf(std::int32_t leaf) {
  if (root_ == kNull) {
    root_ = leaf;
    node(leaf).parent = kNull;
    return;
  }
  const Aabb leaf_box = node(leaf).box;

  // Descend to the best sibling. At node i, pairing the leaf with i itself
  // costs the area of a new parent, 2 area(i + leaf); going further down
  // costs the growth of i, area(i + leaf) - area(i), plus the cost below.
  std::int32_t i = root_;
  while (!node(i).is_leaf()) {
    const Node& n = node(i);
    const double area = n.box.half_area();
    const double combined = merge(n.box, leaf_box).half_area();
    const double pair_here = 2.0 * combined;
    const double inheritance = 2.0 * (combined - area);
    auto descend_cost = [&](std::int32_t child) {
      const Node& c = node(child);
      const double grown = merge(leaf_box, c.box).half_area();
      return (c.is_leaf() ? grown : grown - c.box.half_area()) + inheritance;
    };
    const double cost1 = descend_cost(n.child1);
    const double cost2 = descend_cost(n.child2);
    if (pair_here < cost1 && pair_here < cost2) break;
    i = cost1 <= cost2 ? n.child1 : n.child2;
  }
  const std::int32_t sibling = i;

  const std::int32_t old_parent = node(sibling).parent;
  const std::int32_t parent = allocate_node();
  node(parent).parent = old_parent;
  node(parent).box = merge(leaf_box, node(sibling).box);
  node(parent).height = node(sibling).height + 1;
  node(parent).child1 = sibling;
  node(parent).child2 = leaf;
  node(sibling).parent = parent;
  node(leaf).parent = parent;
  if (old_parent == kNull) {
    root_ = parent;
  } else if (node(old_parent).child1 == sibling) {
    node(old_parent).child1 = parent;
  } else {
    node(old_parent).child2 = parent;
  }
  refit_upwards(node(leaf).parent);
}

void DynamicTree::remove_leaf(std::int32_t leaf) {
  if (leaf == root_) {
    root_ = kNull;
    return;
  }
  const std::int32_t parent = node(leaf).parent;
  const std::int32_t grandparent = node(parent).parent;
  const std::int32_t sibling = node(parent).child1 == leaf ? node(parent).child2 : node(parent).child1;
  if (grandparent == kNull) {
    root_ = sibling;
    node(sibling).parent = kNull;
    free_node(parent);
    return;
  }
  if (node(grandparent).child1 == parent) {
    node(grandparent).child1 = sibling;
  } else {
    node(grandparent).child2 = sibling;
  }
  node(sibling).parent = grandparent;
  free_node(parent);
  refit_upwards(grandparent);
}

void DynamicTree::refit_upwards(std::int32_t i) {
  while (i != kNull) {
    i = balance(i);
    Node& n = node(i);
    n.height = 1 + std::max(node(n.child1).height, node(n.child2).height);
    n.box = merge(node(n.child1).box, node(n.child2).box);
    i = n.parent;
  }
}

// An AVL rotation at node a when its subtrees differ in height by more than
// one: the taller child c takes a's place and a adopts c's shorter child.
// Returns the node now at a's position.
std::int32_t DynamicTree::balance(std::int32_t ia) {
  Node& a = node(ia);
  if (a.is_leaf() || a.height < 2) return ia;
  const std::int32_t ib = a.child1;
  const std::int32_t ic = a.child2;
  const int skew = node(ic).height - node(ib).height;
  if (skew > 1 || skew < -1) {
    // Rotate the taller child (up) over a; "keep" is the child that stays
    // with a, "up" the one that rises.
    const bool c_taller = skew > 1;
    const std::int32_t iup = c_taller ? ic : ib;
    const std::int32_t ikeep = c_taller ? ib : ic;
    Node& up = node(iup);
    const std::int32_t if1 = up.child1;
    const std::int32_t ig1 = up.child2;
    up.child1 = ia;
    up.parent = a.parent;
    a.parent = iup;
    if (up.parent == kNull) {
      root_ = iup;
    } else if (node(up.parent).child1 == ia) {
      node(up.parent).child1 = iup;
    } else {
      node(up.parent).child2 = iup;
    }
    // The taller grandchild stays under up; the shorter moves under a in
    // the slot that up left.
    const bool f_taller = node(if1).height > node(ig1).height;
    const std::int32_t istay = f_taller ? if1 : ig1;
    const std::int32_t imove = f_taller ? ig1 : if1;
    up.child2 = istay;
    if (c_taller) {
      a.child2 = imove;
    } else {
      a.child1 = imove;
    }
    node(imove).parent = ia;
    a.box = merge(node(ikeep).box, node(imove).box);
    a.height = 1 + std::max(node(ikeep).height, node(imove).height);
    up.box = merge(a.box, node(istay).box);
    up.height = 1 + std::max(a.height, node(istay).height);
    return iup;
  }
  return ia;
}

}  // namespace tumble::physics
