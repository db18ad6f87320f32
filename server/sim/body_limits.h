// The physical ranges a body must lie within, and their checks: the one
// place that says how heavy, how large, how lopsided and how dense a body
// may be, and how far out and how fast it may be placed. Every path that
// makes or changes a body (scene file, SpawnBody, SetBodyState, the state
// file, a replay) goes through body_spec.h or request_check.h, which call
// these. docs/physics.md ("Body ranges") gives the table and the reasons.
//
// Inside these ranges the engine's step stays finite: the smallest masses
// and moments keep 1/M and 1/I far from overflow, the largest keep M g dt
// and the solver's impulses far from it, and the ratio bounds keep the
// contact solver converging. Errors name the field path and the range, e.g.
// "bodies[3].mass: 1e-40 kg is outside 1e-6 .. 1e9 kg".
//
// Pure functions; thread-safe.
#pragma once

#include <cmath>
#include <string>

#include "sim/status.h"
#include "tumble/physics/convex_hull.h"
#include "tumble/physics/mass_properties.h"
#include "tumble/v1/types.pb.h"

namespace tumble::sim {

// A closed range of one quantity, in the unit its messages print.
struct Range {
  double min;
  double max;
  const char* unit;

  bool contains(double value) const { return value >= min && value <= max; }  // false for NaN
};

// Mass of a dynamic body (the sum, for point masses).
inline constexpr Range kMassRange{1e-6, 1e9, "kg"};
// Each radius and half extent, a convex hull's thickness across each face
// and reach from its centre of mass, and a point mass's distance from the
// body's origin (its upper bound only). Static and kinematic bodies too.
inline constexpr Range kSizeRange{1e-3, 1e6, "m"};
// A capsule's half height: 0 (a sphere) up to the largest size.
inline constexpr Range kHalfHeightRange{0, 1e6, "m"};
// Each principal moment of inertia of a dynamic body, about its centre of mass.
inline constexpr Range kMomentRange{1e-14, 1e22, "kg m^2"};
// The largest principal moment over the smallest, of a dynamic body.
inline constexpr double kMaxMomentRatio = 1e6;
// Mass over volume of a dynamic body with a solid shape.
inline constexpr Range kDensityRange{1e-6, 3e10, "kg/m^3"};
// Largest magnitude of any coordinate (m), velocity (m/s, rad/s), force,
// torque or impulse a client or file may give; also the step's divergence
// guard (physics::WorldSettings::max_state_magnitude), so a body placed
// inside it is inside the world.
inline constexpr double kMaxMagnitude = 1e9;

// True when `value` is finite and at most kMaxMagnitude in magnitude.
inline bool within_limits(double value) { return std::isfinite(value) && std::abs(value) <= kMaxMagnitude; }

// A number as the messages print it: the shortest of up to 6 significant
// digits, exponents without '+' or leading zeros ("1e-40", "1e9", "0.5").
std::string format_number(double value);

// "PATH: VALUE UNIT is outside MIN .. MAX UNIT" unless range.contains(value).
Status check_range(double value, const Range& range, const std::string& path);

// Each component finite and at most kMaxMagnitude in magnitude; the error
// names the component, e.g. "body.position.x: 2e9 m is outside -1e9 .. 1e9 m".
Status check_magnitude(const tumble::v1::Vec3& v, const char* unit, const std::string& path);

// A dynamic body's mass properties, as computed from its shape and mass:
// principal moments within kMomentRange and their ratio within
// kMaxMomentRatio, and, when volume > 0 (m^3; 0 for point masses), its
// density within kDensityRange. `where` names the body, e.g. "bodies[3]".
Status check_mass_properties(const physics::MassProperties& props, double volume, const std::string& where);

// A convex hull's thickness across each face within kSizeRange, and each
// vertex within kSizeRange.max of the origin (the hull's centre of mass).
Status check_hull_size(const physics::ConvexHull& hull, const std::string& path);

// The volume of a convex hull (m^3).
double hull_volume(const physics::ConvexHull& hull);

}  // namespace tumble::sim
