// Polyhedron: a read-only view of a convex polyhedron's topology in its body
// frame, so boxes and convex hulls share one separating-axis and clipping
// path. BoxPolyhedron builds the view of a box on the stack.
#pragma once

#include <cstdint>

#include "tumble/physics/convex_hull.h"
#include "tumble/physics/math.h"

namespace tumble::physics {

struct Polyhedron {
  const Vec3* vertices = nullptr;
  std::uint32_t vertex_count = 0;
  const ConvexHull::Face* faces = nullptr;
  std::uint32_t face_count = 0;
  const std::uint32_t* face_vertices = nullptr;
  const ConvexHull::Edge* edges = nullptr;
  std::uint32_t edge_count = 0;

  std::uint32_t support(const Vec3& direction) const {
    std::uint32_t best = 0;
    double best_dot = vertices[0].dot(direction);
    for (std::uint32_t i = 1; i < vertex_count; ++i) {
      const double d = vertices[i].dot(direction);
      if (d > best_dot) best_dot = d, best = i;
    }
    return best;
  }
  const Vec3& face_vertex(std::uint32_t face, std::uint32_t k) const {
    return vertices[face_vertices[faces[face].first + k]];
  }
};

Polyhedron polyhedron_of(const ConvexHull& hull);

// A box as a polyhedron. Vertex i has coordinates (+-hx, +-hy, +-hz) with the
// sign of axis k positive when bit k of i is set. Face 2k + s has outward
// normal -e_k for s = 0 and +e_k for s = 1.
struct BoxPolyhedron {
  Vec3 vertices[8];
  ConvexHull::Face faces[6];

  explicit BoxPolyhedron(const Vec3& half_extents);
  Polyhedron view() const;

  // The face polygons (four vertices each, counter-clockwise from outside)
  // and the twelve edges, shared by every box.
  static const std::uint32_t kFaceVertices[24];
  static const ConvexHull::Edge kEdges[12];
};

}  // namespace tumble::physics
