#include "polyhedron.h"

namespace tumble::physics {

// Listed counter-clockwise seen from outside: for face +x, (v3 - v1) x (v7 - v1)
// points along +x, and likewise for the others.
const std::uint32_t BoxPolyhedron::kFaceVertices[24] = {
    0, 4, 6, 2,  // -x
    1, 3, 7, 5,  // +x
    0, 1, 5, 4,  // -y
    2, 6, 7, 3,  // +y
    0, 2, 3, 1,  // -z
    4, 5, 7, 6,  // +z
};

// Each edge with the face that walks it v0 -> v1 and the face that walks it
// back (read off kFaceVertices).
const ConvexHull::Edge BoxPolyhedron::kEdges[12] = {
    {0, 4, 0, 2}, {4, 6, 0, 5}, {6, 2, 0, 3}, {2, 0, 0, 4},  // edges of face -x
    {1, 3, 1, 4}, {3, 7, 1, 3}, {7, 5, 1, 5}, {5, 1, 1, 2},  // edges of face +x
    {0, 1, 2, 4}, {5, 4, 2, 5},                              // -y with -z, +z
    {6, 7, 3, 5}, {3, 2, 3, 4},                              // +y with +z, -z
};

BoxPolyhedron::BoxPolyhedron(const Vec3& h) {
  for (int i = 0; i < 8; ++i) {
    vertices[i] = Vec3((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  }
  for (int k = 0; k < 3; ++k) {
    for (int s = 0; s < 2; ++s) {
      ConvexHull::Face& face = faces[2 * k + s];
      face.normal = Vec3::Zero();
      face.normal[k] = s ? 1.0 : -1.0;
      face.offset = h[k];
      face.first = static_cast<std::uint32_t>(4 * (2 * k + s));
      face.count = 4;
    }
  }
}

Polyhedron BoxPolyhedron::view() const {
  Polyhedron p;
  p.vertices = vertices;
  p.vertex_count = 8;
  p.faces = faces;
  p.face_count = 6;
  p.face_vertices = kFaceVertices;
  p.edges = kEdges;
  p.edge_count = 12;
  return p;
}

Polyhedron polyhedron_of(const ConvexHull& hull) {
  Polyhedron p;
  p.vertices = hull.vertices.data();
  p.vertex_count = static_cast<std::uint32_t>(hull.vertices.size());
  p.faces = hull.faces.data();
  p.face_count = static_cast<std::uint32_t>(hull.faces.size());
  p.face_vertices = hull.face_vertices.data();
  p.edges = hull.edges.data();
  p.edge_count = static_cast<std::uint32_t>(hull.edges.size());
  return p;
}

}  // namespace tumble::physics
