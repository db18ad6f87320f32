#include "tumble/physics/shape.h"

#include <utility>

#include "tumble/physics/convex_hull.h"

namespace tumble::physics {

Shape sphere_shape(double radius) {
  Shape shape;
  shape.type = ShapeType::sphere;
  shape.radius = radius;
  return shape;
}

Shape box_shape(const Vec3& half_extents) {
  Shape shape;
  shape.type = ShapeType::box;
  shape.half_extents = half_extents;
  return shape;
}

Shape capsule_shape(double radius, double half_height) {
  Shape shape;
  shape.type = ShapeType::capsule;
  shape.radius = radius;
  shape.half_height = half_height;
  return shape;
}

Shape plane_shape(const Vec3& normal, double offset) {
  Shape shape;
  shape.type = ShapeType::plane;
  shape.plane_normal = normal;
  shape.plane_offset = offset;
  return shape;
}

Shape convex_hull_shape(std::shared_ptr<const ConvexHull> hull) {
  Shape shape;
  shape.type = ShapeType::convex_hull;
  shape.hull = std::move(hull);
  return shape;
}

}  // namespace tumble::physics
