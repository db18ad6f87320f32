// Box against box, and convex polyhedra (boxes and hulls) in general: the
// separating axis test, then face clipping or an edge-edge point.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "collide_pairs.h"
#include "face_clipping.h"
#include "segment.h"

namespace tumble::physics {
namespace {

// Face axes are preferred over edge axes, and A's faces over B's, unless the
// other separates by more than these (m, and a fraction of the depth), so
// the choice does not flicker between nearly equal axes from step to step
// (which would change the feature ids and lose the warm start).
constexpr double kEdgeTolerance = 1e-3;
constexpr double kFaceTolerance = 5e-4;
constexpr double kRelativeTolerance = 0.02;

bool prefer(double candidate, double incumbent, double tolerance) {
  return candidate > incumbent + tolerance + kRelativeTolerance * std::abs(incumbent);
}

constexpr std::uint32_t kFlipBit = 0x80000000u;

// Face contact: clips face inc_face of inc against face ref_face of ref.
// flip says that ref is shape B (the normal then points the other way).
void face_contact(const Polyhedron& ref, const Transform& tref, std::uint32_t ref_face, const Polyhedron& inc,
                  const Transform& tinc, std::uint32_t inc_face, bool flip, double max_separation, Manifold& m) {
  const ConvexHull::Face& rf = ref.faces[ref_face];
  const ConvexHull::Face& ifc = inc.faces[inc_face];
  const Vec3 normal = tref.rotation * rf.normal;
  const double offset = rf.offset + normal.dot(tref.position);
  Vec3 reference[kMaxClipPolygon];
  Vec3 incident[kMaxClipPolygon];
  const int rcount = static_cast<int>(std::min<std::uint32_t>(rf.count, kMaxClipPolygon));
  const int icount = static_cast<int>(std::min<std::uint32_t>(ifc.count, kMaxClipPolygon));
  for (int k = 0; k < rcount; ++k) reference[k] = tref.apply(ref.face_vertex(ref_face, static_cast<std::uint32_t>(k)));
  for (int k = 0; k < icount; ++k) incident[k] = tinc.apply(inc.face_vertex(inc_face, static_cast<std::uint32_t>(k)));

  ClipPoint points[2 * kMaxClipPolygon];
  int count = clip_incident_face(reference, rcount, normal, offset, incident, icount, max_separation, points);
  count = reduce_to_four(points, count, normal);

  const std::uint32_t faces = ((ref_face & 0x7fu) << 24) | ((inc_face & 0xffu) << 16) | (flip ? kFlipBit : 0u);
  m.normal = flip ? Vec3(-normal) : normal;
  m.point_count = count;
  for (int i = 0; i < count; ++i) {
    const Vec3 on_reference = points[i].point - points[i].separation * normal;
    ManifoldPoint& p = m.points[i];
    p.point_a = flip ? points[i].point : on_reference;
    p.point_b = flip ? on_reference : points[i].point;
    p.separation = points[i].separation;
    p.id = faces | (points[i].id & 0xffffu);
  }
}

// The face of poly (placed by t) whose world normal is most anti-parallel
// to normal.
std::uint32_t incident_face(const Polyhedron& poly, const Transform& t, const Vec3& normal) {
  const Vec3 local = t.rotation.transpose() * normal;
  std::uint32_t best = 0;
  double best_dot = std::numeric_limits<double>::infinity();
  for (std::uint32_t f = 0; f < poly.face_count; ++f) {
    const double d = poly.faces[f].normal.dot(local);
    if (d < best_dot) best_dot = d, best = f;
  }
  return best;
}

// One point at the closest points of edges a0a1 (on A) and b0b1 (on B).
void edge_contact(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, const Vec3& normal, std::uint32_t id,
                  Manifold& m) {
  Vec3 ca, cb;
  closest_points_of_segments(a0, a1, b0, b1, &ca, &cb);
  m.normal = normal;
  m.point_count = 1;
  m.points[0].point_a = ca;
  m.points[0].point_b = cb;
  m.points[0].separation = (cb - ca).dot(normal);
  m.points[0].id = id;
}

}  // namespace

void collide_boxes(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
                   Manifold& m) {
  m.point_count = 0;
  const Vec3& ha = a.half_extents;
  const Vec3& hb = b.half_extents;
  // Everything in A's frame: C holds B's axes as columns, t is B's centre
  // (Ericson 4.4.1).
  const Mat3 c = ta.rotation.transpose() * tb.rotation;
  const Vec3 t = ta.rotation.transpose() * (tb.position - ta.position);
  // The small term keeps near-parallel edge pairs (cross products near zero)
  // from reporting separation where there is none.
  const Mat3 abs_c = c.cwiseAbs().array() + 1e-12;

  // Face axes of A: |t_i| - (ha_i + sum_j hb_j |C_ij|).
  double sep_a = -std::numeric_limits<double>::infinity();
  int axis_a = 0;
  for (int i = 0; i < 3; ++i) {
    const double s = std::abs(t[i]) - (ha[i] + abs_c.row(i).dot(hb));
    if (s > max_separation) return;
    if (s > sep_a) sep_a = s, axis_a = i;
  }
  // Face axes of B: |t . C_j| - (sum_i ha_i |C_ij| + hb_j).
  double sep_b = -std::numeric_limits<double>::infinity();
  int axis_b = 0;
  for (int j = 0; j < 3; ++j) {
    const double s = std::abs(t.dot(c.col(j))) - (abs_c.col(j).dot(ha) + hb[j]);
    if (s > max_separation) return;
    if (s > sep_b) sep_b = s, axis_b = j;
  }
  // Edge axes A_i x B_j, divided by their length |A_i x B_j| = sqrt(1 - C_ij^2)
  // to get distances; near-parallel pairs are left to the face axes.
  double sep_edge = -std::numeric_limits<double>::infinity();
  int edge_i = 0, edge_j = 0;
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const double length = std::sqrt(std::max(0.0, 1.0 - c(i, j) * c(i, j)));
      if (length < 1e-5) continue;
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = ha[i1] * abs_c(i2, j) + ha[i2] * abs_c(i1, j);
      const double rb = hb[j1] * abs_c(i, j2) + hb[j2] * abs_c(i, j1);
      const double s = (std::abs(t[i2] * c(i1, j) - t[i1] * c(i2, j)) - ra - rb) / length;
      if (s > max_separation) return;
      if (s > sep_edge) sep_edge = s, edge_i = i, edge_j = j;
    }
  }

  const BoxPolyhedron box_a(ha), box_b(hb);
  const Polyhedron pa = box_a.view(), pb = box_b.view();
  const double sep_face = std::max(sep_a, sep_b);
  if (prefer(sep_edge, sep_face, kEdgeTolerance)) {
    // Edge against edge: the edge of A along axis i furthest along the
    // normal, the edge of B along axis j furthest against it.
    Vec3 n = Vec3::Unit(edge_i).cross(c.col(edge_j)).normalized();  // A's frame
    if (n.dot(t) < 0) n = -n;
    const Vec3 nb = c.transpose() * n;  // B's frame
    Vec3 mid_a = Vec3::Zero(), mid_b = Vec3::Zero();
    std::uint32_t signs = 0;
    for (int k = 0; k < 3; ++k) {
      if (k != edge_i) {
        mid_a[k] = n[k] >= 0 ? ha[k] : -ha[k];
        signs |= (n[k] >= 0 ? 1u : 0u) << k;
      }
      if (k != edge_j) {
        mid_b[k] = nb[k] >= 0 ? -hb[k] : hb[k];
        signs |= (nb[k] >= 0 ? 1u : 0u) << (k + 3);
      }
    }
    const Vec3 ea = ha[edge_i] * Vec3::Unit(edge_i);
    const Vec3 eb = hb[edge_j] * Vec3::Unit(edge_j);
    const std::uint32_t id = 0x40000000u | static_cast<std::uint32_t>(edge_i * 3 + edge_j) << 8 | signs;
    edge_contact(ta.apply(mid_a - ea), ta.apply(mid_a + ea), tb.apply(mid_b - eb), tb.apply(mid_b + eb),
                 ta.rotation * n, id, m);
    return;
  }
  if (prefer(sep_b, sep_a, kFaceTolerance)) {
    // B's face is the reference; its outward normal points towards A.
    const Vec3 t_in_b = c.transpose() * t;     // B's centre relative to A, in B's frame
    const bool positive = t_in_b[axis_b] < 0;  // A lies on B's +axis side
    const std::uint32_t ref_face = static_cast<std::uint32_t>(2 * axis_b + (positive ? 1 : 0));
    const Vec3 normal = tb.rotation * pb.faces[ref_face].normal;
    face_contact(pb, tb, ref_face, pa, ta, incident_face(pa, ta, normal), true, max_separation, m);
  } else {
    const bool positive = t[axis_a] >= 0;  // B lies on A's +axis side
    const std::uint32_t ref_face = static_cast<std::uint32_t>(2 * axis_a + (positive ? 1 : 0));
    const Vec3 normal = ta.rotation * pa.faces[ref_face].normal;
    face_contact(pa, ta, ref_face, pb, tb, incident_face(pb, tb, normal), false, max_separation, m);
  }
}

