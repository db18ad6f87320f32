// Mass properties against closed forms and against sums over point masses.
#include "tumble/physics/mass_properties.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <numbers>
#include <vector>

namespace tumble::physics {
namespace {

// Relative difference |a - b| / |b|.
double relative_error(double a, double b) { return std::abs(a - b) / std::abs(b); }

// A uniform n x n x n grid of equal point masses at the cell centres of a box
// with the given full extents, centred on center.
MassProperties grid_in_box(double mass, const Vec3& extents, const Vec3& center, int n) {
  const std::size_t count = static_cast<std::size_t>(n) * static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  std::vector<double> masses(count, mass / static_cast<double>(count));
  std::vector<Vec3> positions;
  positions.reserve(count);
  const Vec3 cell = extents / n;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const Vec3 offset((i + 0.5) * cell.x(), (j + 0.5) * cell.y(), (k + 0.5) * cell.z());
        positions.push_back(center - 0.5 * extents + offset);
      }
    }
  }
  return point_mass_properties(masses, positions);
}

TEST(MassPropertiesTest, BoxClosedForm) {
  // m = 3, half extents (0.5, 1, 1.5): I_xx = m/3 (1 + 2.25), ...
  const MassProperties box = box_mass_properties(3.0, Vec3(0.5, 1.0, 1.5));
  EXPECT_DOUBLE_EQ(box.mass, 3.0);
  EXPECT_EQ(box.center, Vec3::Zero());
  Mat3 expected = Mat3::Zero();
  expected.diagonal() = Vec3(3.25, 2.5, 1.25);
  EXPECT_TRUE(box.inertia.isApprox(expected, 1e-15)) << box.inertia;
}

TEST(MassPropertiesTest, SphereClosedForm) {
  const MassProperties sphere = sphere_mass_properties(2.0, 0.5);
  EXPECT_DOUBLE_EQ(sphere.mass, 2.0);
  EXPECT_EQ(sphere.center, Vec3::Zero());
  const Mat3 expected = 0.2 * Mat3::Identity();  // 2/5 * 2 * 0.25
  EXPECT_TRUE(sphere.inertia.isApprox(expected, 1e-15)) << sphere.inertia;
}

TEST(MassPropertiesTest, CapsuleWithoutCylinderIsSphere) {
  const MassProperties capsule = capsule_mass_properties(2.0, 0.5, 0.0);
  const MassProperties sphere = sphere_mass_properties(2.0, 0.5);
  EXPECT_TRUE(capsule.inertia.isApprox(sphere.inertia, 1e-15)) << capsule.inertia;
}

TEST(MassPropertiesTest, CapsuleMatchesPointMassIntegration) {
  // Integrate over the capsule's volume with point masses at the centres of
  // a fine grid of cells inside it (r = 0.3, segment from y = -0.5 to 0.5).
  const double mass = 4.0;
  const double radius = 0.3;
  const double half_height = 0.5;
  const int cells_per_radius = 30;
  const double h = radius / cells_per_radius;
  const int nx = 2 * cells_per_radius;
  const int ny = static_cast<int>(std::ceil(2.0 * (half_height + radius) / h));

  // Cell centres symmetric about the origin, like the capsule.
  std::vector<Vec3> positions;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      for (int k = 0; k < nx; ++k) {
        const Vec3 p((i - 0.5 * (nx - 1)) * h, (j - 0.5 * (ny - 1)) * h, (k - 0.5 * (nx - 1)) * h);
        // Inside when within radius of the nearest point of the segment.
        const Vec3 axis_point(0.0, std::clamp(p.y(), -half_height, half_height), 0.0);
        if ((p - axis_point).squaredNorm() <= radius * radius) positions.push_back(p);
      }
    }
  }
  const std::vector<double> masses(positions.size(), mass / static_cast<double>(positions.size()));
  const MassProperties numeric = point_mass_properties(masses, positions);
  const MassProperties capsule = capsule_mass_properties(mass, radius, half_height);

  EXPECT_DOUBLE_EQ(capsule.mass, mass);
  EXPECT_LT(numeric.center.norm(), 1e-12);
  for (int axis = 0; axis < 3; ++axis) {
    const double err = relative_error(capsule.inertia(axis, axis), numeric.inertia(axis, axis));
    std::printf("[ measured ] capsule I(%d,%d): closed form %.6f, %zu point masses %.6f, relative difference %.2e\n",
                axis, axis, capsule.inertia(axis, axis), positions.size(), numeric.inertia(axis, axis), err);
    EXPECT_LT(err, 0.005) << "axis " << axis << ": closed form " << capsule.inertia(axis, axis) << ", numeric "
                          << numeric.inertia(axis, axis);
  }
  // The capsule is longer than it is wide: the axis is the easy axis.
  EXPECT_LT(capsule.inertia(1, 1), capsule.inertia(0, 0));
  EXPECT_DOUBLE_EQ(capsule.inertia(0, 0), capsule.inertia(2, 2));
}

