// Narrowphase (collide.h) against closed-form answers: the normal, depth and
// points of sphere, capsule, box and plane pairs in the face, edge and corner
// regions; face clipping of stacked boxes (four points, a 45 degree turn
// reduced from eight); edge-edge contacts; the speculative margin for every
// pair kind; geometric invariants over random box poses; and feature ids
// that stay with the same corners under small motions.
#include "collide.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <numbers>
#include <ostream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "geometry_helpers.h"
#include "tumble/physics/convex_hull.h"
#include "tumble/physics/shape.h"

namespace tumble::physics {
namespace {

using testing::box_corners;
using testing::box_surface_height;
using testing::kContactMargin;
using testing::kPi;
using testing::pose;
using testing::random_rotation;
using testing::random_vector;
using testing::rotation_about;

constexpr double kTol = 1e-12;

void expect_vec_near(const Vec3& actual, const Vec3& expected, double tol, const std::string& what = "") {
  EXPECT_LT((actual - expected).norm(), tol)
      << what << ": got " << actual.transpose() << ", want " << expected.transpose();
}

// Every point's separation is (point_b - point_a).normal, as manifold.h
// defines it.
void expect_consistent(const Manifold& m) {
  EXPECT_NEAR(m.normal.norm(), 1.0, 1e-12);
  for (int k = 0; k < m.point_count; ++k) {
    const ManifoldPoint& p = m.points[k];
    EXPECT_NEAR((p.point_b - p.point_a).dot(m.normal), p.separation, 1e-12) << "point " << k;
  }
}

// ---------------------------------------------------------------- spheres

TEST(CollideSphereTest, SphereSphereAlongCentreLine) {
  // Centres 0.9 apart along u, radii 0.5 and 0.6: separation 0.9 - 1.1.
  const Vec3 ca(1.0, 2.0, 3.0);
  const Vec3 u = Vec3(2.0, -1.0, 2.0) / 3.0;
  const Vec3 cb = ca + 0.9 * u;
  Manifold m;
  collide(sphere_shape(0.5), pose(ca), sphere_shape(0.6), pose(cb), kContactMargin, m);
  ASSERT_EQ(m.point_count, 1);
  expect_vec_near(m.normal, u, kTol, "normal");
  EXPECT_NEAR(m.points[0].separation, -0.2, kTol);
  expect_vec_near(m.points[0].point_a, ca + 0.5 * u, kTol, "point_a");
  expect_vec_near(m.points[0].point_b, cb - 0.6 * u, kTol, "point_b");
  expect_consistent(m);
}

// The sphere-box cases share a box of half extents (1, 0.5, 0.75), turned
// and moved off the origin; the sphere centre is given in the box frame.
struct SphereBoxCase {
  const char* region;
  Vec3 centre_local;  // sphere centre, box frame
  double radius;
  Vec3 closest_local;  // closest point of the box surface, box frame
  Vec3 outward_local;  // unit normal from the box towards the sphere, box frame
  double separation;
};

void PrintTo(const SphereBoxCase& c, std::ostream* os) { *os << c.region; }

class SphereBoxTest : public ::testing::TestWithParam<SphereBoxCase> {};

TEST_P(SphereBoxTest, NormalDepthAndPoints) {
  const SphereBoxCase& c = GetParam();
  const Vec3 half(1.0, 0.5, 0.75);
  const Transform box_pose = pose(Vec3(0.5, -1.0, 2.0), rotation_about(Vec3(1, 2, 3), 0.3));
  const Vec3 centre = box_pose.apply(c.centre_local);
  const Vec3 outward = box_pose.rotation * c.outward_local;

  // Sphere first: the normal runs from the sphere into the box.
  Manifold m;
  collide(sphere_shape(c.radius), pose(centre), box_shape(half), box_pose, kContactMargin, m);
  ASSERT_EQ(m.point_count, 1);
  expect_vec_near(m.normal, -outward, 1e-12, "normal");
  EXPECT_NEAR(m.points[0].separation, c.separation, 1e-12);
  expect_vec_near(m.points[0].point_a, centre - c.radius * outward, 1e-12, "point on sphere");
  expect_vec_near(m.points[0].point_b, box_pose.apply(c.closest_local), 1e-12, "point on box");
  expect_consistent(m);

  // Box first: the same contact seen from the box.
  Manifold flipped;
  collide(box_shape(half), box_pose, sphere_shape(c.radius), pose(centre), kContactMargin, flipped);
  ASSERT_EQ(flipped.point_count, 1);
  expect_vec_near(flipped.normal, outward, 1e-12, "flipped normal");
  EXPECT_NEAR(flipped.points[0].separation, c.separation, 1e-12);
  expect_vec_near(flipped.points[0].point_a, box_pose.apply(c.closest_local), 1e-12, "flipped point on box");
}

// Outside the box the closest point is the clamped centre (Ericson 5.1.3)
// and the separation |c - q| - r; inside, the nearest face pushes out and the
// separation is -(depth below that face) - r.
INSTANTIATE_TEST_SUITE_P(
    Regions, SphereBoxTest,
    ::testing::Values(
        // Above the +y face: q = (0.2, 0.5, -0.1), |c - q| = 0.3.
        SphereBoxCase{"face", Vec3(0.2, 0.8, -0.1), 0.4, Vec3(0.2, 0.5, -0.1), Vec3(0, 1, 0), 0.3 - 0.4},
        // Beyond the (+x, +y) edge: c - q = (0.3, 0.4, 0), |c - q| = 0.5.
        SphereBoxCase{"edge", Vec3(1.3, 0.9, 0.2), 0.6, Vec3(1.0, 0.5, 0.2), Vec3(0.6, 0.8, 0), 0.5 - 0.6},
        // Beyond the (-x, +y, -z) corner: c - q = (-0.2, 0.2, -0.1), |c - q| = 0.3.
        SphereBoxCase{"corner", Vec3(-1.2, 0.7, -0.85), 0.35, Vec3(-1.0, 0.5, -0.75), Vec3(-2.0, 2.0, -1.0) / 3.0,
                      0.3 - 0.35},
        // Centre inside, 0.1 below the +y face (the nearest): -0.1 - 0.2.
        SphereBoxCase{"inside", Vec3(0.1, 0.4, 0.0), 0.2, Vec3(0.1, 0.5, 0.0), Vec3(0, 1, 0), -0.1 - 0.2}),
    [](const ::testing::TestParamInfo<SphereBoxCase>& case_info) { return std::string(case_info.param.region); });

TEST(CollideSphereTest, SphereCapsuleSideAndCap) {
  // A capsule of radius 0.3 and half height 1 lying along x (body y turned
  // onto -x), centred at the origin: its core runs from (-1,0,0) to (1,0,0).
  const Shape capsule = capsule_shape(0.3, 1.0);
  const Transform capsule_pose = pose(Vec3::Zero(), rotation_about(Vec3::UnitZ(), kPi / 2));

  // Beside the core: the closest core point is (0.4, 0, 0), 0.7 away.
  {
    const Vec3 centre(0.4, 0.7, 0.0);
    Manifold m;
    collide(sphere_shape(0.5), pose(centre), capsule, capsule_pose, kContactMargin, m);
    ASSERT_EQ(m.point_count, 1);
    expect_vec_near(m.normal, -Vec3::UnitY(), 1e-12, "side normal");
    EXPECT_NEAR(m.points[0].separation, 0.7 - 0.5 - 0.3, 1e-12);
    expect_vec_near(m.points[0].point_b, Vec3(0.4, 0.3, 0.0), 1e-12, "side point on capsule");
    expect_consistent(m);
  }
  // Past the end cap: the closest core point is the end (1, 0, 0), at
  // (0.4, 0.3, 0) from the centre, 0.5 away.
  {
    const Vec3 centre(1.4, 0.3, 0.0);
    Manifold m;
    collide(sphere_shape(0.3), pose(centre), capsule, capsule_pose, kContactMargin, m);
    ASSERT_EQ(m.point_count, 1);
    const Vec3 towards_capsule = -Vec3(0.8, 0.6, 0.0);
    expect_vec_near(m.normal, towards_capsule, 1e-12, "cap normal");
    EXPECT_NEAR(m.points[0].separation, 0.5 - 0.3 - 0.3, 1e-12);
    expect_vec_near(m.points[0].point_b, Vec3(1.0, 0.0, 0.0) - 0.3 * towards_capsule, 1e-12, "cap point");
  }
}

// ---------------------------------------------------------------- capsules

// A capsule of radius 0.3, half height 1, whose core runs along direction.
Transform capsule_along(const Vec3& centre, const Vec3& direction) {
  return pose(centre, Quat::FromTwoVectors(Vec3::UnitY(), direction));
}

TEST(CollideCapsuleTest, ParallelCapsulesGiveTwoPointsOverTheOverlap) {
  // Both along x, B 0.5 above A and shifted by 0.5: the cores overlap over
  // x in [-0.5, 1]; the surfaces overlap by 0.3 + 0.3 - 0.5 = 0.1 there.
  const Shape capsule = capsule_shape(0.3, 1.0);
  Manifold m;
  collide(capsule, capsule_along(Vec3::Zero(), Vec3::UnitX()), capsule,
          capsule_along(Vec3(0.5, 0.5, 0.0), Vec3::UnitX()), kContactMargin, m);
  ASSERT_EQ(m.point_count, 2);
  expect_vec_near(m.normal, Vec3::UnitY(), 1e-12, "normal");
  std::vector<double> xs;
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(m.points[k].separation, -0.1, 1e-12);
    EXPECT_NEAR(m.points[k].point_a.y(), 0.3, 1e-12);
    EXPECT_NEAR(m.points[k].point_b.y(), 0.2, 1e-12);
    xs.push_back(m.points[k].point_a.x());
  }
  std::sort(xs.begin(), xs.end());
  EXPECT_NEAR(xs[0], -0.5, 1e-12);
  EXPECT_NEAR(xs[1], 1.0, 1e-12);
  EXPECT_NE(m.points[0].id, m.points[1].id);
  expect_consistent(m);

