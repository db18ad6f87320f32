#include "wide_constraint.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "rotation.h"

namespace tumble::physics {

Softness make_softness(double hertz, double damping_ratio, double h) {
  Softness s;
  if (hertz <= 0) return s;
  const double omega = 2.0 * std::numbers::pi * hertz;
  const double a1 = 2.0 * damping_ratio + h * omega;
  const double a2 = h * omega * a1;
  const double a3 = 1.0 / (1.0 + a2);
  s.bias_rate = omega / a1;
  s.mass_scale = a2 * a3;
  s.impulse_scale = a3;
  return s;
}
namespace {

// An orthonormal basis (t1, t2) of the plane normal to unit n, continuous
// except at n.z = 0 crossings (Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 2017).
void tangent_basis(const Vec3& n, Vec3* t1, Vec3* t2) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double b = n.x() * n.y() * a;
  *t1 = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  *t2 = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

}  // namespace

void build_lane(const WideRowInputs& in, const ContactConstraint& c, const Contact& contact, int lane,
                WideConstraint& w, WidePoint* points) {
  const Manifold& m = contact.manifold;
  const ContactSolverBodies& bodies = in.bodies;
  const double inverse_mass_a = bodies.inverse_mass[c.body_a];
  const double inverse_mass_b = bodies.inverse_mass[c.body_b];
  w.inverse_mass_a[lane] = static_cast<float>(inverse_mass_a);
  w.inverse_mass_b[lane] = static_cast<float>(inverse_mass_b);
  // Mixing rules: friction is the geometric mean, so a frictionless body
  // slides on anything; restitution the maximum, so a bouncy body bounces
  // on anything (as Box2D).
  w.friction[lane] = static_cast<float>(std::sqrt(bodies.friction[c.body_a] * bodies.friction[c.body_b]));
  w.restitution[lane] = static_cast<float>(std::max(bodies.restitution[c.body_a], bodies.restitution[c.body_b]));
  // A body of infinite mass gets the stiffer push.
  const Softness& softness = inverse_mass_a == 0 || inverse_mass_b == 0 ? in.static_soft : in.soft;
  w.bias_rate[lane] = static_cast<float>(softness.bias_rate);
  w.mass_scale[lane] = static_cast<float>(softness.mass_scale);
  w.impulse_scale[lane] = static_cast<float>(softness.impulse_scale);

  const Vec3& normal = m.normal;
  const SolverVelocity& va = in.velocities[c.body_a];
  const SolverVelocity& vb = in.velocities[c.body_b];
  const Vec3& xa = bodies.transforms[c.body_a].position;
  const Vec3& xb = bodies.transforms[c.body_b].position;
  // Friction directions: the first along the sliding velocity at the
  // manifold's centre when there is one, so a sliding body's friction stays
  // opposite to its motion; otherwise a fixed basis.
  Vec3 tangent1, tangent2;
  {
    Vec3 center = Vec3::Zero();
    for (int k = 0; k < m.point_count; ++k) center += m.points[k].point_a + m.points[k].point_b;
    center /= 2.0 * m.point_count;
    Vec3 slip = vb.linear + vb.angular.cross(center - xb) - va.linear - va.angular.cross(center - xa);
    slip -= slip.dot(normal) * normal;
    const double slip_speed = slip.norm();
    if (slip_speed > 1e-3) {
      tangent1 = slip / slip_speed;
      tangent2 = normal.cross(tangent1);
    } else {
      tangent_basis(normal, &tangent1, &tangent2);
    }
  }
  set_lane(w.normal, lane, normal);
  set_lane(w.tangent1, lane, tangent1);
  set_lane(w.tangent2, lane, tangent2);

  // Rows. A static body, or a kinematic one, has a zero inverse inertia, so
  // its response and its share of the effective mass are zero.
  const Mat3& inertia_a = bodies.inverse_inertia[c.body_a];
  const Mat3& inertia_b = bodies.inverse_inertia[c.body_b];
  // I^-1 j: an isotropic inverse inertia s 1 (a cube's, a sphere's) makes
  // it s j, three products instead of nine, the same numbers.
  const bool reads_a = w.slot_a[lane] != 0, reads_b = w.slot_b[lane] != 0;
  const bool isotropic_a = reads_a && is_isotropic(inertia_a), isotropic_b = reads_b && is_isotropic(inertia_b);
  auto response = [](const Mat3& inertia, bool isotropic, const Vec3& jacobian) {
    return isotropic ? Vec3(inertia(0, 0) * jacobian) : Vec3(inertia * jacobian);
  };
  const double inverse_mass_sum = inverse_mass_a + inverse_mass_b;
  for (int k = 0; k < m.point_count; ++k) {
    const ManifoldPoint& mp = m.points[k];
    const Vec3 point = 0.5 * (mp.point_a + mp.point_b);
    const Vec3 ra = point - xa;
    const Vec3 rb = point - xb;
    WidePoint& p = points[k];
    // A fixed side (the slot of zeros: no velocity, no motion, no inverse
    // inertia) keeps the zeros its terms were given.
    auto make_row = [&](WideRow& row, const Vec3& d, double impulse) {
      double k_row = inverse_mass_sum, angular_part = 0;
      if (reads_a) {
        const Vec3 jacobian = ra.cross(d), r = response(inertia_a, isotropic_a, jacobian);
        k_row += jacobian.dot(r);
        angular_part -= jacobian.dot(va.angular);
        set_lane(row.jacobian_a, lane, jacobian);
        set_lane(row.response_a, lane, r);
      }
      if (reads_b) {
        const Vec3 jacobian = rb.cross(d), r = response(inertia_b, isotropic_b, jacobian);
        k_row += jacobian.dot(r);
        angular_part += jacobian.dot(vb.angular);
        set_lane(row.jacobian_b, lane, jacobian);
        set_lane(row.response_b, lane, r);
      }
      row.mass[lane] = static_cast<float>(k_row > 0 ? 1.0 / k_row : 0.0);
      row.impulse[lane] = static_cast<float>(impulse);
      return angular_part;
    };
    const Vec3& friction_impulse = contact.tangent_impulse[k];
    const double angular_part = make_row(p.normal, normal, contact.normal_impulse[k]);
    make_row(p.tangent1, tangent1, friction_impulse.dot(tangent1));
    make_row(p.tangent2, tangent2, friction_impulse.dot(tangent2));
    p.separation[lane] = static_cast<float>(mp.separation);
    p.relative_velocity[lane] = static_cast<float>(normal.dot(vb.linear - va.linear) + angular_part);
  }

  // The spin row, for a single point: one point has no lever arm about
  // the normal, so nothing else stops a body spinning on it.
  if (m.point_count == 1 && in.spin_friction > 0) {
    double k_row = 0;
    if (reads_a) {
      const Vec3 r = response(inertia_a, isotropic_a, normal);
      k_row += normal.dot(r);
      set_lane(w.spin_response_a, lane, r);
    }
    if (reads_b) {
      const Vec3 r = response(inertia_b, isotropic_b, normal);
      k_row += normal.dot(r);
      set_lane(w.spin_response_b, lane, r);
    }
    if (k_row > 0) {
      w.spin_mass[lane] = static_cast<float>(1.0 / k_row);
      w.spin_impulse[lane] = static_cast<float>(contact.spin_impulse);
      w.spin_limit[lane] = static_cast<float>(double{w.friction[lane]} * in.spin_friction);
      w.spins = true;
    }
  }
}

}  // namespace tumble::physics
