// Shape: the collision geometry of a body, in its body frame (centred on the
// centre of mass). Only the description lives here; collision detection is a
// separate layer. More types (convex hulls, planes) are added as the
// collision layer grows.
#pragma once

#include <cstdint>

#include "physics/math.h"

namespace tumble::physics {

enum class ShapeType : std::uint8_t {
  none,     // point masses: the body has mass but no collision geometry
  sphere,   // uses radius
  box,      // uses half_extents, along the body axes
  capsule,  // uses radius and half_height; the segment runs along body y
};

// A plain description; fields that the type does not use are ignored.
// Lengths in metres.
struct Shape {
  ShapeType type = ShapeType::none;
  Vec3 half_extents = Vec3::Zero();
  double radius = 0;
  double half_height = 0;  // half the length of the capsule's inner segment
};

}  // namespace tumble::physics