  // Nearly parallel (0.01 rad apart, below the 0.05 sine threshold): still
  // two points, so a capsule lying on another does not rock.
  collide(capsule, capsule_along(Vec3::Zero(), Vec3::UnitX()), capsule,
          capsule_along(Vec3(0.5, 0.5, 0.0), Vec3(std::cos(0.01), std::sin(0.01), 0.0)), kContactMargin, m);
  EXPECT_EQ(m.point_count, 2);
}

TEST(CollideCapsuleTest, CrossedCapsulesGiveOnePoint) {
  // A along x at the origin, B along z at (0.2, 0.5, 0.1): the closest core
  // points are (0.2, 0, 0) and (0.2, 0.5, 0).
  const Shape capsule = capsule_shape(0.3, 1.0);
  Manifold m;
  collide(capsule, capsule_along(Vec3::Zero(), Vec3::UnitX()), capsule,
          capsule_along(Vec3(0.2, 0.5, 0.1), Vec3::UnitZ()), kContactMargin, m);
  ASSERT_EQ(m.point_count, 1);
  expect_vec_near(m.normal, Vec3::UnitY(), 1e-12, "normal");
  EXPECT_NEAR(m.points[0].separation, 0.5 - 0.6, 1e-12);
  expect_vec_near(m.points[0].point_a, Vec3(0.2, 0.3, 0.0), 1e-12, "point_a");
  expect_vec_near(m.points[0].point_b, Vec3(0.2, 0.2, 0.0), 1e-12, "point_b");
  expect_consistent(m);
}

TEST(CollideCapsuleTest, IntersectingCoresPushAlongTheCommonPerpendicular) {
  // The cores cross at (0.2, 0, 0): depth r_a + r_b, normal perpendicular to
  // both axes.
  const Shape capsule = capsule_shape(0.3, 1.0);
  Manifold m;
  collide(capsule, capsule_along(Vec3::Zero(), Vec3::UnitX()), capsule,
          capsule_along(Vec3(0.2, 0.0, 0.5), Vec3::UnitZ()), kContactMargin, m);
  ASSERT_EQ(m.point_count, 1);
  EXPECT_NEAR(std::abs(m.normal.y()), 1.0, 1e-12);
  EXPECT_NEAR(m.points[0].separation, -0.6, 1e-12);
  expect_consistent(m);
}

TEST(CollideCapsuleTest, CapsuleLyingOnBoxFaceGivesTwoPoints) {
  // A capsule (r 0.25, half height 0.5) lying along x, 0.01 into the top of a
  // box of half height 0.5: its core ends at x = +-0.5 over the face.
  const Shape capsule = capsule_shape(0.25, 0.5);
  const double d = 0.01;
  Manifold m;
  collide(capsule, capsule_along(Vec3(0.1, 0.5 + 0.25 - d, 0.2), Vec3::UnitX()), box_shape(Vec3(1.0, 0.5, 1.0)),
          pose(Vec3::Zero()), kContactMargin, m);
  ASSERT_EQ(m.point_count, 2);
  expect_vec_near(m.normal, -Vec3::UnitY(), 1e-12, "normal");
  std::vector<double> xs;
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(m.points[k].separation, -d, 1e-12);
    EXPECT_NEAR(m.points[k].point_b.y(), 0.5, 1e-12);
    xs.push_back(m.points[k].point_b.x());
  }
  std::sort(xs.begin(), xs.end());
  EXPECT_NEAR(xs[0], -0.4, 1e-12);
  EXPECT_NEAR(xs[1], 0.6, 1e-12);
  expect_consistent(m);

