#include "contact_islands.h"

#include "union_find.h"

namespace tumble::physics {
namespace {

// No body, no island: an unset entry of the union-find scratch.
constexpr std::uint32_t kNone = 0xffffffff;

}  // namespace

void ContactIslands::add_body(std::uint32_t body, std::span<const double> inverse_mass) {
  if (body == kNoJointBody || inverse_mass[body] == 0 || listed_[body]) return;
  listed_[body] = 1;
  bodies_.push_back(body);
}

void ContactIslands::reserve(std::size_t constraints) {
  constraints_.reserve(constraints);
  pending_.reserve(constraints);
  island_of_pending_.reserve(constraints);
  islands_.reserve(constraints);
}

void ContactIslands::build(std::span<const Contact> contacts, std::span<const ContactLink> links,
                           std::span<const std::uint32_t> active, std::span<const JointConstraint> joints,
                           std::span<const double> inverse_mass) {
  constraint_count_ = 0;
  point_count_ = 0;
  islands_.clear();
  bodies_.clear();
  pending_.clear();
  joints_.clear();
  const std::size_t body_count = inverse_mass.size();
  if (listed_.size() < body_count) {
    listed_.resize(body_count, 0);
    parent_.resize(body_count, kNone);
    island_of_root_.resize(body_count, kNone);
  }

  // The contacts with points and the joints, and the forest their dynamic
  // bodies form.
  auto dynamic = [&](std::uint32_t body) { return body != kNoJointBody && inverse_mass[body] != 0; };
  auto join = [&](std::uint32_t a, std::uint32_t b) {
    if (dynamic(a) && parent_[a] == kNone) parent_[a] = a;
    if (dynamic(b) && parent_[b] == kNone) parent_[b] = b;
    // The forest's shape depends only on the order of the contacts and
    // joints (union_find.h).
    if (dynamic(a) && dynamic(b)) unite(parent_, a, b);
  };
  for (std::uint32_t index : active) {
    if (contacts[index].manifold.point_count == 0) continue;
    pending_.push_back(index);
    join(links[index].body_a, links[index].body_b);
  }
  for (const JointConstraint& j : joints) join(j.body_a, j.body_b);
  if (pending_.empty() && joints.empty()) return;

  // Islands numbered in the order their first contact comes; counted first,
  // so each island's constraints can be placed in a range of their own.
  island_of_pending_.resize(pending_.size());
  for (std::size_t k = 0; k < pending_.size(); ++k) {
    const std::uint32_t index = pending_[k];
    const std::uint32_t a = links[index].body_a, b = links[index].body_b;
    std::uint32_t island = kNone;
    if (dynamic(a) || dynamic(b)) {
      const std::uint32_t r = find_root(parent_, dynamic(a) ? a : b);
      if (island_of_root_[r] == kNone) {
        island_of_root_[r] = static_cast<std::uint32_t>(islands_.size());
        islands_.emplace_back();
      }
      island = island_of_root_[r];
    } else {
      island = static_cast<std::uint32_t>(islands_.size());
      islands_.emplace_back();
    }
    island_of_pending_[k] = island;
    ++islands_[island].constraint_count;
    islands_[island].point_count += static_cast<std::uint32_t>(contacts[index].manifold.point_count);
  }
  // The joints' islands: their bodies' (every joint has a dynamic body).
  island_of_joint_.resize(joints.size());
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const JointConstraint& j = joints[k];
    const std::uint32_t r = find_root(parent_, dynamic(j.body_a) ? j.body_a : j.body_b);
    if (island_of_root_[r] == kNone) {
      island_of_root_[r] = static_cast<std::uint32_t>(islands_.size());
      islands_.emplace_back();
    }
    island_of_joint_[k] = island_of_root_[r];
    ++islands_[island_of_root_[r]].joint_count;
  }
  std::uint32_t first = 0, first_point = 0, first_joint = 0;
  for (ContactIsland& island : islands_) {
    island.first_constraint = first;
    first += island.constraint_count;
    first_point += island.point_count;
    island.constraint_count = 0;  // counts again as the constraints are placed
    island.first_joint = first_joint;
    first_joint += island.joint_count;
    island.joint_count = 0;
  }
  joints_.resize(joints.size());
  for (std::size_t k = 0; k < joints.size(); ++k) {
    ContactIsland& island = islands_[island_of_joint_[k]];
    joints_[island.first_joint + island.joint_count++] = joints[k];
  }
  // Grown, never shrunk: the entries of a build are all written below.
  constraint_count_ = pending_.size();
  point_count_ = first_point;
  if (constraints_.size() < constraint_count_) constraints_.resize(constraint_count_);

  // Constraints island by island, each island's in active order.
  for (std::size_t k = 0; k < pending_.size(); ++k) {
    ContactIsland& island = islands_[island_of_pending_[k]];
    ContactConstraint& c = constraints_[island.first_constraint + island.constraint_count++];
    c.contact = pending_[k];
    c.body_a = links[c.contact].body_a;
    c.body_b = links[c.contact].body_b;
    c.point_count = static_cast<std::uint32_t>(contacts[c.contact].manifold.point_count);
    c.may_touch = links[c.contact].may_touch;
    c.speculative = links[c.contact].speculative;
  }
  for (ContactIsland& island : islands_) {
    island.first_body = static_cast<std::uint32_t>(bodies_.size());
    for (std::uint32_t k = 0; k < island.constraint_count; ++k) {
      const ContactConstraint& c = constraints_[island.first_constraint + k];
      add_body(c.body_a, inverse_mass);
      add_body(c.body_b, inverse_mass);
    }
    for (std::uint32_t k = 0; k < island.joint_count; ++k) {
      const JointConstraint& j = joints_[island.first_joint + k];
      add_body(j.body_a, inverse_mass);
      add_body(j.body_b, inverse_mass);
    }
    island.body_count = static_cast<std::uint32_t>(bodies_.size()) - island.first_body;
  }

  // The scratch is cleared for the next build through the bodies it holds
  // (every dynamic body the forest holds is in a constraint, so listed).
  for (std::uint32_t body : bodies_) {
    listed_[body] = 0;
    island_of_root_[body] = kNone;
    parent_[body] = kNone;
  }
}

}  // namespace tumble::physics
