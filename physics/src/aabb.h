// Axis-aligned bounding boxes in the world frame (m). Plain value type.
#pragma once

#include "tumble/physics/math.h"

namespace tumble::physics {

struct Aabb {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();

  bool overlaps(const Aabb& other) const {
    return min.x() <= other.max.x() && other.min.x() <= max.x() && min.y() <= other.max.y() &&
           other.min.y() <= max.y() && min.z() <= other.max.z() && other.min.z() <= max.z();
  }

  bool contains(const Aabb& inner) const {
    return min.x() <= inner.min.x() && min.y() <= inner.min.y() && min.z() <= inner.min.z() &&
           inner.max.x() <= max.x() && inner.max.y() <= max.y() && inner.max.z() <= max.z();
  }

  // Half the surface area: the cost measure of the tree's surface area
  // heuristic, where only ratios matter.
  double half_area() const {
    const Vec3 d = max - min;
    return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
  }

  Aabb expanded(double margin) const { return {min.array() - margin, max.array() + margin}; }
};

inline Aabb merge(const Aabb& a, const Aabb& b) { return {a.min.cwiseMin(b.min), a.max.cwiseMax(b.max)}; }

}  // namespace tumble::physics
