// Narrowphase: the contact manifold of two shapes in given poses.
//
// Shapes are cores with a radius where that helps: a sphere is a point and a
// capsule a segment, each rounded by its radius; boxes and hulls are
// polyhedra. The pair functions (collide_pairs.h) are:
//   sphere-sphere, sphere-capsule, capsule-capsule: closest points of the
//     cores (two points for nearly parallel capsules);
//   sphere-box: closest point on the box (Ericson 5.1.3), or the nearest face
//     when the centre is inside;
//   sphere-hull, capsule-box, capsule-hull: GJK distance between the cores
//     (gjk.h); a capsule lying along a face is clipped to the face for two
//     points; cores that overlap fall back to the separating axis test;
//   box-box: the separating axis test over the 15 axes (Ericson 4.4.1,
//     Gottschalk's OBB test) then face clipping (face_clipping.h) or the
//     closest points of two edges;
//   box-hull, hull-hull: the separating axis test over face normals and the
//     edge pairs that form a face of the Minkowski difference (Gregorius,
//     "The Separating Axis Test between Convex Polyhedra", GDC 2013), then
//     face clipping or edge closest points;
//   any shape against a plane: the points of the shape below the plane.
//
// Points are reported while their separation is at most max_separation
// (speculative points), so fast bodies get contacts before they touch.
//
// Pure functions; thread-safe; no allocation.
#pragma once

#include "manifold.h"
#include "transform.h"
#include "tumble/physics/shape.h"

namespace tumble::physics {

// The order in which collide() pairs shape types: the pair functions take
// the lower one first (sphere, capsule, box, hull, plane, none). A contact
// that stores its bodies in this order gets its manifold without a swap.
int collide_order(ShapeType type);

// Fills manifold (normal from a towards b) for shapes a and b placed by
// their body-to-world transforms. Planes are static: a plane's transform
// places the plane given in its body frame. Two planes, or a shape of type
// none, make no points.
void collide(const Shape& a, const Transform& transform_a, const Shape& b, const Transform& transform_b,
             double max_separation, Manifold& manifold);

// The world-frame plane normal.dot(p) == offset of a plane shape placed by
// transform.
void world_plane(const Shape& plane, const Transform& transform, Vec3* normal, double* offset);

}  // namespace tumble::physics