  // Sunk so far that the core is 0.05 inside the box (the separating axis
  // path): still pushed out through the top face, separation -(0.05 + r).
  collide(capsule, capsule_along(Vec3(0.1, 0.45, 0.2), Vec3::UnitX()), box_shape(Vec3(1.0, 0.5, 1.0)),
          pose(Vec3::Zero()), kContactMargin, m);
  ASSERT_EQ(m.point_count, 2);
  expect_vec_near(m.normal, -Vec3::UnitY(), 1e-12, "normal, core inside");
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(m.points[k].separation, -0.05 - 0.25, 1e-12);
  expect_consistent(m);
}

// ---------------------------------------------------------------- planes

TEST(CollidePlaneTest, FlatBoxGivesFourCornersAtDepth) {
  // Box of half extents (0.5, 0.25, 0.4) turned about y, its bottom face
  // 0.01 below the plane y = 0: the four bottom corners at separation -0.01.
  const Vec3 half(0.5, 0.25, 0.4);
  const double d = 0.01;
  const Transform box_pose = pose(Vec3(0.3, 0.25 - d, -0.2), rotation_about(Vec3::UnitY(), 0.7));
  Manifold m;
  collide(box_shape(half), box_pose, plane_shape(Vec3::UnitY(), 0.0), pose(Vec3::Zero()), kContactMargin, m);
  ASSERT_EQ(m.point_count, 4);
  expect_vec_near(m.normal, -Vec3::UnitY(), 1e-12, "normal");
  std::set<std::uint32_t> ids;
  for (int k = 0; k < 4; ++k) {
    const ManifoldPoint& p = m.points[k];
    EXPECT_NEAR(p.separation, -d, 1e-12);
    const Vec3 local = box_pose.apply_inverse(p.point_a);
    EXPECT_NEAR(std::abs(local.x()), half.x(), 1e-12);
    EXPECT_NEAR(local.y(), -half.y(), 1e-12);
    EXPECT_NEAR(std::abs(local.z()), half.z(), 1e-12);
    EXPECT_NEAR(p.point_b.y(), 0.0, 1e-12);
    ids.insert(p.id);
  }
  EXPECT_EQ(ids.size(), 4u);
  expect_consistent(m);
}