// For n cell centres across an extent a, the mean of x^2 is
// a^2/12 (1 - 1/n^2), so a uniform n^3 grid of total mass m gives
// I_xx = m/12 (b^2 + c^2)(1 - 1/n^2) exactly.
Vec3 discrete_grid_inertia(double mass, const Vec3& extents, int n) {
  const Vec3 e2 = extents.cwiseProduct(extents);
  const double shrink = 1.0 - 1.0 / (static_cast<double>(n) * n);
  return (mass / 12.0) * shrink * Vec3(e2.y() + e2.z(), e2.x() + e2.z(), e2.x() + e2.y());
}

TEST(MassPropertiesTest, PointGridMatchesDiscreteClosedForm) {
  const double mass = 6.0;
  const Vec3 extents(1.0, 2.0, 3.0);
  const Vec3 center(5.0, -2.0, 1.0);  // away from the origin: exercises the centre of mass
  for (int n : {2, 3, 10, 50}) {
    const MassProperties grid = grid_in_box(mass, extents, center, n);
    // Plain sums over up to 125000 terms: roundoff of a few 1e-12 relative.
    EXPECT_LT(relative_error(grid.mass, mass), 1e-11);
    EXPECT_LT((grid.center - center).norm(), 1e-11 * center.norm()) << "n = " << n;
    const Vec3 expected = discrete_grid_inertia(mass, extents, n);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_LT(relative_error(grid.inertia(axis, axis), expected(axis)), 1e-12)
          << "n = " << n << ", axis " << axis << ": " << grid.inertia(axis, axis) << " vs " << expected(axis);
    }
    // Symmetric grid: no products of inertia.
    const double scale = grid.inertia.diagonal().maxCoeff();
    EXPECT_LT(std::abs(grid.inertia(0, 1)), 1e-12 * scale);
    EXPECT_LT(std::abs(grid.inertia(0, 2)), 1e-12 * scale);
    EXPECT_LT(std::abs(grid.inertia(1, 2)), 1e-12 * scale);
  }
}

TEST(MassPropertiesTest, PointGridConvergesToSolidBox) {
  const double mass = 6.0;
  const Vec3 extents(1.0, 2.0, 3.0);
  const MassProperties solid = box_mass_properties(mass, 0.5 * extents);

  const MassProperties fine = grid_in_box(mass, extents, Vec3::Zero(), 50);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LT(relative_error(fine.inertia(axis, axis), solid.inertia(axis, axis)), 1e-3) << "axis " << axis;
  }
  // A coarse grid is visibly off (factor 1 - 1/9), so the comparison has teeth.
  const MassProperties coarse = grid_in_box(mass, extents, Vec3::Zero(), 3);
  EXPECT_GT(relative_error(coarse.inertia(0, 0), solid.inertia(0, 0)), 0.1);
}

TEST(MassPropertiesTest, CenterOfAsymmetricPointSet) {
  const std::vector<double> masses = {1.0, 2.0, 3.0};
  const std::vector<Vec3> positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 2, 0)};
  const MassProperties props = point_mass_properties(masses, positions);
  EXPECT_DOUBLE_EQ(props.mass, 6.0);
  // c = (1*0 + 2*1 + 3*0, 1*0 + 2*0 + 3*2, 0) / 6.
  EXPECT_NEAR(props.center.x(), 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(props.center.y(), 1.0, 1e-15);
  EXPECT_NEAR(props.center.z(), 0.0, 1e-15);

  // About c: r' = (-1/3, -1, 0), (2/3, -1, 0), (-1/3, 1, 0).
  // I_xx = sum m y'^2 = 1 + 2 + 3 = 6; I_yy = sum m x'^2 = 1/9 + 8/9 + 3/9 = 4/3;
  // I_zz = I_xx + I_yy; I_xy = -sum m x' y' = -(1/3 - 4/3 - 1) = 2.
  Mat3 expected;
  expected << 6.0, 2.0, 0.0,  //
      2.0, 4.0 / 3.0, 0.0,    //
      0.0, 0.0, 6.0 + 4.0 / 3.0;
  EXPECT_TRUE(props.inertia.isApprox(expected, 1e-14)) << props.inertia;
}

TEST(MassPropertiesTest, ProductsOfInertiaOfDiagonalPair) {
  // Two unit masses on the diagonal y = x: a thin rod along (1, 1, 0).
  const std::vector<double> masses = {1.0, 1.0};
  const std::vector<Vec3> positions = {Vec3(1, 1, 0), Vec3(-1, -1, 0)};
  const MassProperties props = point_mass_properties(masses, positions);
  EXPECT_EQ(props.center, Vec3::Zero());
  // Each mass: (r.r) 1 - r r^T = 2 1 - [[1,1,0],[1,1,0],[0,0,0]].
  Mat3 expected;
  expected << 2.0, -2.0, 0.0,  //
      -2.0, 2.0, 0.0,          //
      0.0, 0.0, 4.0;
  EXPECT_TRUE(props.inertia.isApprox(expected, 1e-15)) << props.inertia;
  // The rod's axis carries no inertia.
  EXPECT_NEAR((props.inertia * Vec3(1, 1, 0)).norm(), 0.0, 1e-15);
}

TEST(MassPropertiesTest, EmptyPointSetIsZero) {
  const MassProperties props = point_mass_properties({}, {});
  EXPECT_EQ(props.mass, 0.0);
  EXPECT_EQ(props.center, Vec3::Zero());
  EXPECT_EQ(props.inertia, Mat3::Zero());
}

}  // namespace
}  // namespace tumble::physics
