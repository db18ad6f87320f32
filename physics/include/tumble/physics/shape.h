// Shape: the collision geometry of a body, in its body frame (centred on the
// centre of mass). Only the description lives here; collision detection is
// in collide.h.
#pragma once

#include <cstdint>
#include <memory>

#include "tumble/physics/math.h"

namespace tumble::physics {

struct ConvexHull;

enum class ShapeType : std::uint8_t {
  none,         // point masses: the body has mass but no collision geometry
  sphere,       // uses radius
  box,          // uses half_extents, along the body axes
  capsule,      // uses radius and half_height; the segment runs along body y
  convex_hull,  // uses hull (body frame, centred on the centre of mass)
  plane,        // uses plane_normal and plane_offset; static bodies only
};

// A plain description; fields that the type does not use are ignored.
// Lengths in metres. Copying a Shape shares its (immutable) hull.
struct Shape {
  ShapeType type = ShapeType::none;
  Vec3 half_extents = Vec3::Zero();
  double radius = 0;
  double half_height = 0;  // half the length of the capsule's inner segment

  // plane: the body-frame points p with plane_normal.dot(p) == plane_offset
  // lie on the plane; the solid half-space is plane_normal.dot(p) <
  // plane_offset. plane_normal must be a unit vector. With the body at the
  // origin and unrotated (the defaults of BodyDesc), this is the world plane.
  Vec3 plane_normal = Vec3::UnitY();
  double plane_offset = 0;

  // convex_hull: built by build_convex_hull (convex_hull.h).
  std::shared_ptr<const ConvexHull> hull;
};

Shape sphere_shape(double radius);
Shape box_shape(const Vec3& half_extents);
Shape capsule_shape(double radius, double half_height);
Shape plane_shape(const Vec3& normal, double offset);
Shape convex_hull_shape(std::shared_ptr<const ConvexHull> hull);

}  // namespace tumble::physics