TEST(CollidePlaneTest, TiltedBoxGivesOnlyItsLowEdgeOrCorner) {
  const Vec3 half(0.5, 0.25, 0.4);
  const double d = 0.01;
  const Shape ground = plane_shape(Vec3::UnitY(), 0.0);
  // Tilted by theta about z: the corners at x = -0.5 dip lowest, at
  // -(0.5 sin theta + 0.25 cos theta) from the centre; the others stay more
  // than the margin above the plane. Two points, both at -d.
  {
    const double theta = 0.2;
    const double centre_height = 0.5 * std::sin(theta) + 0.25 * std::cos(theta) - d;
    const Transform box_pose = pose(Vec3(0.0, centre_height, 0.0), rotation_about(Vec3::UnitZ(), theta));
    Manifold m;
    collide(box_shape(half), box_pose, ground, pose(Vec3::Zero()), kContactMargin, m);
    ASSERT_EQ(m.point_count, 2);
    for (int k = 0; k < 2; ++k) {
      EXPECT_NEAR(m.points[k].separation, -d, 1e-12);
      const Vec3 local = box_pose.apply_inverse(m.points[k].point_a);
      EXPECT_NEAR(local.x(), -half.x(), 1e-12);
      EXPECT_NEAR(local.y(), -half.y(), 1e-12);
    }
  }
  // Tilted about a skew axis so one corner is lowest: one point, at the
  // depth of that corner.
  {
    const Transform turned = pose(Vec3::Zero(), rotation_about(Vec3(1.0, 0.0, 0.6), 0.5));
    double lowest = INFINITY;
    for (const Vec3& corner : box_corners(half)) lowest = std::min(lowest, turned.apply(corner).y());
    const Transform box_pose{Vec3(0.0, -lowest - d, 0.0), turned.rotation};
    Manifold m;
    collide(box_shape(half), box_pose, ground, pose(Vec3::Zero()), kContactMargin, m);
    ASSERT_EQ(m.point_count, 1);
    EXPECT_NEAR(m.points[0].separation, -d, 1e-12);
  }
}

TEST(CollidePlaneTest, PlaneBodyTransformPlacesThePlane) {
  // The body-frame plane y = 0.5, turned by 90 degrees about z (body y
  // becomes world -x) and moved to (2, 0, 0): the world plane x = 1.5, with
  // normal -x, so -x = -1.5 and the solid is x > 1.5.
  const Shape plane = plane_shape(Vec3::UnitY(), 0.5);
  const Transform plane_pose = pose(Vec3(2.0, 0.0, 0.0), rotation_about(Vec3::UnitZ(), kPi / 2));
  Vec3 normal;
  double offset;
  world_plane(plane, plane_pose, &normal, &offset);
  expect_vec_near(normal, -Vec3::UnitX(), 1e-12, "world normal");
  EXPECT_NEAR(offset, -1.5, 1e-12);

  // A sphere of radius 0.3 centred at x = 1.3 reaches 0.1 past the plane.
  Manifold m;
  collide(sphere_shape(0.3), pose(Vec3(1.3, 4.0, -1.0)), plane, plane_pose, kContactMargin, m);
  ASSERT_EQ(m.point_count, 1);
  expect_vec_near(m.normal, Vec3::UnitX(), 1e-12, "normal");
  EXPECT_NEAR(m.points[0].separation, -0.1, 1e-12);
  expect_vec_near(m.points[0].point_b, Vec3(1.5, 4.0, -1.0), 1e-12, "point on plane");
}

TEST(CollidePlaneTest, CapsuleLyingFlatGivesBothEnds) {
  const double d = 0.02 / 4;
  Manifold m;
  collide(capsule_shape(0.25, 0.5), capsule_along(Vec3(0.0, 0.25 - d, 0.0), Vec3(1.0, 0.0, 1.0).normalized()),
          plane_shape(Vec3::UnitY(), 0.0), pose(Vec3::Zero()), kContactMargin, m);
  ASSERT_EQ(m.point_count, 2);
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(m.points[k].separation, -d, 1e-12);
    EXPECT_NEAR(std::hypot(m.points[k].point_a.x(), m.points[k].point_a.z()), 0.5, 1e-12);
  }
}

TEST(CollidePlaneTest, HullWithManyVerticesNearThePlaneKeepsItsDeepest) {
  // A 200-sided prism (radius 1) tilted by 0.004 rad: all 200 bottom
  // vertices lie within the margin of the plane, more than the narrowphase
  // keeps as candidates. Whichever way it leans, the lowest vertex is 3 mm
  // below the plane and the manifold's deepest point must be that one.
  const auto hull = testing::centred_hull(testing::polygon_prism(200, 1.0, 0.5));
  ASSERT_NE(hull, nullptr);
  const Shape prism = convex_hull_shape(hull);
  const double depth = 0.003;
  for (const testing::Lean& lean : testing::leaning_poses(*hull, 0.004, depth)) {
    Manifold m;
    collide(prism, lean.pose, plane_shape(Vec3::UnitY(), 0.0), pose(Vec3::Zero()), kContactMargin, m);
    ASSERT_EQ(m.point_count, 4);
    EXPECT_NEAR(testing::deepest_separation(m), -depth, 1e-12) << "leaning towards " << lean.direction << " rad";
  }
}

// ---------------------------------------------------------------- boxes

