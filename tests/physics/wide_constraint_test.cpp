// The rows of a wide constraint (wide_constraint.h), built four lanes at
// once, against each row's terms worked out for one lane at a time in
// double precision: the Jacobians r x d, the responses I^-1 (r x d), the
// effective mass 1 / (1/M_a + 1/M_b + (r_a x d).I_a^-1 (r_a x d) +
// (r_b x d).I_b^-1 (r_b x d)) and the normal velocity before the solve. The
// four lanes differ: two dynamic bodies with four points, a static body
// under a dynamic one with two, no constraint, and one point far from the
// origin; a lane without a point k must take no impulse there, and a side
// read from the slot of zeros has no terms.
#include "wide_constraint.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace tumble::physics {
namespace {

// A symmetric positive definite inverse inertia, not isotropic.
Mat3 inverse_inertia(double a, double b, double c, double off) {
  Mat3 m;
  m << a, off, 0.5 * off, off, b, -off, 0.5 * off, -off, c;
  return m;
}

struct Scene {
  // Bodies: 0 static (the slot of zeros), 1..5 dynamic.
  std::vector<double> inverse_mass{0.0, 1.0, 0.5, 0.25, 2.0, 1.0 / 3};
  std::vector<Mat3> inertia{Mat3::Zero(),
                            inverse_inertia(2.0, 3.0, 4.0, 0.3),
                            inverse_inertia(1.0, 1.5, 0.8, -0.2),
                            inverse_inertia(6.0, 6.0, 6.0, 0.0),
                            inverse_inertia(0.5, 0.7, 0.9, 0.1),
                            inverse_inertia(3.0, 2.0, 1.0, 0.4)};
  std::vector<Transform> transforms;
  std::vector<double> friction = std::vector<double>(6, 0.5);
  std::vector<double> restitution = std::vector<double>(6, 0.0);
  std::vector<SolverVelocity> external = std::vector<SolverVelocity>(6);
  std::vector<SolverVelocity> velocities;
  std::vector<Contact> contacts;
  std::vector<ContactConstraint> constraints;

  Scene() {
    const std::array<Vec3, 6> positions = {Vec3::Zero(),        Vec3(0.1, 1.0, -0.2), Vec3(0.3, 2.1, 0.1),
                                           Vec3(2.0, 0.5, 1.0), Vec3(1e4, 3.0, -2e4), Vec3(1e4, 4.1, -2e4)};
    for (const Vec3& p : positions) transforms.push_back(Transform{p, Mat3::Identity()});
    for (int i = 0; i < 6; ++i) {
      velocities.push_back(SolverVelocity{Vec3(0.1 * i, -0.3, 0.2), Vec3(0.5, -0.1 * i, 0.3)});
    }
    velocities[0] = SolverVelocity{};
    // Lane 0: bodies 1 and 2, four points; lane 1: the static body under
    // body 3, two points; lane 3: bodies 4 and 5, far out, one point.
    add({1, 2}, Vec3(0.1, 1.0, 0.05).normalized(),
        {Vec3(0.0, 1.5, 0.0), Vec3(0.4, 1.55, 0.1), Vec3(0.2, 1.6, -0.3), Vec3(-0.1, 1.5, 0.2)});
    add({0, 3}, Vec3::UnitY(), {Vec3(1.8, 0.0, 0.8), Vec3(2.2, 0.0, 1.2)});
    add({4, 5}, Vec3(0.0, 1.0, -0.1).normalized(), {Vec3(1e4 + 0.1, 3.55, -2e4 + 0.05)});
  }

  void add(std::array<std::uint32_t, 2> bodies, const Vec3& normal, std::vector<Vec3> points) {
    Contact c;
    c.manifold.normal = normal;
    c.manifold.point_count = static_cast<int>(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
      ManifoldPoint& p = c.manifold.points[k];
      p.point_a = points[k] - 0.001 * normal;
      p.point_b = points[k] + 0.001 * normal;
      p.separation = 0.002 - 0.001 * static_cast<double>(k);
      c.normal_impulse[k] = 0.1 * static_cast<double>(k + 1);
    }
    constraints.push_back(ContactConstraint{bodies[0], bodies[1], static_cast<std::uint32_t>(contacts.size()),
                                            static_cast<std::uint32_t>(points.size()), true});
    contacts.push_back(c);
  }

