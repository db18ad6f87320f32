// Distance between two convex polytopes given as vertex sets (their convex
// hulls), by the Gilbert-Johnson-Keerthi algorithm (Ericson, "Real-Time
// Collision Detection" 9.5; van den Bergen, "Collision Detection in
// Interactive 3D Environments" 4.3). The narrowphase uses it for the cores of
// rounded shapes: a sphere is a point and a capsule a segment, each with a
// radius, against a box or hull.
//
// Pure function; thread-safe; no allocation.
#pragma once

#include <span>

#include "tumble/physics/math.h"

namespace tumble::physics {

struct GjkResult {
  Vec3 point_a = Vec3::Zero();  // closest point of hull(a)
  Vec3 point_b = Vec3::Zero();  // closest point of hull(b)
  double distance = 0;          // |point_b - point_a|
  // The sets intersect (or come within a relative 1e-10 of touching); the
  // points and distance are then meaningless.
  bool overlap = false;
};

// a and b are non-empty and in one frame.
GjkResult gjk_distance(std::span<const Vec3> a, std::span<const Vec3> b);

}  // namespace tumble::physics
