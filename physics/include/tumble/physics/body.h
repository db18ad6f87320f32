// Body handles and the description a body is created from.
#pragma once

#include <cstdint>

#include "tumble/physics/mass_properties.h"
#include "tumble/physics/math.h"
#include "tumble/physics/shape.h"

namespace tumble::physics {

// Stable handle to a body in a World. Ids are handed out in increasing order
// and never reused while the World lives, so a stale id is detectably
// unknown (World::contains) rather than silently naming another body.
using BodyId = std::uint32_t;
inline constexpr BodyId kInvalidBodyId = 0xffffffff;

// How a body moves. Static and kinematic bodies have infinite mass (inverse
// mass 0, zero inverse inertia): contacts never change their motion.
enum class MotionType : std::uint8_t {
  static_body,     // never moves (unless teleported with set_state); planes are always static
  kinematic_body,  // moves with the velocity it is given, pushes dynamic bodies, ignores forces
  dynamic_body,    // moved by gravity, forces, impulses and contacts
};

// Everything needed to create a body. The World copies what it needs; the
// description can be discarded after World::add_body.
struct BodyDesc {
  Shape shape;
  // Dynamic bodies: mass > 0 and inertia (about the centre of mass, body
  // axes) positive definite. mass_properties.center is ignored for the
  // state: position IS the centre of mass, and the shape is expected to be
  // centred on it. Ignored for static and kinematic bodies.
  MassProperties mass_properties;
  Vec3 position = Vec3::Zero();          // centre of mass, world frame (m)
  Quat orientation = Quat::Identity();   // body -> world, [w, x, y, z]; normalised on creation
  Vec3 linear_velocity = Vec3::Zero();   // world frame (m/s)
  Vec3 angular_velocity = Vec3::Zero();  // world frame (rad/s)

  MotionType motion_type = MotionType::dynamic_body;  // a plane shape forces static_body
  // Coulomb friction coefficient (>= 0) and coefficient of restitution
  // (0 = no bounce, 1 = elastic). A contact combines the two bodies' values
  // as friction sqrt(f_a f_b) and restitution max(e_a, e_b).
  double friction = 0.5;
  double restitution = 0;
};

}  // namespace tumble::physics
