// The pair functions behind collide() (collide.h), one per pair of shape
// kinds, in the order sphere < capsule < box < hull < plane: the first shape
// is never later in that order than the second. Each clears the manifold
// first. Internal to the physics library.
#pragma once

#include "manifold.h"
#include "polyhedron.h"
#include "transform.h"
#include "tumble/physics/shape.h"

namespace tumble::physics {

void collide_spheres(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
                     Manifold& m);
void collide_sphere_capsule(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                            double max_separation, Manifold& m);
void collide_sphere_box(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
                        Manifold& m);
void collide_sphere_hull(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                         double max_separation, Manifold& m);
void collide_capsules(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
                      Manifold& m);
void collide_capsule_polyhedron(const Shape& a, const Transform& ta, const Polyhedron& b, const Transform& tb,
                                double max_separation, Manifold& m);
void collide_boxes(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double max_separation,
                   Manifold& m);
void collide_polyhedra(const Polyhedron& a, const Transform& ta, const Polyhedron& b, const Transform& tb,
                       double max_separation, Manifold& m);
// a against the world plane normal.dot(p) == offset (b is the plane).
void collide_plane(const Shape& a, const Transform& ta, const Vec3& normal, double offset, double max_separation,
                   Manifold& m);

}  // namespace tumble::physics
