// ContactSolver: sequential impulses on the contact points of one step
// (Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005, and "Fast
// and Simple Physics using Sequential Impulses", GDC 2006), arranged as
// Box2D v3's soft step (Catto, "Solver2D", 2024): the step is split into
// substeps, and each substep
//   1. adds its share of gravity and the external forces to v and w,
//   2. warm starts: applies the accumulated impulses again,
//   3. solves the rows with soft contacts: a penetration s < 0 asks for the
//      separating velocity -bias_rate s (at most max_push_speed), through a
//      spring of contact_hertz with damping ratio damping_ratio, written
//      implicitly as a mass scale and an impulse scale (Catto, "Soft Step",
//      GDC 2011 / Box2D b2MakeSoft),
//   4. moves the bodies by h v (tracked as displacements dp and rotations
//      dtheta of the bodies), so the next substep sees the new separations,
//   5. relaxes: solves again without the push, so the separating velocity the
//      push added moves the bodies but does not stay in their momentum.
// After the substeps comes restitution, then the impulses are stored for the
// next step's warm start.
//
// Rows, with r_a, r_b the contact point relative to the centres of mass
// (fixed for the step) and d the row direction (normal or tangent):
//   relative velocity  c' = d.(v_b - v_a) + (r_b x d).w_b - (r_a x d).w_a
//   effective mass     m = 1 / (1/M_a + 1/M_b + (r_a x d).I_a^-1 (r_a x d) + (r_b x d).I_b^-1 (r_b x d))
//   impulse            lambda = -m s_m (c' + bias) - s_i lambda_acc, accumulated and clamped
// with s_m, s_i the mass and impulse scales (1 and 0 for a rigid row). The
// separation during the step is s = s_0 + d.(dp_b - dp_a) +
// (r_b x d).dtheta_b - (r_a x d).dtheta_a. A speculative point (s > 0) has
// bias s/h, so the bodies may close the gap within the substep but not pass
// it. Normal: accumulated impulse >= 0. Friction: the two tangent impulses
// are clamped together to the disc of radius friction * normal impulse
// (Coulomb's cone). Spin (a contact of one point only): the angular row
// c' = n.(w_b - w_a), m = 1 / (n.I_a^-1 n + n.I_b^-1 n), its impulse
// clamped to friction * spin_friction * normal impulse.
//
// Restitution (Baraff, "Physically Based Modeling: Rigid Body Simulation II"
// section 8, the colliding-contact impulse; applied after the substeps as in
// Box2D v3): a point that approached faster than the threshold and took an
// impulse gets v_n^+ = -e v_n^-.
//
// The solver works on velocities v, w of the bodies (World writes back P =
// M v, L = I w). The displacement of the substeps differs from v dt by
// little; that difference is handed back as a pseudo-velocity which World
// adds to its usual pose update (split-impulse style), so positions follow
// the substeps while the momenta keep only the relaxed velocities.
//
// Islands (contact_islands.h): the constraints are grouped by the dynamic
// bodies they connect; prepare() builds them once a step and islands()
// hands them on (to World's sleep pass). Consecutive islands are gathered
// into groups of at least kGroupPoints points, and each group is solved on
// its own, start to end, as one task of a TaskSystem
// (contact_solver_tasks.cpp). No two groups write the same body or
// contact, so they may run on several threads at once; the groups do not
// depend on the thread count, and each group's arithmetic is the same
// whichever thread runs it, so results do not depend on the thread count.
//
// Wide rows: within a group the constraints are coloured so that no two of
// one colour move the same body (constraint_graph.h), and each colour is
// packed four constraints at a time into a wide constraint, solved in the
// four lanes of Float4 at once (wide_constraint.h). Static bodies and
// kinematic bodies that stand still take no slot: their terms read a slot
// of zeros. A constraint for which no colour is free is solved in a wide
// constraint of its own (one lane used). Within a colour, the contacts
// whose points are all apart are packed together, after the others: a
// point at which no lane holds an impulse, normal or friction, skips its
// friction rows in a pass (the disc is a point at zero, so they would
// change nothing) and the warm start, which mostly spares the speculative
// points of bodies still falling side by side. The arms and friction
// directions are found in double precision, the rows built and solved in
// single precision; the solve hands back each body's change of velocity,
// added to its double velocity.
//
// Thread: prepare() and solve() from the World's thread; solve() runs
// groups on the team's threads and returns when all are done. Arrays are
// reused; no allocation once warmed up.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "constraint_graph.h"
#include "contact.h"
#include "contact_islands.h"
#include "joint_solver.h"
#include "solver_body.h"
#include "tumble/physics/math.h"
#include "tumble/physics/task_system.h"
#include "wide_constraint.h"

