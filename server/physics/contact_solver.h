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
// (Coulomb's cone).
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
// Islands: the constraints are grouped by the dynamic bodies they connect
// (static and kinematic bodies, which no constraint moves, do not join
// islands), and each island is solved on its own, start to end, as one task
// of a WorkerTeam. No two islands write the same body or contact, so the
// islands may run on several threads at once; each island's arithmetic is the
// same whichever thread runs it and however many there are, so results do not
// depend on the thread count. The rows are built before, in blocks of
// constraints taken in the contacts' order.
//
// Fixed bodies: a contact against a body of inverse mass 0 at rest (the
// ground, a static box, a kinematic body standing still) has every term of
// that body zero, so its rows are built and solved for the other body alone
// (as Jolt dispatches its contact solve on the two bodies' motion types);
// the arithmetic of the terms kept is the same, and so are the results.
//
// Thread: prepare() and solve() from the World's thread; solve() runs
// islands on the team's threads and returns when all are done. Arrays are
// reused; no allocation once warmed up.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "physics/contact.h"
#include "physics/math.h"
#include "physics/transform.h"
#include "physics/worker_team.h"

namespace tumble::physics {

// A body's velocity during the solve (m/s, rad/s, world frame).
struct SolverVelocity {
  Vec3 linear = Vec3::Zero();
  Vec3 angular = Vec3::Zero();
};

struct ContactSolverSettings {
  int substeps = 4;          // >= 1
  int iterations = 1;        // soft passes per substep, >= 1
  int relax_iterations = 1;  // rigid passes per substep, >= 0
  double contact_hertz = 30;   // stiffness of the push out of overlap (Hz); capped at a quarter of the substep rate
  double damping_ratio = 10;   // of that push
  double max_push_speed = 3;   // m/s
  double restitution_threshold = 1.0;  // m/s: slower impacts do not bounce
};

// Per-body inputs, all indexed by dense body index. Static and kinematic
// bodies have inverse mass 0 and a zero inverse inertia.
struct ContactSolverBodies {
  std::span<const double> inverse_mass;            // 1/M
  std::span<const Mat3> inverse_inertia;           // I^-1 in the world frame, this step
  std::span<const Transform> transforms;           // centre of mass position this step
  std::span<const double> friction;                // coefficient of each body
  std::span<const double> restitution;             // coefficient of each body
  std::span<const SolverVelocity> external_change;  // change of v and w over the step from gravity and forces
};

class ContactSolver {
 public:
  // Lists a constraint for each contact in active that has points
  // (links[k] names the bodies of contacts[k]) and groups them into islands.
  // contacts and bodies must stay unchanged until solve() returns; solve()
  // writes the contacts' impulses.
  void prepare(std::span<Contact> contacts, std::span<const ContactLink> links, std::span<const std::uint32_t> active,
               const ContactSolverBodies& bodies, double dt, const ContactSolverSettings& settings);
  // Room for this many constraints and four points each, reserved (not
  // written) ahead of need, so a step whose contacts multiply does not copy
  // the rows it has built so far.
  void reserve(std::size_t constraints);
  // Builds the rows, then solves each island, on team's threads (on the
  // caller's alone when team is null): runs the substeps, relax passes and
  // restitution on velocities, and stores the impulses in the contacts for
  // the next step's warm start. velocities holds every body's velocity at
  // the end of the step before contacts (the external change already added).
  void solve(std::span<SolverVelocity> velocities, WorkerTeam* team);

  // Dynamic bodies in at least one constraint this step, island by island.
  std::span<const std::uint32_t> touched_bodies() const { return touched_; }
  // For a touched body after solve(): (displacement of the substeps - v dt)
  // / dt and the same for rotation, where v and w are the final velocities.
  SolverVelocity pseudo_velocity(std::uint32_t body, const SolverVelocity& final_velocity) const;
  std::size_t constraint_count() const { return constraint_count_; }
  std::size_t point_count() const { return point_count_; }
  std::size_t island_count() const { return islands_.size(); }

