// Capsule against capsule, box and hull.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "collide_pairs.h"
#include "gjk.h"
#include "segment.h"

namespace tumble::physics {
namespace {

// Capsules whose axes make an angle with sine below this are treated as
// parallel and get two points, so one lying on another does not rock.
constexpr double kParallelSine = 0.05;
// A capsule lying along a face gets two points when the core-to-face normal
// is within this cosine of the face normal.
constexpr double kFaceAlignedCosine = 0.999;

void segment_of(const Shape& capsule, const Transform& t, Vec3* p0, Vec3* p1) {
  const Vec3 axis = capsule.half_height * t.rotation.col(1);
  *p0 = t.position - axis;
  *p1 = t.position + axis;
}

// Clips segment s0 s1 (parameters [0, 1]) to the prism over face f of the
// polyhedron (inside every side plane). Returns false if nothing is left.
bool clip_segment_to_face(const Polyhedron& poly, std::uint32_t f, const Vec3& s0, const Vec3& s1, double* t0,
                          double* t1) {
  const ConvexHull::Face& face = poly.faces[f];
  *t0 = 0;
  *t1 = 1;
  for (std::uint32_t k = 0; k < face.count; ++k) {
    const Vec3& a = poly.face_vertex(f, k);
    const Vec3& b = poly.face_vertex(f, (k + 1) % face.count);
    const Vec3 side = (b - a).cross(face.normal);  // outward from the polygon
    const double d0 = side.dot(s0 - a);
    const double d1 = side.dot(s1 - a);
    if (d0 > 0 && d1 > 0) return false;
    if (d0 > 0) *t0 = std::max(*t0, d0 / (d0 - d1));
    if (d1 > 0) *t1 = std::min(*t1, d0 / (d0 - d1));
  }
  return *t0 <= *t1;
}

// Points of the segment s0 s1 (polyhedron frame, radius r) over face f,
// with the face normal as the contact normal. Returns false when the
// segment does not lie over the face.
bool capsule_on_face(const Polyhedron& poly, std::uint32_t f, const Vec3& s0, const Vec3& s1, double r,
                     const Transform& tb, double max_separation, Manifold& m) {
  double t0, t1;
  if (!clip_segment_to_face(poly, f, s0, s1, &t0, &t1)) return false;
  const ConvexHull::Face& face = poly.faces[f];
  const int ends = t1 - t0 > 1e-9 ? 2 : 1;
  m.point_count = 0;
  for (int e = 0; e < ends; ++e) {
    const Vec3 q = s0 + (e == 0 ? t0 : t1) * (s1 - s0);
    const double height = face.normal.dot(q) - face.offset;  // of the core point above the face
    const double separation = height - r;
    if (separation > max_separation) continue;
    ManifoldPoint& p = m.points[m.point_count++];
    p.point_a = tb.apply(q - r * face.normal);
    p.point_b = tb.apply(q - height * face.normal);
    p.separation = separation;
    p.id = (f << 8) | static_cast<std::uint32_t>(e);
  }
  m.normal = -(tb.rotation * face.normal);  // from the capsule (A) into the polyhedron (B)
  return true;
}

}  // namespace

void collide_capsules(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
                      Manifold& m) {
  m.point_count = 0;
  Vec3 p0, p1, q0, q1;
  segment_of(a, ta, &p0, &p1);
  segment_of(b, tb, &q0, &q1);
  Vec3 c1, c2;
  closest_points_of_segments(p0, p1, q0, q1, &c1, &c2);
  const double ra = a.radius, rb = b.radius;
  const Vec3 d = c2 - c1;
  const double distance = d.norm();
  if (distance - ra - rb > max_separation) return;
  Vec3 n;
  if (distance > 1e-12) {
    n = d / distance;
  } else {
    // Crossing axes: any direction perpendicular to both.
    const Vec3 cross = (p1 - p0).cross(q1 - q0);
    n = cross.norm() > 1e-12 ? Vec3(cross.normalized()) : Vec3::UnitY();
    if (n.dot(tb.position - ta.position) < 0) n = -n;
  }
  m.normal = n;

  const Vec3 da = p1 - p0, db = q1 - q0;
  const double la2 = da.squaredNorm(), lb2 = db.squaredNorm();
  if (la2 > 0 && lb2 > 0 && da.cross(db).squaredNorm() <= kParallelSine * kParallelSine * la2 * lb2) {
    // Nearly parallel: the overlap of B's projection onto A's segment.
    const double u0 = std::clamp((q0 - p0).dot(da) / la2, 0.0, 1.0);
    const double u1 = std::clamp((q1 - p0).dot(da) / la2, 0.0, 1.0);
    const double lo = std::min(u0, u1), hi = std::max(u0, u1);
    if (hi - lo > 1e-9) {
      for (int e = 0; e < 2; ++e) {
        const Vec3 ca = p0 + (e == 0 ? lo : hi) * da;
        const Vec3 cb = closest_point_on_segment(ca, q0, q1);
        const double separation = (cb - ca).dot(n) - ra - rb;
        if (separation > max_separation) continue;
        ManifoldPoint& p = m.points[m.point_count++];
        p.point_a = ca + ra * n;
        p.point_b = cb - rb * n;
        p.separation = separation;
        p.id = static_cast<std::uint32_t>(e);
      }
      return;
    }
  }
  ManifoldPoint& p = m.points[0];
  p.point_a = c1 + ra * n;
  p.point_b = c2 - rb * n;
  p.separation = distance - ra - rb;
  p.id = 2;
  m.point_count = 1;
}

void collide_capsule_polyhedron(const Shape& a, const Transform& ta, const Polyhedron& poly, const Transform& tb,
                                double max_separation, Manifold& m) {
  m.point_count = 0;
  const double r = a.radius;
  Vec3 w0, w1;
  segment_of(a, ta, &w0, &w1);
  const Vec3 core[2] = {tb.apply_inverse(w0), tb.apply_inverse(w1)};  // polyhedron frame
  const Vec3& s0 = core[0];
  const Vec3& s1 = core[1];
  const GjkResult g = gjk_distance(core, {poly.vertices, poly.vertex_count});

  if (!g.overlap && g.distance > 1e-9) {
    if (g.distance - r > max_separation) return;
    const Vec3 n = (g.point_b - g.point_a) / g.distance;  // from the core towards the polyhedron
    // The face the core faces; if the normal is that face's, the capsule may
    // lie along it: clip for two points.
    std::uint32_t face = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t f = 0; f < poly.face_count; ++f) {
      const double d = poly.faces[f].normal.dot(n);
      if (d < best) best = d, face = f;
    }
    if (-best > kFaceAlignedCosine && capsule_on_face(poly, face, s0, s1, r, tb, max_separation, m)) return;
    m.point_count = 0;
    m.normal = tb.rotation * n;
    ManifoldPoint& p = m.points[0];
    p.point_a = tb.apply(g.point_a + r * n);
    p.point_b = tb.apply(g.point_b);
    p.separation = g.distance - r;
    p.id = 0x10000;
    m.point_count = 1;
    return;
  }

