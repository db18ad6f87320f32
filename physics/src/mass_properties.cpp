#include "tumble/physics/mass_properties.h"

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <numbers>

#include "tumble/physics/convex_hull.h"

namespace tumble::physics {

MassProperties box_mass_properties(double mass, const Vec3& half_extents) {
  // Solid box of full extents a, b, c: I_xx = m/12 (b^2 + c^2); with half
  // extents (a = 2 hx, ...) that is m/3 (hy^2 + hz^2).
  const Vec3 h2 = half_extents.cwiseProduct(half_extents);
  MassProperties props;
  props.mass = mass;
  props.inertia.diagonal() = (mass / 3.0) * Vec3(h2.y() + h2.z(), h2.x() + h2.z(), h2.x() + h2.y());
  return props;
}

MassProperties sphere_mass_properties(double mass, double radius) {
  MassProperties props;
  props.mass = mass;
  props.inertia.diagonal().setConstant(0.4 * mass * radius * radius);  // 2/5 m r^2
  return props;
}

MassProperties capsule_mass_properties(double mass, double radius, double half_height) {
  constexpr double pi = std::numbers::pi;
  const double r = radius;
  const double r2 = r * r;
  const double height = 2.0 * half_height;  // H, length of the cylinder

  // Split the mass between the cylinder and the two hemispheres in
  // proportion to their volumes (one uniform density).
  const double cylinder_volume = pi * r2 * height;
  const double sphere_volume = (4.0 / 3.0) * pi * r2 * r;
  const double total_volume = cylinder_volume + sphere_volume;
  const double m_c = total_volume > 0 ? mass * cylinder_volume / total_volume : 0.0;
  const double m_s = mass - m_c;  // both hemispheres together

  // About the axis (y): a solid cylinder's m r^2 / 2 plus a solid sphere's
  // 2/5 m r^2 (the two hemispheres make one sphere for this axis).
  const double axial = m_c * r2 / 2.0 + m_s * 0.4 * r2;

  // About a transverse axis through the centre. Cylinder: m (H^2/12 + r^2/4).
  // Hemispheres: each has 2/5 m r^2 about a transverse axis through the
  // centre of its flat face and its centroid 3r/8 from that face, so by the
  // parallel-axis theorem, moving from the face to the centroid and then to
  // the capsule centre at distance H/2 + 3r/8:
  //   2/5 r^2 - (3r/8)^2 + (H/2 + 3r/8)^2 = 2/5 r^2 + H^2/4 + 3 H r / 8
  // per unit mass.
  const double transverse =
      m_c * (height * height / 12.0 + r2 / 4.0) + m_s * (0.4 * r2 + height * height / 4.0 + 3.0 * height * r / 8.0);

  MassProperties props;
  props.mass = mass;
  props.inertia.diagonal() = Vec3(transverse, axial, transverse);
  return props;
}

MassProperties convex_hull_mass_properties(const ConvexHull& hull, double mass) {
  if (hull.vertices.empty()) return MassProperties{};
  // A reference point near the middle keeps the products small.
  const Vec3 origin = 0.5 * (hull.local_min + hull.local_max);
  double volume = 0;
  Vec3 first_moment = Vec3::Zero();
  Mat3 covariance = Mat3::Zero();
  for (const ConvexHull::Face& face : hull.faces) {
    const Vec3 a = hull.vertices[hull.face_vertices[face.first]] - origin;
    for (std::uint32_t k = 1; k + 1 < face.count; ++k) {
      const Vec3 b = hull.vertices[hull.face_vertices[face.first + k]] - origin;
      const Vec3 c = hull.vertices[hull.face_vertices[face.first + k + 1]] - origin;
      // det[a b c] = a . (b x c): six times the signed volume, positive for a
      // counter-clockwise (outward) face seen from the reference point.
      const double det = a.dot(b.cross(c));
      const Vec3 sum = a + b + c;
      volume += det / 6.0;
      first_moment += (det / 24.0) * sum;  // volume times the centroid (a + b + c) / 4
      covariance += (det / 120.0) * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
    }
  }
  if (!(volume > 0)) return MassProperties{};
  const Vec3 center = first_moment / volume;
  const Mat3 central = covariance - volume * center * center.transpose();  // parallel-axis shift of the covariance
  const double density = mass / volume;
  MassProperties props;
  props.mass = mass;
  props.center = origin + center;
  props.inertia = density * (central.trace() * Mat3::Identity() - central);
  return props;
}

MassProperties point_mass_properties(std::span<const double> masses, std::span<const Vec3> positions) {
  assert(masses.size() == positions.size());
  const std::size_t n = masses.size() < positions.size() ? masses.size() : positions.size();

  MassProperties props;
  Vec3 first_moment = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    props.mass += masses[i];
    first_moment += masses[i] * positions[i];
  }
  if (props.mass <= 0) return MassProperties{};
  props.center = first_moment / props.mass;  // c = sum m_i r_i / M

  // Second pass about the centre rather than the parallel-axis shift
  // I_c = I_o - M ((c.c) 1 - c c^T), which loses digits when the set sits
  // far from the origin.
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 r = positions[i] - props.center;  // r' = r_i - c
    // Baraff, "The Inertia Tensor": m ((r'.r') 1 - r' r'^T).
    props.inertia += masses[i] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  return props;
}

}  // namespace tumble::physics