namespace tumble::physics {

struct ContactSolverSettings {
  int substeps = 4;           // >= 1
  int iterations = 1;         // soft passes per substep, >= 1
  int relax_iterations = 1;   // rigid passes per substep, >= 0
  double contact_hertz = 30;  // stiffness of the push out of overlap (Hz); capped at a quarter of the substep rate
  double damping_ratio = 10;  // of that push
  double max_push_speed = 3;  // m/s
  double restitution_threshold = 1.0;  // m/s: slower impacts do not bounce
  double spin_friction = 0.005;        // m: a one-point contact's torsional friction arm
  double joint_hertz = 0;              // the joints' spring (Hz); 0: twice contact_hertz
  double joint_damping_ratio = 2;
  double joint_position_correction = 0.2;  // fraction of a joint's gap closed after the substeps
};

class ContactSolver {
 public:
  // Builds this step's islands (contact_islands.h) from the contacts in
  // active that have points (links[k] names the bodies of contacts[k]) and
  // the joints to solve (joint_edges, each naming one of joints), and takes
  // the step's settings. contacts, joints and bodies must stay unchanged
  // until solve() returns; solve() writes the contacts' and the joints'
  // impulses (joint_solver.h).
  // velocities: every body's, as solve() will get them (a kinematic body's
  // tells whether it moves). When the constraints are those of the last
  // step (the same contacts with the same bodies and point counts, the same
  // joints, each body as dynamic, moving or fixed as it was), the last
  // step's islands and plan are kept: they depend on nothing else.
  void prepare(std::span<Contact> contacts, std::span<const ContactLink> links, std::span<const std::uint32_t> active,
               std::span<Joint> joints, std::span<const JointConstraint> joint_edges, const ContactSolverBodies& bodies,
               std::span<const SolverVelocity> velocities, double dt, const ContactSolverSettings& settings);
  // Room for this many constraints and four points each, reserved (not
  // written) ahead of need, so a step whose contacts multiply does not copy
  // the rows it has built so far.
  void reserve(std::size_t constraints);
  // Gathers the islands into groups, colours each group's constraints and
  // packs them into wide constraints (on the caller's thread; unless
  // prepare() kept the last step's), then builds
  // and solves each group on team's threads (on the caller's alone when
  // team is null): runs the substeps, relax passes and
  // restitution on velocities, and stores the impulses in the contacts for
  // the next step's warm start. velocities holds every body's velocity at
  // the end of the step before contacts (the external change already added).
  void solve(std::span<SolverVelocity> velocities, TaskSystem* team);

  // This step's islands, as prepare() built them; valid until the next
  // prepare().
  const ContactIslands& islands() const { return islands_; }
  // Dynamic bodies in at least one constraint this step, island by island.
  std::span<const std::uint32_t> touched_bodies() const { return islands_.bodies(); }
  // For a touched body after solve(): (displacement of the substeps - v dt)
  // / dt and the same for rotation, where v and w are the final velocities.
  SolverVelocity pseudo_velocity(std::uint32_t body, const SolverVelocity& final_velocity) const;
  std::size_t constraint_count() const { return islands_.constraints().size(); }
  std::size_t joint_count() const { return islands_.joints().size(); }
  std::size_t point_count() const { return islands_.point_count(); }
  std::size_t island_count() const { return islands_.islands().size(); }
  // Whether this step kept the last step's islands and plan (prepare()).
  bool plan_kept() const { return plan_kept_; }

