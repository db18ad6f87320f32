#include "face_clipping.h"

#include <algorithm>
#include <utility>

namespace tumble::physics {
namespace {

// A polygon vertex and the label of the line of the polygon edge leaving it.
struct LabelledVertex {
  Vec3 point;
  std::uint32_t label;
};

}  // namespace

int clip_incident_face(const Vec3* reference, int reference_count, const Vec3& reference_normal,
                       double reference_offset, const Vec3* incident, int incident_count, double max_separation,
                       ClipPoint* out) {
  reference_count = std::min(reference_count, kMaxClipPolygon);
  incident_count = std::min(incident_count, kMaxClipPolygon);
  LabelledVertex buffers[2][2 * kMaxClipPolygon];
  LabelledVertex* polygon = buffers[0];
  LabelledVertex* clipped = buffers[1];
  int count = incident_count;
  for (int i = 0; i < incident_count; ++i) polygon[i] = {incident[i], static_cast<std::uint32_t>(i & 127)};

  for (int k = 0; k < reference_count && count > 0; ++k) {
    const Vec3& a = reference[k];
    const Vec3& b = reference[(k + 1) % reference_count];
    // Side plane through edge a -> b, normal pointing out of the polygon
    // (edge x normal for a counter-clockwise polygon).
    const Vec3 side = (b - a).cross(reference_normal);
    const double side_offset = side.dot(a);
    const std::uint32_t plane_label = 128u + static_cast<std::uint32_t>(k & 127);
    int n = 0;
    for (int i = 0; i < count; ++i) {
      const LabelledVertex& p = polygon[(i + count - 1) % count];  // start of the edge
      const LabelledVertex& q = polygon[i];                        // end of the edge
      const std::uint32_t edge_label = p.label;
      const double dp = side.dot(p.point) - side_offset;
      const double dq = side.dot(q.point) - side_offset;
      if (dp <= 0 && dq <= 0) {
        clipped[n++] = q;
      } else if (dp <= 0) {
        // Leaving: the new vertex continues along the side plane.
        clipped[n++] = {p.point + (dp / (dp - dq)) * (q.point - p.point), plane_label};
      } else if (dq <= 0) {
        // Entering: the new vertex continues along the incident edge.
        clipped[n++] = {p.point + (dp / (dp - dq)) * (q.point - p.point), edge_label};
        clipped[n++] = q;
      }
    }
    std::swap(polygon, clipped);
    count = n;
  }

  int written = 0;
  for (int i = 0; i < count; ++i) {
    const double separation = reference_normal.dot(polygon[i].point) - reference_offset;
    if (separation > max_separation) continue;
    const std::uint32_t incoming = polygon[(i + count - 1) % count].label;
    out[written++] = {polygon[i].point, separation, (incoming << 8) | polygon[i].label};
  }
  return written;
}

int reduce_to_four(ClipPoint* points, int count, const Vec3& normal) {
  if (count <= 4) return count;
  auto take = [&](int slot, int index) { std::swap(points[slot], points[index]); };

  int deepest = 0;
  for (int i = 1; i < count; ++i) {
    if (points[i].separation < points[deepest].separation) deepest = i;
  }
  take(0, deepest);
  const Vec3 p0 = points[0].point;

  int far = 1;
  for (int i = 2; i < count; ++i) {
    if ((points[i].point - p0).squaredNorm() > (points[far].point - p0).squaredNorm()) far = i;
  }
  take(1, far);
  const Vec3 p1 = points[1].point;

  // Signed area (twice) of triangle (a, b, c) seen along normal.
  auto area = [&](const Vec3& a, const Vec3& b, const Vec3& c) { return (b - a).cross(c - a).dot(normal); };
  int third = 2;
  for (int i = 3; i < count; ++i) {
    if (std::abs(area(p0, p1, points[i].point)) > std::abs(area(p0, p1, points[third].point))) third = i;
  }
  take(2, third);
  if (area(p0, p1, points[2].point) < 0) std::swap(points[1], points[2]);  // make (0, 1, 2) counter-clockwise
  const Vec3 a = points[0].point, b = points[1].point, c = points[2].point;

  // The fourth point lies furthest outside one edge of the triangle.
  int fourth = -1;
  double most_outside = 0;
  for (int i = 3; i < count; ++i) {
    const Vec3& p = points[i].point;
    const double outside = std::min({area(a, b, p), area(b, c, p), area(c, a, p)});
    if (outside < most_outside) most_outside = outside, fourth = i;
  }
  if (fourth < 0) return 3;
  take(3, fourth);
  return 4;
}

}  // namespace tumble::physics