  WideRowInputs inputs() const {
    return WideRowInputs{ContactSolverBodies{inverse_mass, inertia, transforms, friction, restitution, external},
                         velocities, Softness{}, Softness{}, 0.0};
  }
};

TEST(WideConstraint, RowsOfFourLanesMatchEachLaneWorkedOutInDouble) {
  const Scene scene;
  WideConstraint w;
  // Slots: lane 0 bodies 1, 2 in slots 1, 2; lane 1 the static body in the
  // slot of zeros and body 3 in slot 3; lane 2 unused; lane 3 slots 4, 5.
  const std::uint32_t slot_a[kLanes] = {1, 0, 0, 4}, slot_b[kLanes] = {2, 3, 0, 5};
  const std::uint32_t constraint[kLanes] = {0, 1, kNoConstraint, 2};
  for (int l = 0; l < kLanes; ++l) {
    w.slot_a[l] = slot_a[l];
    w.slot_b[l] = slot_b[l];
    w.constraint[l] = constraint[l];
  }
  w.point_count = kMaxManifoldPoints;
  std::array<WidePoint, kMaxManifoldPoints> points{};
  WideArms arms{};
  const WideRowInputs in = scene.inputs();
  for (int l = 0; l < kLanes; ++l) {
    if (w.constraint[l] == kNoConstraint) continue;
    const ContactConstraint& c = scene.constraints[w.constraint[l]];
    build_lane(in, c, scene.contacts[c.contact], l, w, points.data(), arms);
  }
  build_rows(w, points.data(), arms);

  for (int l = 0; l < kLanes; ++l) {
    for (int k = 0; k < kMaxManifoldPoints; ++k) {
      const WidePoint& p = points[static_cast<std::size_t>(k)];
      const bool has_point = w.constraint[l] != kNoConstraint &&
                             k < scene.contacts[scene.constraints[w.constraint[l]].contact].manifold.point_count;
      const std::array<const WideRow*, 3> rows = {&p.normal, &p.tangent1, &p.tangent2};
      const std::array<const Vec3x4*, 3> directions = {&w.normal, &w.tangent1, &w.tangent2};
      if (!has_point) {
        for (const WideRow* row : rows) {
          EXPECT_EQ(row->mass[l], 0.0f) << "lane " << l << " point " << k;
          EXPECT_EQ(row->impulse[l], 0.0f) << "lane " << l << " point " << k;
          EXPECT_EQ(lane_of(row->jacobian_a, l), Vec3::Zero()) << "lane " << l << " point " << k;
          EXPECT_EQ(lane_of(row->jacobian_b, l), Vec3::Zero()) << "lane " << l << " point " << k;
        }
        continue;
      }
      const ContactConstraint& c = scene.constraints[w.constraint[l]];
      const ManifoldPoint& mp = scene.contacts[c.contact].manifold.points[k];
      const Vec3 point = 0.5 * (mp.point_a + mp.point_b);
      const bool fixed_a = w.slot_a[l] == 0;
      const Vec3 ra = fixed_a ? Vec3::Zero() : Vec3(point - scene.transforms[c.body_a].position);
      const Vec3 rb = point - scene.transforms[c.body_b].position;
      for (std::size_t r = 0; r < rows.size(); ++r) {
        const Vec3 d = lane_of(*directions[r], l);
        const Vec3 ja = ra.cross(d), jb = rb.cross(d);
        const Vec3 response_a = scene.inertia[c.body_a] * ja, response_b = scene.inertia[c.body_b] * jb;
        const double k_row =
            scene.inverse_mass[c.body_a] + scene.inverse_mass[c.body_b] + ja.dot(response_a) + jb.dot(response_b);
        const std::string where =
            "lane " + std::to_string(l) + " point " + std::to_string(k) + " row " + std::to_string(r);
        EXPECT_NEAR(rows[r]->mass[l], 1.0 / k_row, 1e-5 / k_row) << where;
        EXPECT_LT((lane_of(rows[r]->jacobian_a, l) - ja).norm(), 1e-5) << where;
        EXPECT_LT((lane_of(rows[r]->jacobian_b, l) - jb).norm(), 1e-5) << where;
        EXPECT_LT((lane_of(rows[r]->response_a, l) - response_a).norm(), 1e-4) << where;
        EXPECT_LT((lane_of(rows[r]->response_b, l) - response_b).norm(), 1e-4) << where;
      }
      const Vec3 n = lane_of(w.normal, l);
      const SolverVelocity& va = scene.velocities[c.body_a];
      const SolverVelocity& vb = scene.velocities[c.body_b];
      const double vn = n.dot(vb.linear + vb.angular.cross(rb) - va.linear - va.angular.cross(ra));
      EXPECT_NEAR(p.relative_velocity[l], vn, 1e-5) << "lane " << l << " point " << k;
      EXPECT_EQ(p.normal.impulse[l], static_cast<float>(scene.contacts[c.contact].normal_impulse[k]));
    }
  }
}

}  // namespace
}  // namespace tumble::physics
