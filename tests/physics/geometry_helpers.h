// Small builders for the narrowphase, hull and GJK tests: poses, the corner
// sets of boxes, prisms and regular solids, hulls centred on their centre of mass,
// random rotations, point-to-surface distances of boxes and hulls, hulls
// leaning into a surface, and a manifold's deepest point. Header-only.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include "manifold.h"
#include "transform.h"
#include "tumble/physics/convex_hull.h"
#include "tumble/physics/mass_properties.h"
#include "tumble/physics/math.h"

namespace tumble::physics::testing {

inline constexpr double kPi = std::numbers::pi;

// WorldSettings::contact_margin's default: how far apart two shapes already
// make contact points.
inline constexpr double kContactMargin = 0.02;

inline Transform pose(const Vec3& position, const Quat& orientation = Quat::Identity()) {
  return Transform{position, orientation.normalized().toRotationMatrix()};
}

inline Quat rotation_about(const Vec3& axis, double angle) { return Quat(Eigen::AngleAxisd(angle, axis.normalized())); }

// The eight corners (+-hx, +-hy, +-hz).
inline std::vector<Vec3> box_corners(const Vec3& half_extents) {
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back((i & 1) ? half_extents.x() : -half_extents.x(), (i & 2) ? half_extents.y() : -half_extents.y(),
                         (i & 4) ? half_extents.z() : -half_extents.z());
  }
  return corners;
}

// A regular tetrahedron of edge length edge with its centroid at the origin
// and one face on the plane y = -edge sqrt(2/3) / 4, facing -y. Its height
// is edge sqrt(2/3); the centroid sits a quarter of it above the base.
inline std::vector<Vec3> regular_tetrahedron(double edge) {
  const double height = edge * std::sqrt(2.0 / 3.0);
  const double base_radius = edge / std::sqrt(3.0);  // circumradius of the base triangle
  const double base_y = -0.25 * height;
  std::vector<Vec3> points;
  for (int k = 0; k < 3; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / 3.0;
    points.emplace_back(base_radius * std::cos(angle), base_y, base_radius * std::sin(angle));
  }
  points.emplace_back(0.0, 0.75 * height, 0.0);
  return points;
}

// A regular octahedron with vertices at distance r along each axis.
inline std::vector<Vec3> regular_octahedron(double r) {
  return {Vec3(r, 0, 0), Vec3(-r, 0, 0), Vec3(0, r, 0), Vec3(0, -r, 0), Vec3(0, 0, r), Vec3(0, 0, -r)};
}

// The vertices of a prism over a regular polygon of `sides` sides and
// circumradius `radius`, from y = -half_height to y = half_height.
inline std::vector<Vec3> polygon_prism(int sides, double radius, double half_height) {
  std::vector<Vec3> points;
  for (int i = 0; i < sides; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / sides;
    points.emplace_back(radius * std::cos(angle), -half_height, radius * std::sin(angle));
    points.emplace_back(radius * std::cos(angle), half_height, radius * std::sin(angle));
  }
  return points;
}

// The hull of points moved so its centre of mass is at the origin, as a body
// shape wants it.
inline std::shared_ptr<const ConvexHull> centred_hull(std::span<const Vec3> points) {
  const std::shared_ptr<const ConvexHull> hull = build_convex_hull(points);
  if (!hull) return nullptr;
  const MassProperties props = convex_hull_mass_properties(*hull, 1.0);
  return translate_convex_hull(*hull, -props.center);
}

// A rotation drawn uniformly from SO(3) (Shoemake's subgroup algorithm).
inline Quat random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double u1 = unit(rng), u2 = unit(rng), u3 = unit(rng);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  return Quat(a * std::sin(2 * std::numbers::pi * u2), a * std::cos(2 * std::numbers::pi * u2),
              b * std::sin(2 * std::numbers::pi * u3), b * std::cos(2 * std::numbers::pi * u3))
      .normalized();
}

inline Vec3 random_vector(std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> d(lo, hi);
  return Vec3(d(rng), d(rng), d(rng));
}

// How far a body-frame point lies outside the box along its worst axis,
// max_k (|p_k| - h_k): zero on the surface, negative inside (the depth
// below the nearest face), positive outside.
inline double box_surface_height(const Vec3& local, const Vec3& half_extents) {
  return (local.cwiseAbs() - half_extents).maxCoeff();
}

// The same for a hull: the largest height above a face plane, max over the
// faces of n.p - offset.
inline double hull_surface_height(const Vec3& local, const ConvexHull& hull) {
  double height = -INFINITY;
  for (const ConvexHull::Face& face : hull.faces) height = std::max(height, face.normal.dot(local) - face.offset);
  return height;
}

// A hull tilted by `tilt` rad about a horizontal axis, and sunk so that its
// lowest vertex is `depth` m below the plane y = 0.
struct Lean {
  Transform pose;
  double direction = 0;  // rad about +y: the tilt axis is (cos, 0, sin) of it
};

// The hull leaning each of `directions` ways, evenly spread around +y.
inline std::vector<Lean> leaning_poses(const ConvexHull& hull, double tilt, double depth, int directions = 36) {
  std::vector<Lean> leans;
  for (int i = 0; i < directions; ++i) {
    const double phi = 2.0 * std::numbers::pi * i / directions;
    Transform t = pose(Vec3::Zero(), rotation_about(Vec3(std::cos(phi), 0.0, std::sin(phi)), tilt));
    double lowest = INFINITY;
    for (const Vec3& v : hull.vertices) lowest = std::min(lowest, t.apply(v).y());
    t.position.y() = -lowest - depth;
    leans.push_back(Lean{t, phi});
  }
  return leans;
}

// The smallest separation of a manifold's points (the deepest
// penetration, negative); infinity when it has none.
inline double deepest_separation(const Manifold& m) {
  double deepest = INFINITY;
  for (int k = 0; k < m.point_count; ++k) deepest = std::min(deepest, m.points[k].separation);
  return deepest;
}

}  // namespace tumble::physics::testing