 private:
  // One row: a direction d at one point, with its angular Jacobians and
  // their products with the inverse inertias, indexed by side (0 for body
  // a, 1 for body b); a fixed side's entries are not written.
  struct Row {
    Vec3 jacobian[2];    // r_a x d, r_b x d
    Vec3 response[2];    // I_a^-1 (r_a x d), I_b^-1 (r_b x d)
    double mass = 0;     // effective mass
    double impulse = 0;  // accumulated
  };
  struct Point {
    Row normal;
    Row tangent1;
    Row tangent2;
    double separation = 0;         // s_0, at the start of the step (m)
    double relative_velocity = 0;  // normal velocity before the solve (m/s)
    double max_normal_impulse = 0;
  };
  struct Constraint {
    std::uint32_t body_a = 0;
    std::uint32_t body_b = 0;
    std::uint32_t contact = 0;
    std::uint32_t first_point = 0;
    std::uint32_t point_count = 0;
    double inverse_mass_a = 0;
    double inverse_mass_b = 0;
    double friction = 0;
    double restitution = 0;
    bool against_infinite_mass = false;  // one body static or kinematic: stiffer push
    // A body of inverse mass 0 at rest (static, or kinematic standing
    // still) is fixed: every term of its velocity, motion and inertia is
    // zero, and the rows keep only the other side's (one_sided_pass()).
    // kBothSides when neither is fixed.
    std::uint8_t moving_side = kBothSides;
    Vec3 normal;
    Vec3 tangent1;
    Vec3 tangent2;
  };
  // Position of a body within the step, relative to its start.
  struct Motion {
    Vec3 displacement = Vec3::Zero();  // dp (m)
    Vec3 rotation = Vec3::Zero();      // dtheta, sum of w h (rad)
  };
  // The implicit spring of a soft row (Box2D's b2Softness).
  struct Softness {
    double bias_rate = 0;      // 1/s
    double mass_scale = 1;
    double impulse_scale = 0;
  };

  // What a normal row asks this pass at separation s: the velocity bias
  // (m/s) and the mass and impulse scales (1 and 0 for a rigid row).
  struct NormalTarget {
    double bias = 0;
    double mass_scale = 1;
    double impulse_scale = 0;
  };

  // Constraints [first_constraint, + constraint_count) and dynamic bodies
  // touched_[first_body, + body_count) that no other island shares.
  struct Island {
    std::uint32_t first_constraint = 0;
    std::uint32_t constraint_count = 0;
    std::uint32_t first_body = 0;
    std::uint32_t body_count = 0;
    std::uint32_t point_count = 0;
  };
  // The constraints of one island, and a body's motion within the substeps
  // so far: a dynamic body's is tracked in motion_; a static or kinematic
  // body, whose velocity no constraint changes, has moved elapsed v.
  struct IslandView {
    std::span<Constraint> constraints;
    std::span<const std::uint32_t> bodies;
    double elapsed = 0;  // s of substeps integrated
  };

  static constexpr std::uint8_t kBothSides = 2;

  // The moving body of a constraint with a fixed one: its side (0 for a,
  // 1 for b) and dense index, and the sign of its share of an impulse
  // (body b takes the impulse, a its opposite).
  struct MovingBody {
    int side = 0;
    std::uint32_t body = 0;
    double inverse_mass = 0;
    double sign = 0;
  };
  static MovingBody moving_body(const Constraint& c);

  std::uint32_t island_root(std::uint32_t body);
  void touch(std::uint32_t body);
  void solve_island(const Island& island, std::span<SolverVelocity> velocities);
  void build_rows(Constraint& c, std::span<const SolverVelocity> velocities);
  Motion motion_of(std::uint32_t body, double inverse_mass, const SolverVelocity& velocity, double elapsed) const;
  void warm_start(const IslandView& island, std::span<SolverVelocity> velocities) const;
  void solve_pass(const IslandView& island, std::span<SolverVelocity> velocities, bool soft);
  void one_sided_pass(const Constraint& c, const IslandView& island, std::span<SolverVelocity> velocities, bool soft);
  NormalTarget normal_target(const Constraint& c, double separation, bool soft) const;
  static double accumulate_normal(Point& p, double vn, const NormalTarget& target);
  static void accumulate_friction(Point& p, double friction, double vt1, double vt2, double* d1, double* d2);
  void integrate_motion(const IslandView& island, std::span<const SolverVelocity> velocities);
  void apply_restitution(const IslandView& island, std::span<SolverVelocity> velocities);
  void store_impulses(const IslandView& island) const;

  // This step's constraints, island by island, and their points: the first
  // constraint_count_ and point_count_ entries (the vectors only grow).
  std::vector<Constraint> constraints_;
  std::vector<Point> points_;
  std::size_t constraint_count_ = 0;
  std::size_t point_count_ = 0;
  std::vector<Island> islands_;
  std::vector<std::uint32_t> island_order_;  // islands by falling point count: the order a team's tasks start
  std::vector<Motion> motion_;
  std::vector<std::uint8_t> is_touched_;
  std::vector<std::uint32_t> touched_;
  // Scratch of prepare(): the contacts with points in active order, a
  // union-find forest over dynamic bodies and each root's island.
  std::vector<std::uint32_t> pending_;
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> island_of_root_;
  std::vector<std::uint32_t> island_of_pending_;
  std::vector<std::uint32_t> slot_of_pending_;  // where each pending contact's constraint went
  std::span<Contact> contacts_;
  ContactSolverBodies bodies_;
  ContactSolverSettings settings_;
  double dt_ = 0;
  double h_ = 0;  // substep
  double inverse_h_ = 0;
  Softness soft_;
  Softness static_soft_;
};

}  // namespace tumble::physics
