// Vector, quaternion and matrix types of the physics layer.
//
// Conventions used throughout tumble::physics:
//   - SI units: metres, kilograms, seconds, radians, newtons.
//   - Right-handed axes, +Y up.
//   - "World frame" is the fixed inertial frame; "body frame" has its origin at
//     the body's centre of mass and turns with the body. A body's orientation
//     q maps body-frame vectors to world-frame vectors: v_world = q * v_body.
//   - Quaternions are Eigen::Quaterniond, read as [w, x, y, z] with w the
//     scalar part (Eigen stores them as x, y, z, w in memory; use .w(), .x(),
//     .y(), .z() rather than the raw coefficient array).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tumble::physics {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Mat3 = Eigen::Matrix3d;

}  // namespace tumble::physics
