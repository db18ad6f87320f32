// ContactIslands: the islands of one step, built once from the contacts
// with manifold points and read by the contact solver (which solves islands
// apart, contact_solver.h) and by the sleep pass (World::update_sleep,
// island.cpp), as Box2D v3 shares its islands between the two (island.c).
//
// An island is a set of dynamic bodies connected by touching contacts and
// joints, with those contacts and joints. Static and kinematic bodies (inverse mass 0) join no
// island: a floor under two piles keeps them apart, and a chain hung from
// the world is an island of its own. A contact between two bodies of
// infinite mass is an island of its own without bodies.
//
// Order, which the solver's results depend on: islands are numbered in the
// order their first contact comes in `active`, then the islands of joints
// alone in joint order; an island's constraints follow `active`, its joints
// the joint order; its bodies come in the order its constraints, then its
// joints, first name them (body_a before body_b). The union-find forest behind them (path
// halving, the smaller index becomes the root) depends only on that order.
//
// Thread: one thread at a time. Arrays are reused; build() does not
// allocate once they have grown to the scene.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "contact.h"

namespace tumble::physics {

// A contact with points, as the islands list it: its index in the contacts
// and links, its bodies (dense indices) and its number of manifold points.
struct ContactConstraint {
  std::uint32_t body_a = 0;
  std::uint32_t body_b = 0;
  std::uint32_t contact = 0;
  std::uint32_t point_count = 0;
  bool may_touch = false;    // ContactLink::may_touch
  bool speculative = false;  // ContactLink::speculative
};

// A joint's side on the world rather than a body.
inline constexpr std::uint32_t kNoJointBody = 0xffffffff;

// A joint as the islands list it: its bodies (dense indices, kNoJointBody
// for the world) and its index in the World's joints.
struct JointConstraint {
  std::uint32_t body_a = 0;
  std::uint32_t body_b = 0;
  std::uint32_t joint = 0;
};

// Constraints [first_constraint, + constraint_count) of
// ContactIslands::constraints(), dynamic bodies [first_body, + body_count)
// of ContactIslands::bodies(), joints [first_joint, + joint_count) of
// ContactIslands::joints(), and the manifold points of those constraints.
struct ContactIsland {
  std::uint32_t first_constraint = 0;
  std::uint32_t constraint_count = 0;
  std::uint32_t first_joint = 0;
  std::uint32_t joint_count = 0;
  std::uint32_t first_body = 0;
  std::uint32_t body_count = 0;
  std::uint32_t point_count = 0;
};

class ContactIslands {
 public:
  // Lists a constraint for each contact in active that has points
  // (links[k] names the bodies of contacts[k]) and groups them, with the
  // joints (each with at least one dynamic body), into islands;
  // inverse_mass (one per dense body) tells dynamic bodies (> 0) from the
  // rest. Replaces the islands of the previous build.
  void build(std::span<const Contact> contacts, std::span<const ContactLink> links,
             std::span<const std::uint32_t> active, std::span<const JointConstraint> joints,
             std::span<const double> inverse_mass);
  // Room for this many constraints, reserved ahead of need.
  void reserve(std::size_t constraints);

  std::span<const ContactIsland> islands() const { return islands_; }
  // The constraints, island by island.
  std::span<const ContactConstraint> constraints() const { return {constraints_.data(), constraint_count_}; }
  // The dynamic bodies in at least one constraint, island by island; each
  // once.
  std::span<const std::uint32_t> bodies() const { return bodies_; }
  // The joints, island by island.
  std::span<const JointConstraint> joints() const { return joints_; }
  std::size_t point_count() const { return point_count_; }

 private:
  void add_body(std::uint32_t body, std::span<const double> inverse_mass);

  // The first constraint_count_ entries (the vector only grows).
  std::vector<ContactConstraint> constraints_;
  std::size_t constraint_count_ = 0;
  std::size_t point_count_ = 0;
  std::vector<ContactIsland> islands_;
  std::vector<JointConstraint> joints_;
  std::vector<std::uint32_t> bodies_;
  // Scratch of build(), indexed by dense body (cleared through bodies_
  // before build() returns): whether bodies_ holds the body yet, the
  // union-find forest, and each root's island.
  std::vector<std::uint8_t> listed_;
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> island_of_root_;
  // Scratch of build(), by contact with points in active order: the
  // contact and its island.
  std::vector<std::uint32_t> pending_;
  std::vector<std::uint32_t> island_of_pending_;
  std::vector<std::uint32_t> island_of_joint_;  // by joint in the order given
};

}  // namespace tumble::physics