 private:
  // Consecutive islands solved as one task: their constraints, joints and
  // bodies (contiguous, as the islands'), the body slots [first_slot, + slot_count)
  // of solver_bodies_ (slot first_slot is the group's slot of zeros) and the
  // wide constraints [first_wide, + wide_count).
  struct Group {
    std::uint32_t first_constraint = 0;
    std::uint32_t constraint_count = 0;
    std::uint32_t first_body = 0;
    std::uint32_t body_count = 0;
    std::uint32_t first_joint = 0;
    std::uint32_t joint_count = 0;
    std::uint32_t point_count = 0;  // the contacts' points, and kJointPoints for each joint: the group's work
    std::uint32_t first_slot = 0;
    std::uint32_t slot_count = 0;
    std::uint32_t first_wide = 0;
    std::uint32_t wide_count = 0;
  };
  // Position of a body within the step, relative to its start.
  struct Motion {
    Vec3 displacement = Vec3::Zero();  // dp (m)
    Vec3 rotation = Vec3::Zero();      // dtheta, sum of w h (rad)
  };

  static constexpr std::uint32_t kNoBody = 0xffffffff;

  // How the plan reads a body: fixed (static, or kinematic and standing
  // still: the slot of zeros), dynamic (a slot in its group), or moving (a
  // kinematic body in motion: a slot of its own in each group that reads
  // it). velocities as solve() gets them.
  enum class BodyKind : std::uint8_t { fixed, dynamic, moving };
  BodyKind kind_of(std::uint32_t body, std::span<const SolverVelocity> velocities) const;

  // Groups and their dispatch (contact_solver_tasks.cpp): plan() gathers
  // the islands into groups and plans each.
  void plan(std::span<const SolverVelocity> velocities);
  void plan_group(Group& group, std::span<const SolverVelocity> velocities);
  // The passes (contact_solver.cpp).
  void solve_group(const Group& group, std::span<SolverVelocity> velocities);
  void warm_start(const Group& group);
  void solve_pass(const Group& group, bool soft);
  void solve_joints(const Group& group, bool soft);
  void apply_restitution(const Group& group);
  void store_impulses(const Group& group) const;

  ContactIslands islands_;
  ConstraintGraph graph_;  // scratch of plan_group()
  std::vector<Group> groups_;
  std::vector<std::uint32_t> group_order_;  // groups by falling point count: the order a team's tasks start
  std::vector<SolverBody> solver_bodies_;
  std::vector<SolverBody> solver_external_;  // each slot's change of v and w over the step (linear, angular)
  // Each slot's turn so far in the step, exp(rotation), for its joints:
  // measured once after each move rather than once per joint of the body.
  std::vector<Quat> slot_turns_;
  std::vector<WideConstraint> wide_;
  std::vector<WidePoint> wide_points_;
  std::vector<Motion> motion_;  // by dense body, written by solve() for the touched bodies
  // The body of each slot of solver_bodies_ (kNoBody for a group's slot of
  // zeros): the group's dynamic bodies, then the kinematic bodies in motion
  // it reads.
  std::vector<std::uint32_t> slot_body_;
  std::size_t slot_count_ = 0;
  std::size_t wide_count_ = 0;
  std::size_t wide_point_count_ = 0;
  // Scratch of plan_group(): a body's slot in its group (a kinematic
  // body's only where slot_stamp_ holds the group's plan_stamp_).
  std::vector<std::uint32_t> slot_of_body_;
  std::vector<std::uint64_t> slot_stamp_;
  std::vector<std::uint32_t> packing_;  // a colour's members, one-sided first
  std::uint64_t plan_stamp_ = 0;
  // The slots of each joint of islands_.joints() in its group, and its row.
  struct JointSlots {
    std::uint32_t a = 0;
    std::uint32_t b = 0;
  };
  std::vector<JointSlots> joint_slots_;
  // What the islands and the plan are made from (prepare()): per contact
  // its slot and bodies, then its point count, flags and the bodies'
  // kinds; per joint the same. This step's and the last planned step's.
  std::vector<std::uint64_t> plan_key_;
  std::vector<std::uint64_t> planned_key_;
  bool planned_ = false;    // solve() planned from planned_key_'s islands
  bool plan_kept_ = false;  // this step reuses them
  std::vector<JointRow> joint_rows_;
  std::span<Contact> contacts_;
  std::span<Joint> joints_;
  JointStepSettings joint_settings_;
  ContactSolverBodies bodies_;
  ContactSolverSettings settings_;
  double dt_ = 0;
  double h_ = 0;  // substep
  double inverse_h_ = 0;
  Softness soft_;
  Softness static_soft_;
};

}  // namespace tumble::physics
