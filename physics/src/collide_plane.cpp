// Any shape against a plane: the points of the shape within max_separation of
// the plane (or below it), reduced to four.
#include <cstdint>

#include "collide_pairs.h"
#include "face_clipping.h"
#include "tumble/physics/convex_hull.h"

namespace tumble::physics {
namespace {

// Adds a vertex v of A at height h above the plane to the candidates. Once
// they are full, a deeper vertex takes the place of the shallowest one, so
// the deepest vertices are kept whatever their order.
void add_candidate(const Vec3& v, double h, std::uint32_t id, double max_separation, ClipPoint* out, int* count,
                   int capacity) {
  if (h > max_separation) return;
  if (*count < capacity) {
    out[(*count)++] = {v, h, id};
    return;
  }
  int shallowest = 0;
  for (int i = 1; i < capacity; ++i) {
    if (out[i].separation > out[shallowest].separation) shallowest = i;
  }
  if (h < out[shallowest].separation) out[shallowest] = {v, h, id};
}

}  // namespace

void collide_plane(const Shape& a, const Transform& ta, const Vec3& normal, double offset, double max_separation,
                   Manifold& m) {
  m.point_count = 0;
  constexpr int kCapacity = 2 * kMaxClipPolygon;
  ClipPoint candidates[kCapacity];
  int count = 0;
  double radius = 0;  // rounded cores: the candidates are core points
  switch (a.type) {
    case ShapeType::sphere:
      radius = a.radius;
      add_candidate(ta.position, normal.dot(ta.position) - offset - radius, 0, max_separation, candidates, &count,
                    kCapacity);
      break;
    case ShapeType::capsule: {
      radius = a.radius;
      const Vec3 axis = a.half_height * ta.rotation.col(1);
      for (std::uint32_t e = 0; e < 2; ++e) {
        const Vec3 p = e == 0 ? Vec3(ta.position - axis) : Vec3(ta.position + axis);
        add_candidate(p, normal.dot(p) - offset - radius, e, max_separation, candidates, &count, kCapacity);
      }
      break;
    }
    case ShapeType::box: {
      // Heights of the eight corners from the centre's height and the
      // normal in the box frame.
      const Vec3 local = ta.rotation.transpose() * normal;
      const Vec3 reach = a.half_extents.cwiseProduct(local);
      const double center = normal.dot(ta.position) - offset;
      for (std::uint32_t i = 0; i < 8; ++i) {
        const Vec3 corner((i & 1) ? a.half_extents.x() : -a.half_extents.x(),
                          (i & 2) ? a.half_extents.y() : -a.half_extents.y(),
                          (i & 4) ? a.half_extents.z() : -a.half_extents.z());
        const double h = center + ((i & 1) ? reach.x() : -reach.x()) + ((i & 2) ? reach.y() : -reach.y()) +
                         ((i & 4) ? reach.z() : -reach.z());
        if (h <= max_separation) add_candidate(ta.apply(corner), h, i, max_separation, candidates, &count, kCapacity);
      }
      break;
    }
    case ShapeType::convex_hull: {
      const ConvexHull& hull = *a.hull;
      const Vec3 local = ta.rotation.transpose() * normal;
      const double center = normal.dot(ta.position) - offset;
      for (std::uint32_t i = 0; i < hull.vertices.size(); ++i) {
        const double h = center + local.dot(hull.vertices[i]);
        if (h <= max_separation) {
          add_candidate(ta.apply(hull.vertices[i]), h, i, max_separation, candidates, &count, kCapacity);
        }
      }
      break;
    }
    case ShapeType::none:
    case ShapeType::plane:
      return;
  }
  count = reduce_to_four(candidates, count, normal);
  m.normal = -normal;  // from the shape (A) into the plane (B)
  m.point_count = count;
  for (int i = 0; i < count; ++i) {
    // Height of the core point above the plane, before the radius.
    const double core_height = candidates[i].separation + radius;
    ManifoldPoint& p = m.points[i];
    p.point_a = candidates[i].point - radius * normal;
    p.point_b = candidates[i].point - core_height * normal;
    p.separation = candidates[i].separation;
    p.id = candidates[i].id;
  }
}

}  // namespace tumble::physics
