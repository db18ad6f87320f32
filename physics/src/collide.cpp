#include "collide.h"

#include <utility>

#include "collide_pairs.h"
#include "tumble/physics/convex_hull.h"

namespace tumble::physics {
namespace {

// Pairs in collide_order: collide_order(a) <= collide_order(b).
void collide_ordered(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
                     Manifold& m) {
  m.point_count = 0;
  if (b.type == ShapeType::plane) {
    if (a.type == ShapeType::plane) return;
    Vec3 normal;
    double offset;
    world_plane(b, tb, &normal, &offset);
    collide_plane(a, ta, normal, offset, max_separation, m);
    return;
  }
  switch (a.type) {
    case ShapeType::sphere:
      switch (b.type) {
        case ShapeType::sphere:
          return collide_spheres(a, ta, b, tb, max_separation, m);
        case ShapeType::capsule:
          return collide_sphere_capsule(a, ta, b, tb, max_separation, m);
        case ShapeType::box:
          return collide_sphere_box(a, ta, b, tb, max_separation, m);
        case ShapeType::convex_hull:
          return collide_sphere_hull(a, ta, b, tb, max_separation, m);
        default:
          return;
      }
    case ShapeType::capsule:
      switch (b.type) {
        case ShapeType::capsule:
          return collide_capsules(a, ta, b, tb, max_separation, m);
        case ShapeType::box: {
          const BoxPolyhedron box(b.half_extents);
          return collide_capsule_polyhedron(a, ta, box.view(), tb, max_separation, m);
        }
        case ShapeType::convex_hull:
          return collide_capsule_polyhedron(a, ta, polyhedron_of(*b.hull), tb, max_separation, m);
        default:
          return;
      }
    case ShapeType::box:
      switch (b.type) {
        case ShapeType::box:
          return collide_boxes(a, ta, b, tb, max_separation, m);
        case ShapeType::convex_hull: {
          const BoxPolyhedron box(a.half_extents);
          return collide_polyhedra(box.view(), ta, polyhedron_of(*b.hull), tb, max_separation, m);
        }
        default:
          return;
      }
    case ShapeType::convex_hull:
      if (b.type == ShapeType::convex_hull) {
        return collide_polyhedra(polyhedron_of(*a.hull), ta, polyhedron_of(*b.hull), tb, max_separation, m);
      }
      return;
    default:
      return;
  }
}

}  // namespace

int collide_order(ShapeType type) {
  switch (type) {
    case ShapeType::sphere:
      return 0;
    case ShapeType::capsule:
      return 1;
    case ShapeType::box:
      return 2;
    case ShapeType::convex_hull:
      return 3;
    case ShapeType::plane:
      return 4;
    case ShapeType::none:
      return 5;
  }
  return 5;
}

void world_plane(const Shape& plane, const Transform& transform, Vec3* normal, double* offset) {
  // n_local . x_local = d with x_local = R^T (x - p) gives (R n) . x = d + (R n) . p.
  *normal = transform.rotation * plane.plane_normal;
  *offset = plane.plane_offset + normal->dot(transform.position);
}

void collide(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
             Manifold& m) {
  if (collide_order(a.type) <= collide_order(b.type)) return collide_ordered(a, ta, b, tb, max_separation, m);
  collide_ordered(b, tb, a, ta, max_separation, m);
  m.normal = -m.normal;
  for (int i = 0; i < m.point_count; ++i) std::swap(m.points[i].point_a, m.points[i].point_b);
}

}  // namespace tumble::physics
