#include "tumble/physics/convex_hull.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <tuple>
#include <utility>

namespace tumble::physics {
namespace {

// A triangle of the hull under construction, counter-clockwise from outside.
struct Triangle {
  std::uint32_t v[3];
  Vec3 normal;
  double offset;
  bool alive;
};

Triangle make_triangle(const std::vector<Vec3>& points, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  Triangle t{{a, b, c}, Vec3::Zero(), 0.0, true};
  const Vec3 n = (points[b] - points[a]).cross(points[c] - points[a]);
  const double length = n.norm();
  t.normal = length > 0 ? Vec3(n / length) : Vec3::Zero();
  t.offset = t.normal.dot(points[a]);
  return t;
}

// Distance of point p from the line through a and b.
double distance_to_line(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  return (p - a).cross(d).norm() / d.norm();
}

// The convex polygon, counter-clockwise about normal, of the given points of
// one plane: Andrew's monotone chain in the plane's 2D coordinates. Points
// inside the polygon or on its edges (within tolerance) are dropped.
std::vector<std::uint32_t> planar_hull(const std::vector<Vec3>& points, std::vector<std::uint32_t> ids,
                                       const Vec3& normal, double tolerance) {
  // An orthonormal basis (u, w) of the plane with u x w = normal.
  const Vec3 u = (std::abs(normal.x()) < 0.57 ? Vec3::UnitX() : Vec3::UnitY()).cross(normal).normalized();
  const Vec3 w = normal.cross(u);
  auto coord = [&](std::uint32_t i) { return std::pair<double, double>(points[i].dot(u), points[i].dot(w)); };
  std::sort(ids.begin(), ids.end(), [&](std::uint32_t a, std::uint32_t b) {
    const auto pa = coord(a);
    const auto pb = coord(b);
    return pa != pb ? pa < pb : a < b;
  });
  // cross > tolerance * |o->a| * |o->b| keeps strict left turns only.
  auto left_turn = [&](std::uint32_t o, std::uint32_t a, std::uint32_t b) {
    const auto po = coord(o);
    const auto pa = coord(a);
    const auto pb = coord(b);
    const double ax = pa.first - po.first, ay = pa.second - po.second;
    const double bx = pb.first - po.first, by = pb.second - po.second;
    return ax * by - ay * bx > tolerance * std::sqrt((ax * ax + ay * ay) * (bx * bx + by * by));
  };
  std::vector<std::uint32_t> hull(2 * ids.size());
  std::size_t k = 0;
  for (std::uint32_t id : ids) {
    while (k >= 2 && !left_turn(hull[k - 2], hull[k - 1], id)) --k;
    hull[k++] = id;
  }
  for (std::size_t i = ids.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && !left_turn(hull[k - 2], hull[k - 1], ids[i])) --k;
    hull[k++] = ids[i];
  }
  hull.resize(k > 0 ? k - 1 : 0);  // the last point repeats the first
  return hull;
}

void finish_bounds(ConvexHull& hull) {
  hull.bounding_radius = 0;
  hull.local_min = Vec3::Constant(std::numeric_limits<double>::infinity());
  hull.local_max = -hull.local_min;
  for (const Vec3& v : hull.vertices) {
    hull.bounding_radius = std::max(hull.bounding_radius, v.norm());
    hull.local_min = hull.local_min.cwiseMin(v);
    hull.local_max = hull.local_max.cwiseMax(v);
  }
}

}  // namespace

std::uint32_t ConvexHull::support(const Vec3& direction) const {
  std::uint32_t best = 0;
  double best_dot = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const double d = vertices[i].dot(direction);
    if (d > best_dot) {
      best_dot = d;
      best = static_cast<std::uint32_t>(i);
    }
  }
  return best;
}

