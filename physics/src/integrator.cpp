#include "integrator.h"

#include "rotation.h"

namespace tumble::physics {
namespace {

// Fixed-point iterations for w_mid stop when an iteration changes w by less
// than this fraction of |w| (a few units of roundoff), or after
// kMaxMidpointIterations, which bounds the work for very fast spins.
constexpr double kMidpointTolerance = 1e-14;
constexpr int kMaxMidpointIterations = 16;

// w = I^-1 L with I^-1 = R I_body^-1 R^T (Baraff, "Angular Momentum").
Vec3 angular_velocity_at(const Quat& q, const Vec3& angular_momentum, const Mat3& inverse_inertia_body) {
  return apply_body_to_world_tensor(q.toRotationMatrix(), inverse_inertia_body, angular_momentum);
}

}  // namespace

Quat advance_orientation(const Quat& orientation, const Vec3& angular_momentum, const Mat3& inverse_inertia_body,
                         double dt) {
  // An isotropic body's w is the same at every orientation: w_mid is w,
  // and there is no rotation to build.
  const bool isotropic = is_isotropic(inverse_inertia_body);
  Vec3 w_mid = isotropic ? Vec3(inverse_inertia_body(0, 0) * angular_momentum)
                         : angular_velocity_at(orientation, angular_momentum, inverse_inertia_body);
  for (int i = 0; i < kMaxMidpointIterations && !isotropic; ++i) {
    // q_mid = exp(w_mid dt/2) q_n: the orientation half way through the step.
    const Quat q_mid = quat_from_rotation_vector((0.5 * dt) * w_mid) * orientation;
    const Vec3 next = angular_velocity_at(q_mid, angular_momentum, inverse_inertia_body);
    const double change2 = (next - w_mid).squaredNorm();
    w_mid = next;
    if (change2 <= kMidpointTolerance * kMidpointTolerance * w_mid.squaredNorm()) break;
  }
  // q_{n+1} = exp(w_mid dt) q_n. Left multiplication: w is in the world frame.
  // Normalising removes the roundoff the product accumulates.
  return (quat_from_rotation_vector(dt * w_mid) * orientation).normalized();
}

void integrate_momentum(BodyState& state, const BodyMass& mass, const Vec3& gravity, double dt) {
  // dP/dt = F (Baraff, "Rigid Body Equations of Motion"), gravity as M g.
  state.linear_momentum += (state.force + mass.mass * gravity) * dt;
  // dL/dt = tau.
  state.angular_momentum += state.torque * dt;
}

void integrate_pose(BodyState& state, const BodyMass& mass, double dt) {
  // Semi-implicit: the position moves with the updated velocity v = P / M.
  state.position += (state.linear_momentum * mass.inverse_mass) * dt;
  state.orientation = advance_orientation(state.orientation, state.angular_momentum, mass.inverse_inertia_body, dt);
}

void integrate_body(BodyState& state, const BodyMass& mass, const Vec3& gravity, double dt) {
  integrate_momentum(state, mass, gravity, dt);
  integrate_pose(state, mass, dt);
}

}  // namespace tumble::physics