void collide_polyhedra(const Polyhedron& pa, const Transform& ta, const Polyhedron& pb, const Transform& tb,
                       double max_separation, Manifold& m) {
  m.point_count = 0;
  // Face axes of one polyhedron: the separation of the other's support point
  // in the direction against the face normal.
  auto face_query = [&](const Polyhedron& p, const Transform& tp, const Polyhedron& q, const Transform& tq,
                        std::uint32_t* best_face) {
    double best = -std::numeric_limits<double>::infinity();
    for (std::uint32_t f = 0; f < p.face_count; ++f) {
      const Vec3 n = tp.rotation * p.faces[f].normal;
      const double offset = p.faces[f].offset + n.dot(tp.position);
      const Vec3 v = tq.apply(q.vertices[q.support(-(tq.rotation.transpose() * n))]);
      const double s = n.dot(v) - offset;
      if (s > best) {
        best = s;
        *best_face = f;
        if (s > max_separation) break;
      }
    }
    return best;
  };
  std::uint32_t face_a = 0, face_b = 0;
  const double sep_a = face_query(pa, ta, pb, tb, &face_a);
  if (sep_a > max_separation) return;
  const double sep_b = face_query(pb, tb, pa, ta, &face_b);
  if (sep_b > max_separation) return;

  // Edge pairs. Only pairs whose Gauss-map arcs cross make a face of the
  // Minkowski difference and so a candidate axis (Gregorius 2013): with a, b
  // the normals of A's edge faces and c, d the negated normals of B's.
  double sep_edge = -std::numeric_limits<double>::infinity();
  std::uint32_t edge_a = 0, edge_b = 0;
  Vec3 edge_normal = Vec3::Zero();
  for (std::uint32_t i = 0; i < pa.edge_count; ++i) {
    const ConvexHull::Edge& ea = pa.edges[i];
    const Vec3 a0 = ta.apply(pa.vertices[ea.v0]);
    const Vec3 da = ta.apply(pa.vertices[ea.v1]) - a0;
    const Vec3 na = ta.rotation * pa.faces[ea.face0].normal;
    const Vec3 nb = ta.rotation * pa.faces[ea.face1].normal;
    const Vec3 b_x_a = nb.cross(na);
    for (std::uint32_t j = 0; j < pb.edge_count; ++j) {
      const ConvexHull::Edge& eb = pb.edges[j];
      const Vec3 nc = -(tb.rotation * pb.faces[eb.face0].normal);
      const Vec3 nd = -(tb.rotation * pb.faces[eb.face1].normal);
      const Vec3 d_x_c = nd.cross(nc);
      const double cba = nc.dot(b_x_a), dba = nd.dot(b_x_a);
      const double adc = na.dot(d_x_c), bdc = nb.dot(d_x_c);
      if (!(cba * dba < 0 && adc * bdc < 0 && cba * bdc > 0)) continue;
      const Vec3 b0 = tb.apply(pb.vertices[eb.v0]);
      const Vec3 db = tb.apply(pb.vertices[eb.v1]) - b0;
      Vec3 axis = da.cross(db);
      const double length = axis.norm();
      if (length <= 1e-6 * da.norm() * db.norm()) continue;  // parallel edges
      axis /= length;
      if (axis.dot(a0 - ta.position) < 0) axis = -axis;  // out of A
      const double s = axis.dot(b0 - a0);
      if (s > max_separation) return;
      if (s > sep_edge) sep_edge = s, edge_a = i, edge_b = j, edge_normal = axis;
    }
  }

  if (prefer(sep_edge, std::max(sep_a, sep_b), kEdgeTolerance)) {
    const ConvexHull::Edge& ea = pa.edges[edge_a];
    const ConvexHull::Edge& eb = pb.edges[edge_b];
    edge_contact(ta.apply(pa.vertices[ea.v0]), ta.apply(pa.vertices[ea.v1]), tb.apply(pb.vertices[eb.v0]),
                 tb.apply(pb.vertices[eb.v1]), edge_normal, 0x40000000u | (edge_a & 0x3fffu) << 14 | (edge_b & 0x3fffu),
                 m);
    return;
  }
  if (prefer(sep_b, sep_a, kFaceTolerance)) {
    const Vec3 normal = tb.rotation * pb.faces[face_b].normal;
    face_contact(pb, tb, face_b, pa, ta, incident_face(pa, ta, normal), true, max_separation, m);
  } else {
    const Vec3 normal = ta.rotation * pa.faces[face_a].normal;
    face_contact(pa, ta, face_a, pb, tb, incident_face(pb, tb, normal), false, max_separation, m);
  }
}

}  // namespace tumble::physics
