// The quaternion exponential and tensor change of frame.
#include "rotation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tumble/physics/mass_properties.h"

namespace tumble::physics {
namespace {

TEST(RotationTest, ZeroRotationVectorIsIdentity) {
  const Quat q = quat_from_rotation_vector(Vec3::Zero());
  EXPECT_EQ(q.w(), 1.0);
  EXPECT_EQ(q.vec(), Vec3::Zero());
}

TEST(RotationTest, MatchesAxisAngleAtAllScales) {
  const Vec3 axis = Vec3(0.3, -0.8, 0.5).normalized();
  // Both sides of 1e-4 and of 0.5 rad, where the series give way to sin and cos.
  for (double angle :
       {1e-9, 1e-5, 9.9e-5, 1.01e-4, 1e-3, 0.1, 0.3, 0.4999, 0.5, 0.5001, 1.0, 3.0, std::numbers::pi, 5.0, 12.0}) {
    const Quat q = quat_from_rotation_vector(angle * axis);
    const Quat expected(Eigen::AngleAxisd(angle, axis));
    EXPECT_NEAR(q.w(), expected.w(), 1e-15) << "angle " << angle;
    EXPECT_LT((q.vec() - expected.vec()).norm(), 1e-15) << "angle " << angle;
    EXPECT_NEAR(q.norm(), 1.0, 1e-15) << "angle " << angle;
  }
}

TEST(RotationTest, RotatesAboutTheVector) {
  // A quarter turn about +z takes +x to +y (right-handed).
  const Quat q = quat_from_rotation_vector(Vec3(0.0, 0.0, std::numbers::pi / 2));
  EXPECT_LT((q * Vec3::UnitX() - Vec3::UnitY()).norm(), 1e-15);
  // The rotation vector is its own axis: it is left unchanged.
  const Vec3 theta(0.4, -1.2, 0.9);
  EXPECT_LT((quat_from_rotation_vector(theta) * theta - theta).norm(), 1e-15);
}

TEST(RotationTest, BodyToWorldTensor) {
  // A rod along body x, turned a quarter about z, lies along world y: its
  // small moment is now about world y.
  Mat3 rod = Mat3::Zero();
  rod.diagonal() = Vec3(0.1, 2.0, 2.0);
  const Quat q = quat_from_rotation_vector(Vec3(0.0, 0.0, std::numbers::pi / 2));
  Mat3 expected = Mat3::Zero();
  expected.diagonal() = Vec3(2.0, 0.1, 2.0);
  EXPECT_TRUE(body_to_world_tensor(q, rod).isApprox(expected, 1e-15)) << body_to_world_tensor(q, rod);
}

TEST(RotationTest, IsotropicTensorsAreTheSameInEveryFrame) {
  // A cube's inertia and its inverse are c 1 exactly; R (c 1) R^T is c 1,
  // returned as it is.
  const Mat3 cube = box_mass_properties(3.0, Vec3::Constant(0.15)).inertia;
  EXPECT_TRUE(is_isotropic(cube));
  EXPECT_TRUE(is_isotropic(cube.inverse()));
  const Quat q = quat_from_rotation_vector(Vec3(0.3, -1.1, 0.7));
  EXPECT_EQ(body_to_world_tensor(q, cube.inverse()), cube.inverse());
  // Not c 1: a box of unequal sides, an off-diagonal entry of 1e-300.
  EXPECT_FALSE(is_isotropic(box_mass_properties(3.0, Vec3(0.15, 0.15, 0.2)).inertia));
  Mat3 nearly = cube;
  nearly(0, 1) = 1e-300;
  EXPECT_FALSE(is_isotropic(nearly));
  EXPECT_FALSE(is_isotropic(Vec3(1.0, 1.0, 1.0 + 1e-15).asDiagonal().toDenseMatrix()));
}

}  // namespace
}  // namespace tumble::physics