  // The core reaches inside: separating axes over the faces and the
  // crossings of the core with each edge. Axes point out of the polyhedron.
  Vec3 center = Vec3::Zero();
  for (std::uint32_t i = 0; i < poly.vertex_count; ++i) center += poly.vertices[i];
  center /= poly.vertex_count;
  double best_face = -std::numeric_limits<double>::infinity();
  std::uint32_t face = 0;
  for (std::uint32_t f = 0; f < poly.face_count; ++f) {
    const ConvexHull::Face& fc = poly.faces[f];
    const double separation = std::min(fc.normal.dot(s0), fc.normal.dot(s1)) - fc.offset - r;
    if (separation > best_face) best_face = separation, face = f;
  }
  double best_edge = -std::numeric_limits<double>::infinity();
  std::uint32_t edge = 0;
  Vec3 edge_axis = Vec3::Zero();
  const Vec3 dir = s1 - s0;
  for (std::uint32_t e = 0; e < poly.edge_count; ++e) {
    const Vec3& v0 = poly.vertices[poly.edges[e].v0];
    const Vec3& v1 = poly.vertices[poly.edges[e].v1];
    Vec3 axis = dir.cross(v1 - v0);
    const double length = axis.norm();
    if (length <= 1e-9 * dir.norm() * (v1 - v0).norm()) continue;
    axis /= length;
    if (axis.dot(v0 - center) < 0) axis = -axis;
    const double separation = std::min(axis.dot(s0), axis.dot(s1)) - axis.dot(poly.vertices[poly.support(axis)]) - r;
    if (separation > best_edge) best_edge = separation, edge = e, edge_axis = axis;
  }
  if (std::max(best_face, best_edge) > max_separation) return;
  if (best_edge <= best_face + 1e-3 && capsule_on_face(poly, face, s0, s1, r, tb, max_separation, m)) return;
  m.point_count = 0;
  if (best_edge == -std::numeric_limits<double>::infinity()) {
    // No edge axis (a degenerate core): push out through the best face.
    const ConvexHull::Face& fc = poly.faces[face];
    const Vec3 q = fc.normal.dot(s0) < fc.normal.dot(s1) ? s0 : s1;
    const double height = fc.normal.dot(q) - fc.offset;
    m.normal = -(tb.rotation * fc.normal);
    ManifoldPoint& p = m.points[0];
    p.point_a = tb.apply(q - r * fc.normal);
    p.point_b = tb.apply(q - height * fc.normal);
    p.separation = height - r;
    p.id = 0x20000;
    m.point_count = 1;
    return;
  }
  Vec3 c1, c2;
  closest_points_of_segments(s0, s1, poly.vertices[poly.edges[edge].v0], poly.vertices[poly.edges[edge].v1], &c1, &c2);
  m.normal = -(tb.rotation * edge_axis);
  ManifoldPoint& p = m.points[0];
  p.point_a = tb.apply(c1 - r * edge_axis);
  p.point_b = tb.apply(c2);
  p.separation = (p.point_b - p.point_a).dot(m.normal);
  p.id = 0x30000 | edge;
  m.point_count = 1;
}

}  // namespace tumble::physics
