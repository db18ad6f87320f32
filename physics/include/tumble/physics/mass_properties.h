// Mass properties of rigid bodies: total mass, centre of mass and the inertia
// tensor about the centre of mass, following Baraff, "An Introduction to
// Physically Based Modeling: Rigid Body Simulation I" (SIGGRAPH course
// notes), sections "Center of Mass" and "The Inertia Tensor".
//
// The solid-shape functions assume uniform density and describe the shape
// centred on its centre of mass with its symmetry axes along the body axes,
// so their inertia tensors are diagonal and their centre is zero.
//
// Pure functions; thread-safe.
#pragma once

#include <span>

#include "tumble/physics/math.h"

namespace tumble::physics {

struct ConvexHull;

// Mass (kg), centre of mass (m) and inertia tensor about the centre of mass
// (kg m^2), in body axes.
struct MassProperties {
  double mass = 0;
  Vec3 center = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
};

// Solid box with the given half extents (hx, hy, hz):
// I_xx = m/3 (hy^2 + hz^2), I_yy = m/3 (hx^2 + hz^2), I_zz = m/3 (hx^2 + hy^2).
MassProperties box_mass_properties(double mass, const Vec3& half_extents);

// Solid sphere: I = 2/5 m r^2 about every axis.
MassProperties sphere_mass_properties(double mass, double radius);

// Solid capsule: a cylinder of length H = 2 half_height along body y, capped
// by two hemispheres of the same radius, all of one uniform density. With
// m_c the cylinder's and m_s both hemispheres' share of the mass (in
// proportion to the volumes pi r^2 H and 4/3 pi r^3):
//   I_yy = m_c r^2 / 2 + m_s 2/5 r^2
//   I_xx = I_zz = m_c (H^2/12 + r^2/4) + m_s (2/5 r^2 + H^2/4 + 3 H r / 8).
MassProperties capsule_mass_properties(double mass, double radius, double half_height);

// Solid convex hull of uniform density, by tetrahedral decomposition: each
// face is fanned into triangles (a, b, c) and each makes a tetrahedron with a
// reference point o. Relative to o, a tetrahedron has volume det[a b c] / 6
// and second moment (covariance) integral x x^T dV =
// det/120 (a a^T + b b^T + c c^T + (a+b+c)(a+b+c)^T) (Blow and Binstock,
// "How to find the inertia tensor (or other mass properties) of a 3D solid
// body represented by a triangle mesh", 2004). Summed over the tetrahedra,
// moved to the centre of mass c (C_c = C - V c c^T) and scaled by the
// density M / V, the inertia is I = tr(C_c) 1 - C_c. The result's center is
// the centre of mass in the hull's frame; it is not zero unless the hull was
// centred (translate_convex_hull).
MassProperties convex_hull_mass_properties(const ConvexHull& hull, double mass);

// A rigid set of point masses m_i at positions r_i (any frame; the result is
// in the same frame). Baraff's sums ("Center of Mass", "The Inertia Tensor"):
//   M = sum m_i,  c = sum m_i r_i / M,
//   I = sum m_i ((r'.r') 1 - r' r'^T)  with r' = r_i - c.
// masses and positions must have the same length. An empty set, or one of
// zero total mass, gives all zeros.
MassProperties point_mass_properties(std::span<const double> masses, std::span<const Vec3> positions);

}  // namespace tumble::physics