TEST(CollideBoxTest, StackedBoxesGiveFourCornersAtDepth) {
  // A (half extents (1, 0.5, 0.8)) turned about y; B (0.3, 0.25, 0.2) on its
  // top face, turned a further 0.3 about A's up axis, sunk d into it. The
  // reference face is A's top; the points are B's bottom corners.
  const Vec3 ha(1.0, 0.5, 0.8), hb(0.3, 0.25, 0.2);
  const double d = 0.004;
  const Quat qa = rotation_about(Vec3::UnitY(), 0.4);
  const Transform ta = pose(Vec3(1.0, 2.0, 3.0), qa);
  const Transform tb = pose(ta.apply(Vec3(0.2, ha.y() + hb.y() - d, -0.1)), qa * rotation_about(Vec3::UnitY(), 0.3));
  Manifold m;
  collide(box_shape(ha), ta, box_shape(hb), tb, kContactMargin, m);
  ASSERT_EQ(m.point_count, 4);
  const Vec3 up = ta.rotation.col(1);
  expect_vec_near(m.normal, up, 1e-12, "normal along the stack");
  std::set<int> corners_seen;
  for (int k = 0; k < 4; ++k) {
    const ManifoldPoint& p = m.points[k];
    EXPECT_NEAR(p.separation, -d, 1e-12);
    const Vec3 local_b = tb.apply_inverse(p.point_b);
    // A bottom corner of B: (+-0.3, -0.25, +-0.2).
    EXPECT_NEAR(std::abs(local_b.x()), hb.x(), 1e-12);
    EXPECT_NEAR(local_b.y(), -hb.y(), 1e-12);
    EXPECT_NEAR(std::abs(local_b.z()), hb.z(), 1e-12);
    corners_seen.insert((local_b.x() > 0 ? 1 : 0) + (local_b.z() > 0 ? 2 : 0));
    // The point on A is that corner moved onto A's top face.
    expect_vec_near(p.point_a, p.point_b + d * up, 1e-12, "point on A");
    EXPECT_NEAR(ta.apply_inverse(p.point_a).y(), ha.y(), 1e-12);
  }
  EXPECT_EQ(corners_seen.size(), 4u);
  expect_consistent(m);
}

TEST(CollideBoxTest, SlightlyTiltedStackHasEachCornersOwnDepth) {
  // B tilted by alpha about its x axis: the bottom corner (x, -hy, z) sits at
  // -hy cos(alpha) - z sin(alpha) below B's centre, so its separation is
  // its height above A's top face, centre_height - ha_y - hy cos(alpha) - z sin(alpha).
  const Vec3 ha(1.0, 0.5, 1.0), hb(0.4, 0.25, 0.3);
  const double alpha = 0.02;
  const double centre_height = ha.y() + hb.y() - 0.005;  // of B's centre above A's
  const Transform ta = pose(Vec3::Zero());
  const Transform tb = pose(Vec3(0.1, centre_height, 0.0), rotation_about(Vec3::UnitX(), alpha));
  Manifold m;
  collide(box_shape(ha), ta, box_shape(hb), tb, kContactMargin, m);
  ASSERT_EQ(m.point_count, 4);
  expect_vec_near(m.normal, Vec3::UnitY(), 1e-12, "normal");
  for (int k = 0; k < 4; ++k) {
    const Vec3 local_b = tb.apply_inverse(m.points[k].point_b);
    const double corner_z = local_b.z();  // +-hz
    const double expected = centre_height - ha.y() - hb.y() * std::cos(alpha) - corner_z * std::sin(alpha);
    EXPECT_NEAR(m.points[k].separation, expected, 1e-12) << "corner z " << corner_z;
  }
}

// Twice the signed area of the polygon (p_0, ..., p_{n-1}) seen along normal,
// with the points ordered by angle about their mean.
double convex_polygon_area(std::vector<Vec3> points, const Vec3& normal) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  const Vec3 u = (points[0] - mean).normalized();
  const Vec3 w = normal.cross(u);
  std::sort(points.begin(), points.end(), [&](const Vec3& a, const Vec3& b) {
    return std::atan2((a - mean).dot(w), (a - mean).dot(u)) < std::atan2((b - mean).dot(w), (b - mean).dot(u));
  });
  double area2 = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    area2 += (points[i] - mean).cross(points[(i + 1) % points.size()] - mean).dot(normal);
  }
  return 0.5 * area2;
}

