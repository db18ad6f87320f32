// The per-body records a World keeps in its dense arrays: BodyState, which
// step() advances, and BodyMass, which is fixed at creation. Plain data; the
// World owns every instance.
#pragma once

#include "tumble/physics/math.h"

namespace tumble::physics {

// Dynamic state in Baraff's form ("Rigid Body Equations of Motion"): the
// momenta P and L, not the velocities, are the state variables; v and w are
// derived from them. All vectors in the world frame.
struct BodyState {
  Vec3 position = Vec3::Zero();          // x: centre of mass (m)
  Quat orientation = Quat::Identity();   // q: body -> world, unit, [w, x, y, z]
  Vec3 linear_momentum = Vec3::Zero();   // P = M v (kg m/s)
  Vec3 angular_momentum = Vec3::Zero();  // L = I w, about the centre of mass (kg m^2/s)
  Vec3 force = Vec3::Zero();             // F accumulated for the next step (N)
  Vec3 torque = Vec3::Zero();            // tau about the centre of mass, accumulated (N m)
};

// Constant mass data. Inertia tensors are about the centre of mass in body
// axes; the world-frame tensor is R I_body R^T (Baraff, "The Inertia
// Tensor").
struct BodyMass {
  double mass = 0;                           // M (kg)
  double inverse_mass = 0;                   // 1 / M
  Mat3 inertia_body = Mat3::Zero();          // I_body (kg m^2)
  Mat3 inverse_inertia_body = Mat3::Zero();  // I_body^-1
};

}  // namespace tumble::physics
