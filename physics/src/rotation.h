// Rotations: the exponential map from rotation vectors to unit quaternions
// and the change of frame of second-order tensors. Pure functions;
// thread-safe.
#pragma once

#include "tumble/physics/math.h"

namespace tumble::physics {

// The unit quaternion of a rotation by the angle |theta| (rad) about the axis
// theta / |theta|: exp(theta) = [cos(|theta|/2), sin(|theta|/2) theta/|theta|].
// Exact for any angle (no small-angle approximation of the rotation) and
// smooth through theta = 0.
Quat quat_from_rotation_vector(const Vec3& theta);

// Whether t is exactly c times the identity (the inertia of a cube or a
// sphere, or its inverse): then R t R^T = t for every rotation R.
bool is_isotropic(const Mat3& t);

// A tensor given in body axes expressed in world axes: R T R^T with R the
// rotation matrix of q (Baraff, "The Inertia Tensor": I(t) = R I_body R^T);
// an isotropic tensor as it is.
Mat3 body_to_world_tensor(const Quat& q, const Mat3& tensor_body);
// The same with R given.
Mat3 body_to_world_tensor(const Mat3& r, const Mat3& tensor_body);
// (R T R^T) v without forming the product: R (T (R^T v)), or c v for an
// isotropic T = c 1.
Vec3 apply_body_to_world_tensor(const Mat3& r, const Mat3& tensor_body, const Vec3& v);

}  // namespace tumble::physics