TEST(CollideBoxTest, BoxTurnedFortyFiveDegreesOnBoxReducesOctagonToFour) {
  // Two unit cubes, the top one turned 45 degrees about the stack axis: the
  // overlap of the faces is a regular octagon of area 2 (sqrt 2 - 1) with
  // vertices where an edge of one square crosses an edge of the other. The
  // clip makes those eight points; the reduction keeps four of them that
  // span the overlap (the best four-vertex subset, every other vertex, has
  // 1/sqrt(2) of the octagon's area).
  const Vec3 half = Vec3::Constant(0.5);
  const double d = 0.003;
  const Transform ta = pose(Vec3::Zero());
  const Transform tb = pose(Vec3(0.0, 1.0 - d, 0.0), rotation_about(Vec3::UnitY(), kPi / 4));
  Manifold m;
  collide(box_shape(half), ta, box_shape(half), tb, kContactMargin, m);
  ASSERT_EQ(m.point_count, 4);
  expect_vec_near(m.normal, Vec3::UnitY(), 1e-12, "normal");
  std::vector<Vec3> footprint;
  std::set<std::uint32_t> ids;
  for (int k = 0; k < 4; ++k) {
    const ManifoldPoint& p = m.points[k];
    EXPECT_NEAR(p.separation, -d, 1e-12);
    // On the boundary of both squares: a vertex of the octagon.
    const Vec3 in_a = p.point_a;
    const Vec3 in_b = tb.apply_inverse(p.point_b);
    EXPECT_NEAR(std::max(std::abs(in_a.x()), std::abs(in_a.z())), 0.5, 1e-12) << "on A's top face edge";
    EXPECT_NEAR(std::max(std::abs(in_b.x()), std::abs(in_b.z())), 0.5, 1e-12) << "on B's bottom face edge";
    EXPECT_NEAR(in_b.y(), -0.5, 1e-12);
    footprint.emplace_back(in_a.x(), 0.0, in_a.z());
    ids.insert(p.id);
  }
  EXPECT_EQ(ids.size(), 4u);
  const double octagon_area = 2.0 * (std::sqrt(2.0) - 1.0);
  const double area = convex_polygon_area(footprint, Vec3::UnitY());
  EXPECT_NEAR(area, octagon_area / std::sqrt(2.0), 1e-9) << "area spanned by the four points";
  expect_consistent(m);
}

TEST(CollideBoxTest, CrossedEdgesGiveOnePointAlongTheEdgeCross) {
  // A unit cube turned 45 degrees about z has a top edge along z at height
  // sqrt(2)/2; one turned 45 degrees about x has a bottom edge along x at
  // sqrt(2)/2 below its centre. B's centre at (0.1, sqrt(2) - d, -0.15): the
  // edges cross at x = 0, z = -0.15, d apart, and the normal is z x x = y.
  const Vec3 half = Vec3::Constant(0.5);
  const double d = 0.005;
  const double r = std::sqrt(0.5);
  const Transform ta = pose(Vec3::Zero(), rotation_about(Vec3::UnitZ(), kPi / 4));
  const Transform tb = pose(Vec3(0.1, 2.0 * r - d, -0.15), rotation_about(Vec3::UnitX(), kPi / 4));
  Manifold m;
  collide(box_shape(half), ta, box_shape(half), tb, kContactMargin, m);
  ASSERT_EQ(m.point_count, 1);
  expect_vec_near(m.normal, Vec3::UnitZ().cross(Vec3::UnitX()), 1e-12, "normal");
  EXPECT_NEAR(m.points[0].separation, -d, 1e-12);
  expect_vec_near(m.points[0].point_a, Vec3(0.0, r, -0.15), 1e-12, "point on A's edge");
  expect_vec_near(m.points[0].point_b, Vec3(0.0, r - d, -0.15), 1e-12, "point on B's edge");
  expect_consistent(m);
}

TEST(CollideBoxTest, RandomOverlapsSatisfyManifoldInvariants) {
  // Over random poses of two boxes that may touch: unit normal from A's side
  // towards B, at most four points with distinct ids, each on the surface of
  // both boxes, separation (point_b - point_a).n and at most the margin.
  std::mt19937 rng(12345);
  int touching = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 ha = random_vector(rng, 0.1, 1.0), hb = random_vector(rng, 0.1, 1.0);
    const Transform ta = pose(random_vector(rng, -1.0, 1.0), random_rotation(rng));
    const Transform tb = pose(ta.position + random_vector(rng, -1.5, 1.5), random_rotation(rng));
    Manifold m;
    collide(box_shape(ha), ta, box_shape(hb), tb, kContactMargin, m);
    if (m.point_count == 0) continue;
    ++touching;
    ASSERT_LE(m.point_count, kMaxManifoldPoints);
    EXPECT_NEAR(m.normal.norm(), 1.0, 1e-12);
    EXPECT_GE(m.normal.dot(tb.position - ta.position), -1e-12) << "trial " << trial;
    std::set<std::uint32_t> ids;
    for (int k = 0; k < m.point_count; ++k) {
      const ManifoldPoint& p = m.points[k];
      ids.insert(p.id);
      EXPECT_NEAR((p.point_b - p.point_a).dot(m.normal), p.separation, 1e-12);
      EXPECT_LE(p.separation, kContactMargin + 1e-12);
      EXPECT_NEAR(box_surface_height(ta.apply_inverse(p.point_a), ha), 0.0, 1e-9)
          << "trial " << trial << " point " << k;
      EXPECT_NEAR(box_surface_height(tb.apply_inverse(p.point_b), hb), 0.0, 1e-9)
          << "trial " << trial << " point " << k;
    }
    EXPECT_EQ(ids.size(), static_cast<std::size_t>(m.point_count)) << "trial " << trial;
  }
  EXPECT_GT(touching, 500);
}

// ---------------------------------------------------------------- margin

// Two shapes placed so that their closest distance is a given gap, known in
// closed form, and the separation the narrowphase must report for them.
struct GapCase {
  const char* name;
  std::function<void(double gap, Shape* a, Transform* ta, Shape* b, Transform* tb)> place;
};

std::shared_ptr<const ConvexHull> unit_cube_hull() {
  const std::vector<Vec3> corners = box_corners(Vec3::Constant(0.5));
  return build_convex_hull(corners);
}

