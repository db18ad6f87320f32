// The contact points of two convex polyhedra meeting face to face: the
// incident face (of one shape) is clipped against the side planes of the
// reference face (of the other) by Sutherland-Hodgman (Ericson, "Real-Time
// Collision Detection" 8.3.4), the points below the reference face (or within
// the speculative distance above it) are kept, and more than four are
// reduced to four that span the largest area.
//
// Pure functions; thread-safe; no allocation.
#pragma once

#include <cstdint>

#include "tumble/physics/math.h"

namespace tumble::physics {

// A candidate point on the incident face with its separation from the
// reference face plane (negative below it) and a feature id.
struct ClipPoint {
  Vec3 point = Vec3::Zero();
  double separation = 0;
  std::uint32_t id = 0;
};

// Polygons larger than this are cut to their first kMaxClipPolygon vertices.
inline constexpr int kMaxClipPolygon = 64;

// reference: the reference face polygon, world frame, counter-clockwise
// about reference_normal (its outward normal; the reference face plane is
// reference_normal.dot(p) == reference_offset). incident: the incident face
// polygon, world frame, any orientation. Writes the clipped points whose
// separation is at most max_separation to out (capacity 2 kMaxClipPolygon)
// and returns their count. The id of a point names the two polygon edges
// (incident edges 0..127, reference side planes 128..255) whose lines cross
// there: (incoming << 8) | outgoing.
int clip_incident_face(const Vec3* reference, int reference_count, const Vec3& reference_normal,
                       double reference_offset, const Vec3* incident, int incident_count, double max_separation,
                       ClipPoint* out);

// Reorders points so the first min(count, 4) best describe the contact
// region and returns that number: the deepest point, the point furthest from
// it, the point making the largest triangle with them, and the point adding
// the most area outside that triangle (Gregorius, "Robust Contact Creation
// for Physics Simulations", GDC 2015). normal is the contact normal.
int reduce_to_four(ClipPoint* points, int count, const Vec3& normal);

}  // namespace tumble::physics
