#include "wide_constraint.h"

#include <algorithm>
#include <cmath>
#include <numbers>

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
                WideConstraint& w, WidePoint* points, WideArms& arms) {
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

  // A static body, or a kinematic one standing still, is read from the
  // slot of zeros: its arms, inertia and velocities stay zero, and so do its
  // Jacobians and responses. A moving kinematic body has a slot, and a zero
  // inverse inertia.
  const bool reads_a = w.slot_a[lane] != 0, reads_b = w.slot_b[lane] != 0;
  const Mat3& inertia_a = bodies.inverse_inertia[c.body_a];
  const Mat3& inertia_b = bodies.inverse_inertia[c.body_b];
  for (int r = 0; r < 3; ++r) {
    if (reads_a) set_lane(arms.inverse_inertia_a.row[r], lane, inertia_a.row(r).transpose());
    if (reads_b) set_lane(arms.inverse_inertia_b.row[r], lane, inertia_b.row(r).transpose());
  }
  if (reads_a) {
    set_lane(arms.linear_a, lane, va.linear);
    set_lane(arms.angular_a, lane, va.angular);
  }
  if (reads_b) {
    set_lane(arms.linear_b, lane, vb.linear);
    set_lane(arms.angular_b, lane, vb.angular);
  }
  for (int k = 0; k < m.point_count; ++k) {
    const ManifoldPoint& mp = m.points[k];
    const Vec3 point = 0.5 * (mp.point_a + mp.point_b);
    // The arms in double: the bodies may be far from the origin.
    if (reads_a) set_lane(arms.arm_a[k], lane, point - xa);
    if (reads_b) set_lane(arms.arm_b[k], lane, point - xb);
    arms.has_point[k][lane] = -1;
    WidePoint& p = points[k];
    const Vec3& friction_impulse = contact.tangent_impulse[k];
    p.normal.impulse[lane] = static_cast<float>(contact.normal_impulse[k]);
    p.tangent1.impulse[lane] = static_cast<float>(friction_impulse.dot(tangent1));
    p.tangent2.impulse[lane] = static_cast<float>(friction_impulse.dot(tangent2));
    p.separation[lane] = static_cast<float>(mp.separation);
  }

  // The spin row, for a single point: one point has no lever arm about
  // the normal, so nothing else stops a body spinning on it.
  if (m.point_count == 1 && in.spin_friction > 0) {
    double k_row = 0;
    if (reads_a) {
      const Vec3 r = inertia_a * normal;
      k_row += normal.dot(r);
      set_lane(w.spin_response_a, lane, r);
    }
    if (reads_b) {
      const Vec3 r = inertia_b * normal;
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

void build_rows(WideConstraint& w, WidePoint* points, const WideArms& arms) {
  const Float4 inverse_mass_sum = w.inverse_mass_a + w.inverse_mass_b;
  const Float4 zero = splat4(0.0f), one = splat4(1.0f);
  for (std::uint32_t k = 0; k < w.point_count; ++k) {
    WidePoint& p = points[k];
    const Vec3x4& arm_a = arms.arm_a[k];
    const Vec3x4& arm_b = arms.arm_b[k];
    const Mask4 has_point = arms.has_point[k];
    auto make_row = [&](WideRow& row, const Vec3x4& d) {
      row.jacobian_a = cross4(arm_a, d);
      row.jacobian_b = cross4(arm_b, d);
      row.response_a = arms.inverse_inertia_a * row.jacobian_a;
      row.response_b = arms.inverse_inertia_b * row.jacobian_b;
      // K = 1/M_a + 1/M_b + (r_a x d).I_a^-1 (r_a x d) + (r_b x d).I_b^-1
      // (r_b x d); a lane without point k, or with K = 0, takes no impulse.
      const Float4 k_row =
          inverse_mass_sum + dot4(row.jacobian_a, row.response_a) + dot4(row.jacobian_b, row.response_b);
      const Mask4 solvable = has_point & (k_row > zero);
      row.mass = select4(solvable, one / select4(solvable, k_row, one), zero);
    };
    make_row(p.normal, w.normal);
    make_row(p.tangent1, w.tangent1);
    make_row(p.tangent2, w.tangent2);
    // v_n = n.(v_b - v_a) + (r_b x n).w_b - (r_a x n).w_a
    p.relative_velocity = dot4(w.normal, arms.linear_b - arms.linear_a) + dot4(p.normal.jacobian_b, arms.angular_b) -
                          dot4(p.normal.jacobian_a, arms.angular_a);
  }
}

}  // namespace tumble::physics
