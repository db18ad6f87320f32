// A rigid transform body -> world with its rotation as a matrix, the form the
// collision code wants (one matrix product per point instead of a quaternion
// sandwich). Plain value type.
#pragma once

#include "tumble/physics/math.h"

namespace tumble::physics {

struct Transform {
  Vec3 position = Vec3::Zero();      // origin of the body frame in the world (m)
  Mat3 rotation = Mat3::Identity();  // columns are the body axes in the world

  Vec3 apply(const Vec3& local) const { return rotation * local + position; }
  Vec3 apply_inverse(const Vec3& world) const { return rotation.transpose() * (world - position); }
};

}  // namespace tumble::physics
