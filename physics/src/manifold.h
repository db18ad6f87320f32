// Manifold: the contact points the narrowphase finds between two shapes,
// all sharing one normal. Plain data.
#pragma once

#include <cstdint>

#include "tumble/physics/math.h"

namespace tumble::physics {

// Up to four points describe a convex contact region (a face resting on a
// face: the corners of the overlap, reduced to four).
inline constexpr int kMaxManifoldPoints = 4;

struct ManifoldPoint {
  Vec3 point_a = Vec3::Zero();  // on the surface of A, world frame (m)
  Vec3 point_b = Vec3::Zero();  // on the surface of B, world frame (m)
  // (point_b - point_a).dot(normal): negative when the shapes overlap (m).
  // A positive separation is a speculative point: not yet touching, but close
  // enough to touch within the step.
  double separation = 0;
  // Names the pair of features (vertex, edge, face) that made the point, so
  // the same point found again next step is recognised and its impulses are
  // carried over (warm starting).
  std::uint32_t id = 0;
};

struct Manifold {
  Vec3 normal = Vec3::UnitY();  // unit, world frame, from A towards B
  ManifoldPoint points[kMaxManifoldPoints];
  int point_count = 0;
};

}  // namespace tumble::physics
