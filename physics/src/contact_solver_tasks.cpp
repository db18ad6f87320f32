// ContactSolver::solve: the islands gathered into groups, each group
// planned (its body slots, its colours and its wide constraints) on the
// caller's thread, then each group solved as one task of a TaskSystem
// (contact_solver.h, "Islands"). The passes a task runs are in
// contact_solver.cpp.
#include <algorithm>

#include "contact_solver.h"
#include "run_tasks.h"

namespace tumble::physics {
namespace {

// A group gathers islands until it holds this many points: enough to fill
// the lanes of each colour, few enough that the landing of a thousand boxes
// makes several tasks for a team.
constexpr std::uint32_t kGroupPoints = 1024;
// What a joint weighs in a group's work, in contact points: its rows are
// solved one at a time, in double precision.
constexpr std::uint32_t kJointPoints = 8;

}  // namespace

void ContactSolver::solve(std::span<SolverVelocity> velocities, TaskSystem* team) {
  if (!plan_kept_) plan(velocities);
  planned_ = true;
  if (team == nullptr || team->thread_count() == 1) {
    for (const Group& group : groups_) solve_group(group, velocities);
    return;
  }
  // Largest groups first, so the last task to start is a small one. (The
  // order changes which thread takes a group, not its result.)
  group_order_.resize(groups_.size());
  for (std::uint32_t i = 0; i < group_order_.size(); ++i) group_order_[i] = i;
  std::sort(group_order_.begin(), group_order_.end(), [&](std::uint32_t x, std::uint32_t y) {
    return groups_[x].point_count != groups_[y].point_count ? groups_[x].point_count > groups_[y].point_count : x < y;
  });
  auto task = [&](std::size_t k) { solve_group(groups_[group_order_[k]], velocities); };
  run_tasks(*team, group_order_.size(), task);
}

void ContactSolver::plan(std::span<const SolverVelocity> velocities) {
  // Groups of consecutive islands (their constraints and bodies are
  // contiguous), then their slots and wide constraints, on this thread.
  groups_.clear();
  slot_count_ = 0;
  wide_count_ = 0;
  wide_point_count_ = 0;
  for (const ContactIsland& island : islands_.islands()) {
    if (groups_.empty() || groups_.back().point_count >= kGroupPoints) {
      Group group;
      group.first_constraint = island.first_constraint;
      group.first_body = island.first_body;
      group.first_joint = island.first_joint;
      groups_.push_back(group);
    }
    Group& group = groups_.back();
    group.constraint_count += island.constraint_count;
    group.body_count += island.body_count;
    group.joint_count += island.joint_count;
    group.point_count += island.point_count + kJointPoints * island.joint_count;
  }
  const std::size_t joint_count = islands_.joints().size();
  if (joint_slots_.size() < joint_count) {
    joint_slots_.resize(joint_count);
    joint_rows_.resize(joint_count);
  }
  for (Group& group : groups_) plan_group(group, velocities);
  if (solver_bodies_.size() < slot_count_) {
    solver_bodies_.resize(slot_count_);
    solver_external_.resize(slot_count_);
    slot_turns_.resize(slot_count_);
  }
  if (wide_points_.size() < wide_point_count_) wide_points_.resize(wide_point_count_);
}

void ContactSolver::plan_group(Group& group, std::span<const SolverVelocity> velocities) {
  // Slots: the slot of zeros, the group's dynamic bodies, then each
  // kinematic body in motion that a constraint reads. A static body, or a
  // kinematic one standing still, reads the slot of zeros.
  group.first_slot = static_cast<std::uint32_t>(slot_count_);
  auto add_slot = [&](std::uint32_t body) {
    if (slot_body_.size() <= slot_count_) slot_body_.resize(slot_count_ + 1);
    slot_body_[slot_count_++] = body;
  };
  add_slot(kNoBody);
  const std::span<const std::uint32_t> bodies = islands_.bodies();
  for (std::uint32_t k = 0; k < group.body_count; ++k) {
    const std::uint32_t body = bodies[group.first_body + k];
    slot_of_body_[body] = k + 1;
    add_slot(body);
  }
  // A kinematic body's slot is valid in this group only: stamped with the
  // plan that made it.
  ++plan_stamp_;
  auto slot_of = [&](std::uint32_t body) -> std::uint32_t {
    const BodyKind kind = kind_of(body, velocities);
    if (kind == BodyKind::dynamic) return slot_of_body_[body];
    if (kind == BodyKind::fixed) return 0;
    if (slot_stamp_[body] != plan_stamp_) {
      slot_stamp_[body] = plan_stamp_;
      slot_of_body_[body] = static_cast<std::uint32_t>(slot_count_) - group.first_slot;
      add_slot(body);
    }
    return slot_of_body_[body];
  };

  const std::span<const ContactConstraint> constraints =
      islands_.constraints().subspan(group.first_constraint, group.constraint_count);
  graph_.colour(constraints, bodies_.inverse_mass, slot_of_body_, group.body_count);

  // Wide constraints: each colour four at a time, then the overflow one
  // at a time. Within a colour (no two of its constraints share a body, so
  // their order does not matter) those with side a on the slot of zeros
  // come first and those with side b there last: the passes skip a side
  // that every lane of a wide constraint has on the slot of zeros.
  group.first_wide = static_cast<std::uint32_t>(wide_count_);
  for (std::uint32_t colour = 0; colour <= ConstraintGraph::kOverflow; ++colour) {
    const std::span<const std::uint32_t> members = graph_.members(colour);
    const bool overflow = colour == ConstraintGraph::kOverflow;
    const std::size_t width = overflow ? 1 : kLanes;
    packing_.clear();
    if (overflow) {
      packing_.assign(members.begin(), members.end());
    } else {
      // Within each of the three, the contacts whose points are all apart
      // come last, so they share wide constraints: such a lane mostly
      // takes no impulse, and a point no lane pushes on skips its
      // friction (solve_wide).
      auto fixed = [&](std::uint32_t body) { return slot_of(body) == 0; };
      auto sides = [&](const ContactConstraint& c) { return fixed(c.body_a) ? 0 : fixed(c.body_b) ? 2 : 1; };
      for (int side = 0; side < 3; ++side) {
        for (const bool speculative : {false, true}) {
          for (const std::uint32_t m : members) {
            if (sides(constraints[m]) == side && constraints[m].speculative == speculative) packing_.push_back(m);
          }
        }
      }
    }
    for (std::size_t k = 0; k < packing_.size(); k += width) {
      if (wide_.size() <= wide_count_) wide_.resize(wide_count_ + 1);
      WideConstraint& w = wide_[wide_count_++];
      w.point_count = 0;
      w.moves_a = w.moves_b = false;
      for (int lane = 0; lane < kLanes; ++lane) {
        const std::size_t at = k + static_cast<std::size_t>(lane);
        if (static_cast<std::size_t>(lane) >= width || at >= packing_.size()) {
          w.constraint[lane] = kNoConstraint;
          w.slot_a[lane] = w.slot_b[lane] = 0;
          continue;
        }
        const std::uint32_t index = group.first_constraint + packing_[at];
        const ContactConstraint& c = constraints[packing_[at]];
        w.constraint[lane] = index;
        w.slot_a[lane] = slot_of(c.body_a);
        w.slot_b[lane] = slot_of(c.body_b);
        w.moves_a = w.moves_a || w.slot_a[lane] != 0;
        w.moves_b = w.moves_b || w.slot_b[lane] != 0;
        w.point_count = std::max(w.point_count, c.point_count);
      }
      w.first_point = static_cast<std::uint32_t>(wide_point_count_);
      wide_point_count_ += w.point_count;
    }
  }
  group.wide_count = static_cast<std::uint32_t>(wide_count_) - group.first_wide;

  // The joints' slots; a side on the world reads the slot of zeros.
  const std::span<const JointConstraint> joints = islands_.joints();
  for (std::uint32_t k = 0; k < group.joint_count; ++k) {
    const std::uint32_t index = group.first_joint + k;
    const JointConstraint& j = joints[index];
    joint_slots_[index].a = j.body_a == kNoJointBody ? 0 : slot_of(j.body_a);
    joint_slots_[index].b = j.body_b == kNoJointBody ? 0 : slot_of(j.body_b);
  }
  group.slot_count = static_cast<std::uint32_t>(slot_count_) - group.first_slot;
}

}  // namespace tumble::physics
