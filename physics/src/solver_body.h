// The bodies as the contact solver sees them (contact_solver.h): a body's
// velocity in double precision, the per-body inputs of a step, and a body's
// slot in single precision while a group is solved.
#pragma once

#include <span>

#include "transform.h"
#include "tumble/physics/math.h"

namespace tumble::physics {

// A body's velocity during the solve (m/s, rad/s, world frame).
struct SolverVelocity {
  Vec3 linear = Vec3::Zero();
  Vec3 angular = Vec3::Zero();
};

// Per-body inputs, all indexed by dense body index. Static and kinematic
// bodies have inverse mass 0 and a zero inverse inertia.
struct ContactSolverBodies {
  std::span<const double> inverse_mass;             // 1/M
  std::span<const Mat3> inverse_inertia;            // I^-1 in the world frame, this step
  std::span<const Transform> transforms;            // centre of mass position this step
  std::span<const double> friction;                 // coefficient of each body
  std::span<const double> restitution;              // coefficient of each body
  std::span<const SolverVelocity> external_change;  // change of v and w over the step from gravity and forces
};

// A body during the solve of its group, single precision, world frame: its
// velocity (m/s, rad/s) and its motion within the step so far, the
// displacement dp (m) and rotation dtheta = sum of w h (rad). The fourth
// float of each is padding, so a vector loads as one Float4.
struct alignas(16) SolverBody {
  float linear[4] = {};
  float angular[4] = {};
  float displacement[4] = {};
  float rotation[4] = {};
};

// One vector of a SolverBody (or of a slot laid out like one) in double
// precision, and back, its padding zeroed.
inline Vec3 load_vec3(const float (&x)[4]) { return Vec3(x[0], x[1], x[2]); }

inline void store_vec3(float (&to)[4], const Vec3& x) {
  to[0] = static_cast<float>(x.x());
  to[1] = static_cast<float>(x.y());
  to[2] = static_cast<float>(x.z());
  to[3] = 0.0f;
}

}  // namespace tumble::physics
