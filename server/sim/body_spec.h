// Turns a tumble.v1.BodySpec (from a scene file or a client) into the
// physics engine's BodyDesc, checking that it describes a real body: a name
// within the limits of string_limits.h; mass, sizes, moments of inertia,
// density, position and velocities within the ranges of body_limits.h; a
// unit orientation, friction >= 0 and restitution in [0, 1]. Planes must be
// static and point masses dynamic;
// static and kinematic bodies need no mass. A convex shape is re-centred on
// its centre of mass.
#pragma once

#include <string>

#include "sim/body_limits.h"
#include "sim/status.h"
#include "tumble/physics/body.h"
#include "tumble/v1/scene.pb.h"

namespace tumble::sim {

// Most points accepted for a convex shape: the hull is built in O(n^2) at
// load time, and a bigger cloud is surely a mesh sent by mistake.
inline constexpr int kMaxConvexPoints = 4096;

// Fills `desc` from `spec`. `where` names the body in errors, e.g.
// "bodies[3]"; messages name the offending field below it.
Status body_desc_from_spec(const tumble::v1::BodySpec& spec, const std::string& where, physics::BodyDesc* desc);

// The wire's name for how a body moves.
tumble::v1::Motion wire_motion(physics::MotionType type);

}  // namespace tumble::sim