std::shared_ptr<const ConvexHull> build_convex_hull(std::span<const Vec3> input) {
  const std::vector<Vec3> points(input.begin(), input.end());
  const std::size_t n = points.size();
  if (n < 4) return nullptr;

  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double scale = (hi - lo).maxCoeff();
  if (!(scale > 0) || !std::isfinite(scale)) return nullptr;
  const double eps = 1e-9 * std::max(scale, (hi.cwiseAbs().cwiseMax(lo.cwiseAbs())).maxCoeff());

  // Initial tetrahedron: the extreme points along the widest axis, the
  // point furthest from their line, the point furthest from their plane.
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  std::uint32_t i0 = 0, i1 = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (points[i][axis] < points[i0][axis]) i0 = i;
    if (points[i][axis] > points[i1][axis]) i1 = i;
  }
  std::uint32_t i2 = i0;
  double best = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double d = distance_to_line(points[i], points[i0], points[i1]);
    if (d > best) best = d, i2 = i;
  }
  if (best <= eps) return nullptr;
  const Vec3 base_normal = (points[i1] - points[i0]).cross(points[i2] - points[i0]).normalized();
  std::uint32_t i3 = i0;
  best = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double d = std::abs(base_normal.dot(points[i] - points[i0]));
    if (d > best) best = d, i3 = i;
  }
  if (best <= eps) return nullptr;

  std::vector<Triangle> triangles;
  const Vec3 inside = 0.25 * (points[i0] + points[i1] + points[i2] + points[i3]);
  auto add_oriented = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    Triangle t = make_triangle(points, a, b, c);
    if (t.normal.dot(inside) > t.offset) t = make_triangle(points, a, c, b);  // face the interior away
    triangles.push_back(t);
  };
  add_oriented(i0, i1, i2);
  add_oriented(i0, i1, i3);
  add_oriented(i0, i2, i3);
  add_oriented(i1, i2, i3);

  // Add the points one at a time. A point in front of some faces (by more
  // than eps) replaces them with a fan from the horizon, the boundary of the
  // visible region: the directed edges of visible faces whose reverse edge
  // belongs to no visible face.
  std::vector<std::size_t> visible;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> visible_edges;
  for (std::uint32_t p = 0; p < n; ++p) {
    if (p == i0 || p == i1 || p == i2 || p == i3) continue;
    visible.clear();
    for (std::size_t f = 0; f < triangles.size(); ++f) {
      if (triangles[f].alive && triangles[f].normal.dot(points[p]) - triangles[f].offset > eps) visible.push_back(f);
    }
    if (visible.empty()) continue;
    visible_edges.clear();
    for (std::size_t f : visible) {
      const Triangle& t = triangles[f];
      for (int k = 0; k < 3; ++k) visible_edges.emplace_back(t.v[k], t.v[(k + 1) % 3]);
    }
    for (std::size_t f : visible) triangles[f].alive = false;
    for (const auto& edge : visible_edges) {
      const bool interior = std::find(visible_edges.begin(), visible_edges.end(),
                                      std::make_pair(edge.second, edge.first)) != visible_edges.end();
      if (!interior) triangles.push_back(make_triangle(points, edge.first, edge.second, p));
    }
  }

  // Merge coplanar triangles: group by plane, then take the planar convex
  // hull of each group's vertices as the face polygon.
  struct PlaneGroup {
    Vec3 normal;  // area-weighted sum of the triangle normals
    double offset;
    std::vector<std::uint32_t> ids;
  };
  std::vector<PlaneGroup> groups;
  for (const Triangle& t : triangles) {
    if (!t.alive || t.normal.isZero()) continue;
    const double area = (points[t.v[1]] - points[t.v[0]]).cross(points[t.v[2]] - points[t.v[0]]).norm();
    PlaneGroup* group = nullptr;
    for (PlaneGroup& g : groups) {
      const Vec3 gn = g.normal.normalized();
      if (gn.dot(t.normal) > 1.0 - 1e-10 && std::abs(gn.dot(points[t.v[0]]) - g.offset) <= 4 * eps) {
        group = &g;
        break;
      }
    }
    if (group == nullptr) {
      groups.push_back({Vec3::Zero(), t.offset, {}});
      group = &groups.back();
    }
    group->normal += area * t.normal;
    for (std::uint32_t v : t.v) {
      if (std::find(group->ids.begin(), group->ids.end(), v) == group->ids.end()) group->ids.push_back(v);
    }
  }

  auto hull = std::make_shared<ConvexHull>();
  std::vector<std::uint32_t> remap(n, 0xffffffffu);
  for (const PlaneGroup& g : groups) {
    const Vec3 normal = g.normal.normalized();
    const std::vector<std::uint32_t> polygon = planar_hull(points, g.ids, normal, 1e-9);
    if (polygon.size() < 3) continue;
    ConvexHull::Face face;
    face.normal = normal;
    face.first = static_cast<std::uint32_t>(hull->face_vertices.size());
    face.count = static_cast<std::uint32_t>(polygon.size());
    face.offset = -std::numeric_limits<double>::infinity();
    for (std::uint32_t v : polygon) {
      if (remap[v] == 0xffffffffu) {
        remap[v] = static_cast<std::uint32_t>(hull->vertices.size());
        hull->vertices.push_back(points[v]);
      }
      hull->face_vertices.push_back(remap[v]);
      face.offset = std::max(face.offset, normal.dot(points[v]));
    }
    hull->faces.push_back(face);
  }

  // Edges: every directed polygon edge, paired with its reverse.
  struct HalfEdge {
    std::uint32_t lo, hi, face;
    bool forward;  // walks lo -> hi
  };
  std::vector<HalfEdge> half_edges;
  for (std::uint32_t f = 0; f < hull->faces.size(); ++f) {
    const ConvexHull::Face& face = hull->faces[f];
    for (std::uint32_t k = 0; k < face.count; ++k) {
      const std::uint32_t a = hull->face_vertices[face.first + k];
      const std::uint32_t b = hull->face_vertices[face.first + (k + 1) % face.count];
      half_edges.push_back({std::min(a, b), std::max(a, b), f, a < b});
    }
  }
  std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return std::tie(x.lo, x.hi, x.forward) < std::tie(y.lo, y.hi, y.forward);
  });
  if (half_edges.size() % 2 != 0) return nullptr;
  for (std::size_t i = 0; i < half_edges.size(); i += 2) {
    const HalfEdge& back = half_edges[i];       // forward == false: walks hi -> lo
    const HalfEdge& front = half_edges[i + 1];  // forward == true
    if (back.lo != front.lo || back.hi != front.hi || back.forward || !front.forward) return nullptr;
    hull->edges.push_back({front.lo, front.hi, front.face, back.face});
  }
  // Euler's formula for a convex polyhedron: V - E + F = 2.
  if (hull->vertices.size() + hull->faces.size() != hull->edges.size() + 2) return nullptr;

  finish_bounds(*hull);
  return hull;
}

std::shared_ptr<const ConvexHull> translate_convex_hull(const ConvexHull& hull, const Vec3& offset) {
  auto moved = std::make_shared<ConvexHull>(hull);
  for (Vec3& v : moved->vertices) v += offset;
  for (ConvexHull::Face& face : moved->faces) face.offset += face.normal.dot(offset);
  finish_bounds(*moved);
  return moved;
}

}  // namespace tumble::physics
