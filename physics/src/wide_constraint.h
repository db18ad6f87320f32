// Wide constraints: four contact constraints of one colour
// (constraint_graph.h) solved at once, one in each lane of Float4
// (float4.h), as Box2D v3 solves its colours (Catto, "Solver2D", 2024).
// Here are their rows, the build of the rows from the contacts, and the
// gather and scatter of the lanes' bodies between the slots of a group
// (SolverBody, one body a row) and Vec3x4 (one component a Float4).
//
// Each lane's arms and friction directions are found in double precision
// and stored in single; the rows are then built from them in single
// precision, the four lanes at once. The row terms follow
// contact_solver.h: with r_a, r_b the contact point relative to the
// centres of mass and d the row direction, the Jacobians r_a x d and
// r_b x d, their products with the inverse inertias (the responses) and
// the effective mass
//   1 / (1/M_a + 1/M_b + (r_a x d).I_a^-1 (r_a x d) + (r_b x d).I_b^-1 (r_b x d)).
// A lane without a constraint, or whose constraint has fewer points, holds
// zeros and takes no impulse.
//
// Slots: index 0 of a group's slots is its slot of zeros, read by a static
// body, or a kinematic one standing still: no velocity, no motion, and
// (their inverse mass and inertia being zero) no response.
//
// Thread: plain data and functions of their arguments; a group's wide
// constraints are touched by the thread that solves the group.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>

#include "contact.h"
#include "contact_islands.h"
#include "float4.h"
#include "solver_body.h"

