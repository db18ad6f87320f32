// Sphere against sphere, capsule, box and hull.
#include <cmath>
#include <cstdint>
#include <limits>

#include "collide_pairs.h"
#include "gjk.h"
#include "segment.h"
#include "tumble/physics/convex_hull.h"

namespace tumble::physics {
namespace {

// Two rounded points: centres ca, cb with radii ra, rb. The normal runs
// along the centre line; coincident centres take +y.
void collide_points(const Vec3& ca, double ra, const Vec3& cb, double rb, double max_separation, Manifold& m) {
  const Vec3 d = cb - ca;
  const double reach = ra + rb + max_separation;
  const double distance2 = d.squaredNorm();
  if (distance2 > reach * reach) return;
  const double distance = std::sqrt(distance2);
  const Vec3 n = distance > 1e-12 ? Vec3(d / distance) : Vec3::UnitY();
  m.normal = n;
  ManifoldPoint& p = m.points[0];
  p.point_a = ca + ra * n;
  p.point_b = cb - rb * n;
  p.separation = distance - ra - rb;
  p.id = 0;
  m.point_count = 1;
}

}  // namespace

void collide_spheres(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
                     Manifold& m) {
  m.point_count = 0;
  collide_points(ta.position, a.radius, tb.position, b.radius, max_separation, m);
}

void collide_sphere_capsule(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                            double max_separation, Manifold& m) {
  m.point_count = 0;
  const Vec3 axis = b.half_height * tb.rotation.col(1);
  const Vec3 q = closest_point_on_segment(ta.position, tb.position - axis, tb.position + axis);
  collide_points(ta.position, a.radius, q, b.radius, max_separation, m);
}

void collide_sphere_box(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
                        Manifold& m) {
  m.point_count = 0;
  const Vec3& h = b.half_extents;
  const double r = a.radius;
  const Vec3 c = tb.apply_inverse(ta.position);  // sphere centre in the box frame
  const Vec3 q = c.cwiseMax(-h).cwiseMin(h);     // closest point of the box (Ericson 5.1.3)
  Vec3 outward;                                  // unit, box frame, from the box towards the centre
  Vec3 surface;                                  // point of the box surface, box frame
  double separation;
  if (q != c) {
    const Vec3 d = c - q;
    const double distance = d.norm();
    separation = distance - r;
    if (separation > max_separation) return;
    outward = d / distance;
    surface = q;
  } else {
    // Centre inside: leave through the nearest face.
    const Vec3 depth = h - c.cwiseAbs();
    int k = 0;
    depth.minCoeff(&k);
    const double sign = c[k] >= 0 ? 1.0 : -1.0;
    outward = Vec3::Zero();
    outward[k] = sign;
    surface = c;
    surface[k] = sign * h[k];
    separation = -depth[k] - r;
  }
  const Vec3 n = -(tb.rotation * outward);  // from the sphere (A) to the box (B)
  m.normal = n;
  ManifoldPoint& p = m.points[0];
  p.point_a = ta.position + r * n;
  p.point_b = tb.apply(surface);
  p.separation = separation;
  p.id = 0;
  m.point_count = 1;
}

void collide_sphere_hull(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                         double max_separation, Manifold& m) {
  m.point_count = 0;
  const ConvexHull& hull = *b.hull;
  const double r = a.radius;
  const Vec3 c = tb.apply_inverse(ta.position);  // hull frame
  const GjkResult g = gjk_distance({&c, 1}, hull.vertices);
  Vec3 n;  // hull frame, from the sphere to the hull
  Vec3 surface;
  double separation;
  if (!g.overlap && g.distance > 1e-9) {
    separation = g.distance - r;
    if (separation > max_separation) return;
    n = (g.point_b - c) / g.distance;
    surface = g.point_b;
  } else {
    // Centre inside: leave through the face of least penetration.
    std::uint32_t best = 0;
    double best_height = -std::numeric_limits<double>::infinity();
    for (std::uint32_t f = 0; f < hull.faces.size(); ++f) {
      const double height = hull.faces[f].normal.dot(c) - hull.faces[f].offset;
      if (height > best_height) best_height = height, best = f;
    }
    n = -hull.faces[best].normal;
    surface = c + best_height * n;
    separation = best_height - r;
  }
  m.normal = tb.rotation * n;
  ManifoldPoint& p = m.points[0];
  p.point_a = ta.position + r * m.normal;
  p.point_b = tb.apply(surface);
  p.separation = separation;
  p.id = 0;
  m.point_count = 1;
}

}  // namespace tumble::physics
