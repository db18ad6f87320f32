// Closest points on line segments (Ericson, "Real-Time Collision Detection"
// 5.1.2 and 5.1.9). Inline pure functions.
#pragma once

#include <algorithm>

#include "tumble/physics/math.h"

namespace tumble::physics {

// Parameter t in [0, 1] of the point a + t (b - a) closest to p.
inline double closest_parameter_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 <= 0) return 0;
  return std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
}

inline Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  return a + closest_parameter_on_segment(p, a, b) * (b - a);
}

// Closest points c1 = p1 + s (q1 - p1) and c2 = p2 + t (q2 - p2) of the
// segments p1q1 and p2q2 (Ericson 5.1.9, ClosestPtSegmentSegment).
inline void closest_points_of_segments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, Vec3* c1,
                                       Vec3* c2) {
  const Vec3 d1 = q1 - p1;
  const Vec3 d2 = q2 - p2;
  const Vec3 r = p1 - p2;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  constexpr double kTiny = 1e-24;
  double s = 0, t = 0;
  if (a <= kTiny && e <= kTiny) {
    s = t = 0;
  } else if (a <= kTiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kTiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;  // >= 0; zero for parallel segments
      s = denom > kTiny * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  *c1 = p1 + s * d1;
  *c2 = p2 + t * d2;
}

}  // namespace tumble::physics
