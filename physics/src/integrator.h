// The time-stepping scheme of a single rigid body. World::step applies it to
// every body; it is exposed for tests and for tools that advance one body.
//
// Linear part, semi-implicit (symplectic) Euler on Baraff's state
// ("Rigid Body Equations of Motion"):
//   P_{n+1} = P_n + (F + M g) dt
//   v_{n+1} = P_{n+1} / M
//   x_{n+1} = x_n + v_{n+1} dt
//
// Angular part: L_{n+1} = L_n + tau dt, then L_{n+1} is held fixed while the
// orientation turns through the implicit midpoint rule on the rotation group:
//   w_mid = R_mid I_body^-1 R_mid^T L_{n+1},  q_mid = exp(w_mid dt/2) q_n
//   q_{n+1} = exp(w_mid dt) q_n
// with exp the exact quaternion exponential of a rotation vector. Because L
// is the state, a torque-free body keeps L exactly; because the rotation
// update is time-symmetric, its kinetic energy oscillates with an O(dt^2)
// amplitude and does not drift.
//
// Pure functions; thread-safe.
#pragma once

#include "body_state.h"
#include "tumble/physics/math.h"

namespace tumble::physics {

// Orientation after turning for dt seconds with the world-frame angular
// momentum held at angular_momentum, by the implicit midpoint update above.
// w_mid is found by fixed-point iteration starting from w at q_n; each
// iteration shrinks the error by about |w| dt / 2 times the body's inertia
// anisotropy, so it converges in a few iterations while |w| dt is well below
// one radian per step. An isotropic body needs none: w = I_body^-1 L at
// every orientation. The result is normalised.
Quat advance_orientation(const Quat& orientation, const Vec3& angular_momentum, const Mat3& inverse_inertia_body,
                         double dt);

// One step of dt seconds for one body under gravity g (m/s^2) and the force
// and torque accumulated in state. Does not clear the accumulators.
// Equivalent to integrate_momentum followed by integrate_pose; World::step
// runs the contact solver between the two.
void integrate_body(BodyState& state, const BodyMass& mass, const Vec3& gravity, double dt);

// The momentum half: P += (F + M g) dt, L += tau dt.
void integrate_momentum(BodyState& state, const BodyMass& mass, const Vec3& gravity, double dt);

// The pose half: x += (P / M) dt, and q turned by the implicit midpoint
// update with L held fixed.
void integrate_pose(BodyState& state, const BodyMass& mass, double dt);

}  // namespace tumble::physics