std::vector<GapCase> gap_cases() {
  const Quat tilt = rotation_about(Vec3(1.0, 2.0, -1.0), 0.6);  // a common turn of the whole scene
  auto placed = [tilt](const Vec3& p, const Quat& q = Quat::Identity()) { return pose(tilt * p, tilt * q); };
  const Quat edge_down = rotation_about(Vec3::UnitX(), kPi / 4);
  const Quat edge_up = rotation_about(Vec3::UnitZ(), kPi / 4);
  const double r = std::sqrt(0.5);
  return {
      {"SphereSphere",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = sphere_shape(0.5), *ta = placed(Vec3::Zero());
         *b = sphere_shape(0.25), *tb = placed(Vec3(0.0, 0.75 + g, 0.0));
       }},
      {"SphereCapsule",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = sphere_shape(0.5), *ta = placed(Vec3::Zero());
         *b = capsule_shape(0.25, 1.0), *tb = placed(Vec3(0.3, 0.75 + g, 0.0), rotation_about(Vec3::UnitZ(), kPi / 2));
       }},
      {"SphereBox",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = sphere_shape(0.5), *ta = placed(Vec3(0.2, 1.0 + g, 0.1));
         *b = box_shape(Vec3(1.0, 0.5, 1.0)), *tb = placed(Vec3::Zero());
       }},
      {"SphereHull",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = sphere_shape(0.5), *ta = placed(Vec3(0.1, 1.0 + g, -0.2));
         *b = convex_hull_shape(unit_cube_hull()), *tb = placed(Vec3::Zero());
       }},
      {"CapsuleCapsule",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = capsule_shape(0.25, 1.0), *ta = placed(Vec3::Zero(), rotation_about(Vec3::UnitZ(), kPi / 2));
         *b = capsule_shape(0.25, 1.0), *tb = placed(Vec3(0.0, 0.5 + g, 0.0), rotation_about(Vec3::UnitX(), kPi / 2));
       }},
      {"CapsuleBox",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = capsule_shape(0.25, 0.3), *ta = placed(Vec3(0.0, 0.75 + g, 0.0), rotation_about(Vec3::UnitZ(), kPi / 2));
         *b = box_shape(Vec3(1.0, 0.5, 1.0)), *tb = placed(Vec3::Zero());
       }},
      {"CapsuleHull",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = capsule_shape(0.25, 0.5), *ta = placed(Vec3(0.0, 1.25 + g, 0.0));  // standing on its end
         *b = convex_hull_shape(unit_cube_hull()), *tb = placed(Vec3::Zero());
       }},
      {"BoxBoxFace",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = box_shape(Vec3(1.0, 0.5, 1.0)), *ta = placed(Vec3::Zero());
         *b = box_shape(Vec3::Constant(0.25)), *tb = placed(Vec3(0.3, 0.75 + g, 0.0));
       }},
      {"BoxBoxEdge",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = box_shape(Vec3::Constant(0.5)), *ta = placed(Vec3::Zero(), edge_up);
         *b = box_shape(Vec3::Constant(0.5)), *tb = placed(Vec3(0.0, 2.0 * r + g, 0.0), edge_down);
       }},
      {"BoxHull",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = box_shape(Vec3(1.0, 0.5, 1.0)), *ta = placed(Vec3::Zero());
         *b = convex_hull_shape(unit_cube_hull()),
         *tb = placed(Vec3(0.2, 1.0 + g, 0.1), rotation_about(Vec3::UnitY(), 0.3));
       }},
      {"HullHull",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = convex_hull_shape(unit_cube_hull()), *ta = placed(Vec3::Zero(), edge_up);
         *b = convex_hull_shape(unit_cube_hull()), *tb = placed(Vec3(0.0, 2.0 * r + g, 0.0), edge_down);
       }},
      {"SpherePlane",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = sphere_shape(0.5), *ta = placed(Vec3(3.0, 0.5 + g, 1.0));
         *b = plane_shape(Vec3::UnitY(), 0.0), *tb = placed(Vec3::Zero());
       }},
      {"CapsulePlane",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = capsule_shape(0.25, 0.5), *ta = placed(Vec3(0.0, 0.25 + g, 0.0), rotation_about(Vec3::UnitX(), kPi / 2));
         *b = plane_shape(Vec3::UnitY(), 0.0), *tb = placed(Vec3::Zero());
       }},
      {"BoxPlane",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = box_shape(Vec3(0.5, 0.25, 0.5)),
         *ta = placed(Vec3(0.0, 0.25 + g, 0.0), rotation_about(Vec3::UnitY(), 1.0));
         *b = plane_shape(Vec3::UnitY(), 0.0), *tb = placed(Vec3::Zero());
       }},
      {"HullPlane",
       [=](double g, Shape* a, Transform* ta, Shape* b, Transform* tb) {
         *a = convex_hull_shape(unit_cube_hull()), *ta = placed(Vec3(0.0, 0.5 + g, 0.0));
         *b = plane_shape(Vec3::UnitY(), 0.0), *tb = placed(Vec3::Zero());
       }},
  };
}

void PrintTo(const GapCase& c, std::ostream* os) { *os << c.name; }

class GapTest : public ::testing::TestWithParam<GapCase> {};

