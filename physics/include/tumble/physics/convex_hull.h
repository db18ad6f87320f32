// ConvexHull: a convex polyhedron as the collision code uses it, with
// polygonal faces (coplanar triangles merged, so a box-shaped hull has six
// quads and the face clipping of collide_polyhedra.cpp makes four-point
// manifolds), and the edge list with each edge's two faces (for the edge
// axes of the separating axis test).
//
// Built once from a point list and shared, immutable, between the Shapes
// that use it. Lengths in metres, in the hull's own (body) frame.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "tumble/physics/math.h"

namespace tumble::physics {

struct ConvexHull {
  // A planar convex polygon of the boundary.
  struct Face {
    Vec3 normal = Vec3::Zero();  // outward, unit
    double offset = 0;           // normal.dot(p) == offset on the face; the solid is below
    std::uint32_t first = 0;     // first entry in face_vertices
    std::uint32_t count = 0;     // >= 3; counter-clockwise seen from outside
  };
  // An edge between two faces. face0 walks it v0 -> v1, face1 walks v1 -> v0.
  struct Edge {
    std::uint32_t v0 = 0;
    std::uint32_t v1 = 0;
    std::uint32_t face0 = 0;
    std::uint32_t face1 = 0;
  };

  std::vector<Vec3> vertices;
  std::vector<Face> faces;
  std::vector<std::uint32_t> face_vertices;  // polygons of faces, indices into vertices
  std::vector<Edge> edges;
  double bounding_radius = 0;     // max |v| over the vertices: a sphere about the origin holding the hull
  Vec3 local_min = Vec3::Zero();  // bounding box of the vertices
  Vec3 local_max = Vec3::Zero();

  // Index of a vertex furthest along direction (the first such in index
  // order).
  std::uint32_t support(const Vec3& direction) const;
};

// The convex hull of points by incremental construction (Ericson, "Real-Time
// Collision Detection" 12.4.2; the horizon of the faces a new point sees is
// replaced by a fan to that point), then coplanar triangles merged into
// polygons. Points closer than a relative tolerance (1e-9 of the extent) to
// the hull surface do not become vertices. Returns nullptr when the points
// span no volume (fewer than four, or all coplanar). The hull stays in the
// points' frame; see translate_convex_hull to centre it on its centre of
// mass.
std::shared_ptr<const ConvexHull> build_convex_hull(std::span<const Vec3> points);

// A copy of hull with every vertex moved by offset.
std::shared_ptr<const ConvexHull> translate_convex_hull(const ConvexHull& hull, const Vec3& offset);

}  // namespace tumble::physics