namespace tumble::physics {

// Lanes of a wide constraint (Float4).
inline constexpr int kLanes = 4;
// The constraint of an unused lane.
inline constexpr std::uint32_t kNoConstraint = 0xffffffff;

// One row of four lanes: a direction d at one point of each lane's
// constraint, with its angular Jacobians r_a x d, r_b x d, their products
// with the inverse inertias, the effective mass and the accumulated
// impulse.
struct WideRow {
  Vec3x4 jacobian_a, jacobian_b;
  Vec3x4 response_a, response_b;
  Float4 mass, impulse;
};

// The rows at the k-th point of each lane's constraint.
struct WidePoint {
  WideRow normal, tangent1, tangent2;
  Float4 separation;         // s_0, at the start of the step (m)
  Float4 relative_velocity;  // normal velocity before the solve (m/s)
  Float4 max_normal_impulse;
};

// Four constraints of one colour (no two move the same body), lane by
// lane: their body slots, relative to the group's first slot, and
// constraint index (kNoConstraint in an unused lane), then the rows'
// common terms. A soft row's spring (contact_solver.h, step 3) differs
// between lanes against a body of infinite mass and the others.
struct WideConstraint {
  std::uint32_t slot_a[kLanes] = {};
  std::uint32_t slot_b[kLanes] = {};
  std::uint32_t constraint[kLanes] = {};
  std::uint32_t first_point = 0;  // in the solver's WidePoint array
  std::uint32_t point_count = 0;  // the most of the four lanes
  Vec3x4 normal, tangent1, tangent2;
  Float4 inverse_mass_a, inverse_mass_b;
  Float4 friction, restitution;
  Float4 bias_rate, mass_scale, impulse_scale;
  // The spin row about the normal of a lane whose contact has one point
  // (contact_solver.h): the responses I^-1 n, its effective mass (zero in
  // the other lanes), its impulse, and friction * spin_friction.
  Vec3x4 spin_response_a, spin_response_b;
  Float4 spin_mass, spin_impulse, spin_limit;
  bool spins = false;  // whether any lane has a spin row
  // Whether some lane's side a (b) reads a slot other than the slot of
  // zeros. A side that none does (a body of infinite mass at rest in every
  // lane, as the ground under a pile) is skipped by the passes.
  bool moves_a = true, moves_b = true;
};

// The implicit spring of a soft row (Box2D's b2Softness).
struct Softness {
  double bias_rate = 0;  // 1/s
  double mass_scale = 1;
  double impulse_scale = 0;
};

// The spring of frequency `hertz` with `damping_ratio` over a substep h
// (b2MakeSoft): with omega = 2 pi f and zeta the damping ratio,
// a1 = 2 zeta + h omega, a2 = h omega a1, a3 = 1 / (1 + a2); bias rate
// omega / a1, mass scale a2 a3, impulse scale a3. hertz <= 0: a rigid row.
Softness make_softness(double hertz, double damping_ratio, double h);

// What build_lane() reads besides its constraint: the step's bodies, their
// velocities before the solve, and the springs of the soft rows.
struct WideRowInputs {
  ContactSolverBodies bodies;
  std::span<const SolverVelocity> velocities;
  Softness soft;             // between two dynamic bodies
  Softness static_soft;      // against a body of infinite mass
  double spin_friction = 0;  // m (WorldSettings::spin_friction)
};

// A 3 x 3 matrix of four lanes, row by row: lane l holds the l-th of four
// matrices.
struct Mat3x4 {
  Vec3x4 row[3];
};

inline Vec3x4 operator*(const Mat3x4& m, const Vec3x4& v) {
  return {dot4(m.row[0], v), dot4(m.row[1], v), dot4(m.row[2], v)};
}

inline Vec3x4 cross4(const Vec3x4& a, const Vec3x4& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// What the rows of a wide constraint are built from, lane by lane: each
// point's arms r_a and r_b, the bodies' inverse inertias and velocities
// (all zero on a side read from the slot of zeros), and which lanes have a
// point k. Filled by build_lane(), read by build_rows().
struct WideArms {
  Vec3x4 arm_a[kMaxManifoldPoints], arm_b[kMaxManifoldPoints];
  Mask4 has_point[kMaxManifoldPoints];
  Mat3x4 inverse_inertia_a, inverse_inertia_b;
  Vec3x4 linear_a, linear_b, angular_a, angular_b;
};

// Writes lane `lane` of w and of its points (w.first_point's, at points)
// from constraint c and its contact: the common terms, the friction
// directions, the spin row, and for each point its separation and the
// accumulated impulses of the last step as the rows' impulses; and the
// lane of arms. In double precision, then stored in single. Expects w's
// slots set, the lane's terms and arms zero.
void build_lane(const WideRowInputs& in, const ContactConstraint& c, const Contact& contact, int lane,
                WideConstraint& w, WidePoint* points, WideArms& arms);

// Then the rows of every lane at once: for each point and direction d, the
// Jacobians r_a x d and r_b x d, their responses and the effective mass
// (zero in a lane without that point), and the normal velocity before the
// solve. A side read from the slot of zeros has zero arms, so its terms
// stay zero.
void build_rows(WideConstraint& w, WidePoint* points, const WideArms& arms);

// The velocities of one side of four lanes, and their motion.
struct WideVelocity {
  Vec3x4 linear, angular;
};
struct WideMotion {
  Vec3x4 displacement, rotation;
};

inline void set_lane(Vec3x4& v, int lane, const Vec3& x) {
  v.x[lane] = static_cast<float>(x.x());
  v.y[lane] = static_cast<float>(x.y());
  v.z[lane] = static_cast<float>(x.z());
}

inline Vec3 lane_of(const Vec3x4& v, int lane) { return Vec3(v.x[lane], v.y[lane], v.z[lane]); }

// The first three floats of four rows, one row a lane, as three Float4 (a
// 4 x 4 transpose; the fourth float of each row is padding).
[[gnu::always_inline]] inline Vec3x4 transpose_rows(const float* r0, const float* r1, const float* r2,
                                                    const float* r3) {
  Float4 a, b, c, d;
  std::memcpy(&a, r0, sizeof a);
  std::memcpy(&b, r1, sizeof b);
  std::memcpy(&c, r2, sizeof c);
  std::memcpy(&d, r3, sizeof d);
  const Float4 xy01 = __builtin_shufflevector(a, b, 0, 4, 1, 5);  // x0 x1 y0 y1
  const Float4 xy23 = __builtin_shufflevector(c, d, 0, 4, 1, 5);
  const Float4 zw01 = __builtin_shufflevector(a, b, 2, 6, 3, 7);  // z0 z1 w0 w1
  const Float4 zw23 = __builtin_shufflevector(c, d, 2, 6, 3, 7);
  return Vec3x4{__builtin_shufflevector(xy01, xy23, 0, 1, 4, 5), __builtin_shufflevector(xy01, xy23, 2, 3, 6, 7),
                __builtin_shufflevector(zw01, zw23, 0, 1, 4, 5)};
}

// One vector of a SolverBody (linear, angular, displacement or rotation).
using SolverBodyField = float (SolverBody::*)[4];

// That vector of the bodies in slots index[0..3], lane by lane.
[[gnu::always_inline]] inline Vec3x4 gather(const SolverBody* slots, const std::uint32_t (&index)[kLanes],
                                            SolverBodyField field) {
  return transpose_rows(slots[index[0]].*field, slots[index[1]].*field, slots[index[2]].*field, slots[index[3]].*field);
}

[[gnu::always_inline]] inline WideVelocity gather_velocity(const SolverBody* slots,
                                                           const std::uint32_t (&index)[kLanes]) {
  return WideVelocity{gather(slots, index, &SolverBody::linear), gather(slots, index, &SolverBody::angular)};
}

[[gnu::always_inline]] inline WideMotion gather_motion(const SolverBody* slots, const std::uint32_t (&index)[kLanes]) {
  return WideMotion{gather(slots, index, &SolverBody::displacement), gather(slots, index, &SolverBody::rotation)};
}

// Writes lane l's velocities back to slot index[l], for the lanes whose
// body moves (inverse_mass[l] != 0): a lane's body of infinite mass may be
// another lane's too, or the slot of zeros.
[[gnu::always_inline]] inline void scatter_velocity(SolverBody* slots, const std::uint32_t (&index)[kLanes],
                                                    const Float4& inverse_mass, const WideVelocity& v) {
  // Lane l's (x, y, z, 0) of both vectors: the transpose back.
  const Float4 zero = splat4(0.0f);
  const Float4 xy01 = __builtin_shufflevector(v.linear.x, v.linear.y, 0, 4, 1, 5);  // x0 y0 x1 y1
  const Float4 xy23 = __builtin_shufflevector(v.linear.x, v.linear.y, 2, 6, 3, 7);
  const Float4 z01 = __builtin_shufflevector(v.linear.z, zero, 0, 4, 1, 5);  // z0 0 z1 0
  const Float4 z23 = __builtin_shufflevector(v.linear.z, zero, 2, 6, 3, 7);
  const Float4 linear[4] = {
      __builtin_shufflevector(xy01, z01, 0, 1, 4, 5), __builtin_shufflevector(xy01, z01, 2, 3, 6, 7),
      __builtin_shufflevector(xy23, z23, 0, 1, 4, 5), __builtin_shufflevector(xy23, z23, 2, 3, 6, 7)};
  const Float4 axy01 = __builtin_shufflevector(v.angular.x, v.angular.y, 0, 4, 1, 5);
  const Float4 axy23 = __builtin_shufflevector(v.angular.x, v.angular.y, 2, 6, 3, 7);
  const Float4 az01 = __builtin_shufflevector(v.angular.z, zero, 0, 4, 1, 5);
  const Float4 az23 = __builtin_shufflevector(v.angular.z, zero, 2, 6, 3, 7);
  const Float4 angular[4] = {
      __builtin_shufflevector(axy01, az01, 0, 1, 4, 5), __builtin_shufflevector(axy01, az01, 2, 3, 6, 7),
      __builtin_shufflevector(axy23, az23, 0, 1, 4, 5), __builtin_shufflevector(axy23, az23, 2, 3, 6, 7)};
  for (int lane = 0; lane < kLanes; ++lane) {
    if (inverse_mass[lane] == 0) continue;
    SolverBody& b = slots[index[lane]];
    std::memcpy(b.linear, &linear[lane], sizeof b.linear);
    std::memcpy(b.angular, &angular[lane], sizeof b.angular);
  }
}

}  // namespace tumble::physics