TEST_P(GapTest, PointsOnlyWithinTheSpeculativeMargin) {
  const GapCase& c = GetParam();
  Shape a, b;
  Transform ta, tb;
  // Touching within the margin: speculative points, the nearest at the gap.
  for (double gap : {-0.01, 0.0, 0.5 * kContactMargin, kContactMargin - 1e-4}) {
    c.place(gap, &a, &ta, &b, &tb);
    Manifold m;
    collide(a, ta, b, tb, kContactMargin, m);
    ASSERT_GE(m.point_count, 1) << "gap " << gap;
    double nearest = INFINITY;
    for (int k = 0; k < m.point_count; ++k) {
      nearest = std::min(nearest, m.points[k].separation);
      EXPECT_LE(m.points[k].separation, kContactMargin) << "gap " << gap;
    }
    EXPECT_NEAR(nearest, gap, 1e-9) << "gap " << gap;
    expect_consistent(m);
  }
  // Beyond the margin: nothing.
  for (double gap : {kContactMargin + 1e-4, 2 * kContactMargin, 1.0}) {
    c.place(gap, &a, &ta, &b, &tb);
    Manifold m;
    collide(a, ta, b, tb, kContactMargin, m);
    EXPECT_EQ(m.point_count, 0) << "gap " << gap;
  }
}

INSTANTIATE_TEST_SUITE_P(AllPairKinds, GapTest, ::testing::ValuesIn(gap_cases()),
                         [](const ::testing::TestParamInfo<GapCase>& case_info) {
                           return std::string(case_info.param.name);
                         });

// ---------------------------------------------------------------- feature ids

// Collides box B resting on box A over frames with small random motions of
// B (up to 1 mm and 5e-4 rad, the jitter of a settling stack); each frame
// maps the ids to where their points lie in B's frame. The ids must stay
// the same and name the same points: the warm start of the solver finds last
// step's impulses by id. (Tilts of 1e-3 rad and more may swap which box gives
// the reference face when B overhangs, by design: the face choice only
// resists changes smaller than half a millimetre.)
void expect_ids_persist(const Vec3& ha, const Vec3& hb, const Vec3& offset_on_a) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  const Transform ta = pose(Vec3::Zero());
  const double depth = 0.002;
  std::map<std::uint32_t, Vec3> first;
  for (int frame = 0; frame < 200; ++frame) {
    const Vec3 shift = 1e-3 * Vec3(jitter(rng), 0.5 * jitter(rng), jitter(rng));
    const Quat wobble = rotation_about(random_vector(rng, -1.0, 1.0), 5e-4 * jitter(rng));
    const Transform tb = pose(Vec3(offset_on_a.x(), ha.y() + hb.y() - depth, offset_on_a.z()) + shift,
                              wobble * rotation_about(Vec3::UnitY(), 0.1));
    Manifold m;
    collide(box_shape(ha), ta, box_shape(hb), tb, kContactMargin, m);
    ASSERT_EQ(m.point_count, 4) << "frame " << frame;
    std::map<std::uint32_t, Vec3> now;
    for (int k = 0; k < 4; ++k) now[m.points[k].id] = tb.apply_inverse(m.points[k].point_b);
    ASSERT_EQ(now.size(), 4u) << "ids not distinct in frame " << frame;
    if (frame == 0) {
      first = now;
      continue;
    }
    for (const auto& [id, local] : now) {
      const auto it = first.find(id);
      ASSERT_NE(it, first.end()) << "frame " << frame << ": new id " << std::hex << id;
      // The same corner, or the same edge crossing moved by the jitter.
      EXPECT_LT((local - it->second).norm(), 1e-2) << "frame " << frame << ", id " << std::hex << id;
    }
  }
}

TEST(CollideFeatureIdTest, BoxRestingInsideFaceKeepsCornerIds) {
  // B's footprint well inside A's top face: the points are B's corners.
  expect_ids_persist(Vec3(2.0, 0.5, 2.0), Vec3(0.5, 0.25, 0.4), Vec3(0.3, 0.0, -0.2));
}

TEST(CollideFeatureIdTest, BoxOverhangingCornerKeepsClipIds) {
  // B hangs over A's (+x, +z) corner: two points are edge crossings of the
  // clip, whose ids name the crossing edges.
  expect_ids_persist(Vec3(1.0, 0.5, 1.0), Vec3(0.5, 0.25, 0.5), Vec3(1.0, 0.0, 0.9));
}

TEST(CollideFeatureIdTest, BoxOnPlaneKeepsCornerIds) {
  std::mt19937 rng(3);
  const Vec3 half(0.5, 0.25, 0.4);
  std::map<std::uint32_t, Vec3> first;
  for (int frame = 0; frame < 100; ++frame) {
    const Quat wobble = rotation_about(random_vector(rng, -1.0, 1.0), 1e-3);
    const Transform tb = pose(Vec3(0.0, 0.249, 0.0) + random_vector(rng, -5e-4, 5e-4), wobble);
    Manifold m;
    collide(box_shape(half), tb, plane_shape(Vec3::UnitY(), 0.0), pose(Vec3::Zero()), kContactMargin, m);
    ASSERT_EQ(m.point_count, 4);
    std::map<std::uint32_t, Vec3> now;
    for (int k = 0; k < 4; ++k) now[m.points[k].id] = tb.apply_inverse(m.points[k].point_a);
    if (frame == 0) first = now;
    ASSERT_EQ(now.size(), 4u);
    for (const auto& [id, local] : now) {
      ASSERT_TRUE(first.count(id)) << "frame " << frame;
      EXPECT_LT((local - first[id]).norm(), 1e-12) << "a corner id names another corner";
    }
  }
}

}  // namespace
}  // namespace tumble::physics
