#include "gjk.h"

#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <limits>

namespace tumble::physics {
namespace {

// A vertex of the simplex in the Minkowski difference A - B: w = a - b.
struct SimplexVertex {
  Vec3 a;
  Vec3 b;
  Vec3 w;
  std::size_t index_a;
  std::size_t index_b;
};

struct Simplex {
  SimplexVertex v[4];
  double weight[4];  // barycentric coordinates of the closest point
  int count = 0;
};

std::size_t support(std::span<const Vec3> set, const Vec3& direction) {
  std::size_t best = 0;
  double best_dot = set[0].dot(direction);
  for (std::size_t i = 1; i < set.size(); ++i) {
    const double d = set[i].dot(direction);
    if (d > best_dot) best_dot = d, best = i;
  }
  return best;
}

// Keeps the listed vertices with the given weights.
void keep(Simplex& s, std::initializer_list<int> indices, std::initializer_list<double> weights) {
  SimplexVertex kept[4];
  double w[4];
  int n = 0;
  auto wi = weights.begin();
  for (int i : indices) {
    kept[n] = s.v[i];
    w[n] = *wi++;
    ++n;
  }
  for (int i = 0; i < n; ++i) s.v[i] = kept[i], s.weight[i] = w[i];
  s.count = n;
}

// Closest point to the origin on segment (0, 1) of the simplex, reducing the
// simplex to the vertices whose span holds it.
void solve_segment(Simplex& s) {
  const Vec3& a = s.v[0].w;
  const Vec3 ab = s.v[1].w - a;
  const double t = -a.dot(ab);
  if (t <= 0) return keep(s, {0}, {1.0});
  const double denom = ab.squaredNorm();
  if (t >= denom) return keep(s, {1}, {1.0});
  const double u = t / denom;
  keep(s, {0, 1}, {1.0 - u, u});
}

// Closest point to the origin on triangle (i0, i1, i2) of the simplex, by
// Voronoi regions (Ericson 5.1.5, ClosestPtPointTriangle, with p = 0).
void solve_triangle(Simplex& s, int i0, int i1, int i2) {
  const Vec3& a = s.v[i0].w;
  const Vec3& b = s.v[i1].w;
  const Vec3& c = s.v[i2].w;
  const Vec3 ab = b - a, ac = c - a, ap = -a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return keep(s, {i0}, {1.0});
  const Vec3 bp = -b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return keep(s, {i1}, {1.0});
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return keep(s, {i0, i1}, {1.0 - v, v});
  }
  const Vec3 cp = -c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return keep(s, {i2}, {1.0});
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return keep(s, {i0, i2}, {1.0 - w, w});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return keep(s, {i1, i2}, {1.0 - w, w});
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  keep(s, {i0, i1, i2}, {1.0 - v - w, v, w});
}

Vec3 closest_point(const Simplex& s) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < s.count; ++i) p += s.weight[i] * s.v[i].w;
  return p;
}

// Closest point to the origin on the tetrahedron (Ericson 5.1.6): the best
// of the faces the origin lies outside of. Returns false when the origin is
// inside (the sets overlap).
bool solve_tetrahedron(Simplex& s) {
  const Vec3 p[4] = {s.v[0].w, s.v[1].w, s.v[2].w, s.v[3].w};
  const double volume = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]));
  const double scale = (p[1] - p[0]).norm() * (p[2] - p[0]).norm() * (p[3] - p[0]).norm();
  const bool flat = std::abs(volume) <= 1e-12 * scale;
  // Face k leaves out vertex k.
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  Simplex best = s;
  double best_distance2 = std::numeric_limits<double>::infinity();
  bool outside_any = false;
  for (int k = 0; k < 4; ++k) {
    const int* f = kFaces[k];
    const Vec3 n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
    // The origin is outside face k when it lies on the other side of the
    // face's plane from vertex k.
    const double side_origin = -p[f[0]].dot(n);
    const double side_vertex = (p[k] - p[f[0]]).dot(n);
    if (!flat && side_origin * side_vertex >= 0) continue;
    outside_any = true;
    Simplex candidate = s;
    solve_triangle(candidate, f[0], f[1], f[2]);
    const double d2 = closest_point(candidate).squaredNorm();
    if (d2 < best_distance2) best_distance2 = d2, best = candidate;
  }
  if (!outside_any) return false;
  s = best;
  return true;
}

}  // namespace

GjkResult gjk_distance(std::span<const Vec3> a, std::span<const Vec3> b) {
  GjkResult result;
  Simplex s;
  s.v[0] = {a[0], b[0], a[0] - b[0], 0, 0};
  s.weight[0] = 1.0;
  s.count = 1;

  constexpr int kMaxIterations = 64;
  Vec3 v = s.v[0].w;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const double distance2 = v.squaredNorm();
    if (distance2 <= 1e-20 * (a[0].squaredNorm() + b[0].squaredNorm() + 1.0)) {
      result.overlap = true;
      return result;
    }
    // New support point of A - B in the direction -v.
    const std::size_t ia = support(a, -v);
    const std::size_t ib = support(b, v);
    const Vec3 w = a[ia] - b[ib];
    // No progress towards the origin: v is the closest point (the relative
    // gap test of van den Bergen 4.3.5).
    if (distance2 - v.dot(w) <= 1e-10 * distance2) break;
    bool repeated = false;
    for (int i = 0; i < s.count; ++i) repeated = repeated || (s.v[i].index_a == ia && s.v[i].index_b == ib);
    if (repeated) break;

    const Simplex previous = s;
    s.v[s.count] = {a[ia], b[ib], w, ia, ib};
    s.weight[s.count] = 0;
    ++s.count;
    switch (s.count) {
      case 2:
        solve_segment(s);
        break;
      case 3:
        solve_triangle(s, 0, 1, 2);
        break;
      default:
        if (!solve_tetrahedron(s)) {
          result.overlap = true;
          return result;
        }
        break;
    }
    const Vec3 next = closest_point(s);
    // The distance must shrink; stop when roundoff stalls it.
    if (next.squaredNorm() >= distance2) {
      s = previous;
      break;
    }
    v = next;
  }

  for (int i = 0; i < s.count; ++i) {
    result.point_a += s.weight[i] * s.v[i].a;
    result.point_b += s.weight[i] * s.v[i].b;
  }
  result.distance = (result.point_b - result.point_a).norm();
  return result;
}

}  // namespace tumble::physics
