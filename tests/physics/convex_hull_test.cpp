// Convex hulls (convex_hull.h): the topology of known solids (a cube with
// interior and surface points is 8 vertices, 6 quads, 12 edges), Euler's
// formula V - E + F = 2 and containment of every input point on random
// clouds, degenerate inputs rejected, and hull mass properties against the
// closed forms of the box, tetrahedron and octahedron.
#include "tumble/physics/convex_hull.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "geometry_helpers.h"
#include "tumble/physics/mass_properties.h"

namespace tumble::physics {
namespace {

using testing::box_corners;
using testing::random_rotation;
using testing::random_vector;
using testing::regular_octahedron;
using testing::regular_tetrahedron;

// Structural checks every hull must pass, given the points it was built
// from: Euler's formula; every edge shared by the two faces it names, walked
// in opposite directions; faces planar, convex and counter-clockwise seen
// from outside; every vertex one of the inputs; every input inside or on
// the hull (within tolerance, relative to the extent).
void expect_valid_hull(const ConvexHull& hull, const std::vector<Vec3>& points) {
  const std::size_t v = hull.vertices.size(), e = hull.edges.size(), f = hull.faces.size();
  EXPECT_EQ(static_cast<long>(v) - static_cast<long>(e) + static_cast<long>(f), 2)
      << "V " << v << " E " << e << " F " << f;

  double extent = 0;
  for (const Vec3& p : points) extent = std::max(extent, p.cwiseAbs().maxCoeff());
  const double tol = 1e-9 * std::max(extent, 1.0);

  std::size_t corner_slots = 0;
  std::set<std::pair<std::uint32_t, std::uint32_t>> directed;  // polygon edges, as walked
  for (std::size_t fi = 0; fi < f; ++fi) {
    const ConvexHull::Face& face = hull.faces[fi];
    ASSERT_GE(face.count, 3u);
    EXPECT_NEAR(face.normal.norm(), 1.0, 1e-12);
    corner_slots += face.count;
    for (std::uint32_t k = 0; k < face.count; ++k) {
      const std::uint32_t ia = hull.face_vertices[face.first + k];
      const std::uint32_t ib = hull.face_vertices[face.first + (k + 1) % face.count];
      const std::uint32_t ic = hull.face_vertices[face.first + (k + 2) % face.count];
      const Vec3& a = hull.vertices[ia];
      const Vec3& b = hull.vertices[ib];
      const Vec3& c = hull.vertices[ic];
      EXPECT_NEAR(face.normal.dot(a), face.offset, tol) << "vertex off its face plane";
      EXPECT_GT((b - a).cross(c - b).dot(face.normal), 0.0) << "face " << fi << " not convex counter-clockwise";
      directed.insert({ia, ib});
    }
  }
  // Every polygon edge appears once per direction: 2E slots.
  EXPECT_EQ(corner_slots, 2 * e);
  EXPECT_EQ(directed.size(), 2 * e);
  for (const ConvexHull::Edge& edge : hull.edges) {
    EXPECT_TRUE(directed.count({edge.v0, edge.v1})) << "edge not walked forward";
    EXPECT_TRUE(directed.count({edge.v1, edge.v0})) << "edge not walked back";
    auto walks = [&](std::uint32_t fi, std::uint32_t from, std::uint32_t to) {
      const ConvexHull::Face& face = hull.faces[fi];
      for (std::uint32_t k = 0; k < face.count; ++k) {
        if (hull.face_vertices[face.first + k] == from && hull.face_vertices[face.first + (k + 1) % face.count] == to) {
          return true;
        }
      }
      return false;
    };
    EXPECT_TRUE(walks(edge.face0, edge.v0, edge.v1)) << "face0 does not walk v0 -> v1";
    EXPECT_TRUE(walks(edge.face1, edge.v1, edge.v0)) << "face1 does not walk v1 -> v0";
  }

  for (const Vec3& vertex : hull.vertices) {
    const bool is_input = std::any_of(points.begin(), points.end(), [&](const Vec3& p) { return p == vertex; });
    EXPECT_TRUE(is_input) << "vertex " << vertex.transpose() << " is not an input point";
  }
  for (const Vec3& p : points) {
    for (const ConvexHull::Face& face : hull.faces) {
      EXPECT_LE(face.normal.dot(p) - face.offset, tol) << "input point " << p.transpose() << " outside the hull";
    }
  }
  // Bounds follow the vertices.
  double radius = 0;
  for (const Vec3& vertex : hull.vertices) radius = std::max(radius, vertex.norm());
  EXPECT_DOUBLE_EQ(hull.bounding_radius, radius);
}

TEST(ConvexHullTest, CubeWithInteriorAndSurfacePointsIsEightVerticesSixQuads) {
  const Vec3 half(0.5, 1.0, 1.5);
  std::vector<Vec3> points = box_corners(half);
  std::mt19937 rng(1);
  for (int i = 0; i < 60; ++i) points.push_back(random_vector(rng, -1.0, 1.0).cwiseProduct(0.99 * half));
  // Points on the surface that are not corners: face centres and edge
  // midpoints must not become vertices.
  for (int k = 0; k < 3; ++k) {
    for (double sign : {-1.0, 1.0}) {
      Vec3 centre = Vec3::Zero();
      centre[k] = sign * half[k];
      points.push_back(centre);
    }
  }
  points.emplace_back(half.x(), half.y(), 0.0);
  points.emplace_back(0.0, -half.y(), half.z());
  std::shuffle(points.begin(), points.end(), rng);

  const auto hull = build_convex_hull(points);
  ASSERT_NE(hull, nullptr);
  EXPECT_EQ(hull->vertices.size(), 8u);
  EXPECT_EQ(hull->faces.size(), 6u);
  EXPECT_EQ(hull->edges.size(), 12u);
  for (const Vec3& vertex : hull->vertices) EXPECT_TRUE(vertex.cwiseAbs().isApprox(half, 0.0)) << vertex.transpose();
  std::set<int> axes_seen;
  for (const ConvexHull::Face& face : hull->faces) {
    EXPECT_EQ(face.count, 4u);
    int axis = 0;
    face.normal.cwiseAbs().maxCoeff(&axis);
    EXPECT_NEAR(std::abs(face.normal[axis]), 1.0, 1e-12);
    EXPECT_NEAR(face.offset, half[axis], 1e-12);
    axes_seen.insert(face.normal[axis] > 0 ? axis : axis + 3);
  }
  EXPECT_EQ(axes_seen.size(), 6u);
  EXPECT_TRUE(hull->local_min.isApprox(-half, 0.0));
  EXPECT_TRUE(hull->local_max.isApprox(half, 0.0));
  expect_valid_hull(*hull, points);
}

TEST(ConvexHullTest, RandomCloudsSatisfyEulerAndContainEveryPoint) {
  std::mt19937 rng(2024);
  for (int cloud = 0; cloud < 8; ++cloud) {
    // Points in a turned, stretched ball, off the origin.
    const Quat turn = random_rotation(rng);
    const Vec3 stretch = random_vector(rng, 0.2, 2.0);
    const Vec3 centre = random_vector(rng, -5.0, 5.0);
    std::vector<Vec3> points;
    std::normal_distribution<double> normal(0.0, 1.0);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    while (points.size() < 300) {
      const Vec3 direction = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
      const Vec3 p = std::cbrt(unit(rng)) * direction;
      points.push_back(centre + turn * p.cwiseProduct(stretch));
    }
    const auto hull = build_convex_hull(points);
    ASSERT_NE(hull, nullptr) << "cloud " << cloud;
    EXPECT_GT(hull->vertices.size(), 20u);
    expect_valid_hull(*hull, points);
  }
}

TEST(ConvexHullTest, PointsOnSphereAreAllVerticesOfATriangulatedHull) {
  // Points in general position on a sphere are all extreme and no four are
  // coplanar, so V = n and every face is a triangle: E = 3V - 6, F = 2V - 4.
  std::mt19937 rng(99);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Vec3> points;
  for (int i = 0; i < 120; ++i) points.push_back(Vec3(normal(rng), normal(rng), normal(rng)).normalized());
  const auto hull = build_convex_hull(points);
  ASSERT_NE(hull, nullptr);
  EXPECT_EQ(hull->vertices.size(), 120u);
  EXPECT_EQ(hull->edges.size(), 3u * 120 - 6);
  EXPECT_EQ(hull->faces.size(), 2u * 120 - 4);
  for (const ConvexHull::Face& face : hull->faces) EXPECT_EQ(face.count, 3u);
  expect_valid_hull(*hull, points);
}

TEST(ConvexHullTest, SupportIsTheFurthestVertex) {
  std::mt19937 rng(5);
  std::vector<Vec3> points;
  for (int i = 0; i < 40; ++i) points.push_back(random_vector(rng, -1.0, 1.0));
  const auto hull = build_convex_hull(points);
  ASSERT_NE(hull, nullptr);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 direction = random_vector(rng, -1.0, 1.0);
    double best = -INFINITY;
    for (const Vec3& v : hull->vertices) best = std::max(best, v.dot(direction));
    EXPECT_EQ(hull->vertices[hull->support(direction)].dot(direction), best);
  }
}

TEST(ConvexHullTest, DegenerateInputsGiveNoHull) {
  const std::vector<Vec3> none;
  EXPECT_EQ(build_convex_hull(none), nullptr);
  const std::vector<Vec3> three = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_EQ(build_convex_hull(three), nullptr);
  const std::vector<Vec3> repeated(10, Vec3(1, 2, 3));
  EXPECT_EQ(build_convex_hull(repeated), nullptr);
  std::vector<Vec3> collinear;
  for (int i = 0; i < 10; ++i) collinear.push_back(Vec3(1, 2, 3) + 0.3 * i * Vec3(1, -1, 2));
  EXPECT_EQ(build_convex_hull(collinear), nullptr);

  // Many points on one tilted plane, spread over a square metre, some
  // within 1e-12 m of it (below the flatness tolerance).
  std::mt19937 rng(11);
  const Quat tilt = random_rotation(rng);
  std::vector<Vec3> coplanar;
  for (int i = 0; i < 50; ++i) {
    const Vec3 local = random_vector(rng, -0.5, 0.5);
    coplanar.push_back(tilt * Vec3(local.x(), (i % 7 == 0) ? 1e-12 * local.y() : 0.0, local.z()) + Vec3(3, 4, 5));
  }
  EXPECT_EQ(build_convex_hull(coplanar), nullptr);
  const std::vector<Vec3> four_coplanar = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1)};
  EXPECT_EQ(build_convex_hull(four_coplanar), nullptr);

  // The same plane plus one point off it is a pyramid: the apex and the
  // planar hull of the base.
  coplanar.push_back(tilt * Vec3(0.0, 0.3, 0.0) + Vec3(3, 4, 5));
  const auto pyramid = build_convex_hull(coplanar);
  ASSERT_NE(pyramid, nullptr);
  std::size_t base_vertices = 0;
  for (const ConvexHull::Face& face : pyramid->faces) base_vertices = std::max<std::size_t>(base_vertices, face.count);
  EXPECT_EQ(pyramid->vertices.size(), base_vertices + 1);
  EXPECT_EQ(pyramid->faces.size(), base_vertices + 1);
  expect_valid_hull(*pyramid, coplanar);
}

// ---------------------------------------------------------------- mass

void expect_matrix_near(const Mat3& actual, const Mat3& expected, double tol) {
  EXPECT_LT((actual - expected).cwiseAbs().maxCoeff(), tol) << "got\n" << actual << "\nwant\n" << expected;
}

TEST(ConvexHullMassTest, BoxHullMatchesBoxClosedForm) {
  // A box of half extents h centred at c: centre c, and
  // I_xx = m/3 (hy^2 + hz^2) etc. (box_mass_properties).
  const Vec3 half(0.5, 1.0, 1.5);
  const Vec3 centre(2.0, -1.0, 3.0);
  std::vector<Vec3> points = box_corners(half);
  for (Vec3& p : points) p += centre;
  const auto hull = build_convex_hull(points);
  ASSERT_NE(hull, nullptr);
  const MassProperties props = convex_hull_mass_properties(*hull, 6.0);
  const MassProperties expected = box_mass_properties(6.0, half);
  EXPECT_DOUBLE_EQ(props.mass, 6.0);
  EXPECT_LT((props.center - centre).norm(), 1e-12);
  expect_matrix_near(props.inertia, expected.inertia, 1e-12);

  // Turned by R, the same box has inertia R I R^T about its centre.
  std::mt19937 rng(8);
  const Quat turn = random_rotation(rng);
  std::vector<Vec3> turned = box_corners(half);
  for (Vec3& p : turned) p = turn * p;
  const auto turned_hull = build_convex_hull(turned);
  ASSERT_NE(turned_hull, nullptr);
  const Mat3 r = turn.toRotationMatrix();
  expect_matrix_near(convex_hull_mass_properties(*turned_hull, 6.0).inertia, r * expected.inertia * r.transpose(),
                     1e-12);
}

TEST(ConvexHullMassTest, RightTetrahedronMatchesClosedForm) {
  // Vertices 0, a e_x, b e_y, c e_z: centroid (a, b, c) / 4 and, about it,
  // I_xx = 3m/80 (b^2 + c^2), I_yy = 3m/80 (a^2 + c^2), I_zz = 3m/80 (a^2 + b^2)
  // and off the diagonal -integral x'y' dm = m ab/80, m ac/80, m bc/80 (the
  // central moments of a tetrahedron: Tonon, "Explicit exact formulas for the
  // 3-D tetrahedron inertia tensor in terms of its vertex coordinates",
  // J. Math. Stat. 2004).
  const double a = 1.0, b = 2.0, c = 3.0, m = 5.0;
  const std::vector<Vec3> points = {Vec3::Zero(), Vec3(a, 0, 0), Vec3(0, b, 0), Vec3(0, 0, c)};
  const auto hull = build_convex_hull(points);
  ASSERT_NE(hull, nullptr);
  EXPECT_EQ(hull->faces.size(), 4u);
  const MassProperties props = convex_hull_mass_properties(*hull, m);
  EXPECT_LT((props.center - Vec3(a, b, c) / 4.0).norm(), 1e-12);
  Mat3 expected;
  expected << 3 * m / 80 * (b * b + c * c), m * a * b / 80, m * a * c / 80,  //
      m * a * b / 80, 3 * m / 80 * (a * a + c * c), m * b * c / 80,          //
      m * a * c / 80, m * b * c / 80, 3 * m / 80 * (a * a + b * b);
  expect_matrix_near(props.inertia, expected, 1e-12);
}

TEST(ConvexHullMassTest, RegularTetrahedronAndOctahedronAreIsotropic) {
  // Regular tetrahedron of edge e: I = m e^2 / 20 about every axis through
  // the centroid. Regular octahedron |x| + |y| + |z| <= r: the mean of x^2
  // is r^2 / 10, so I = m r^2 / 5.
  const double e = 0.8, m = 2.0;
  const auto tetrahedron = build_convex_hull(regular_tetrahedron(e));
  ASSERT_NE(tetrahedron, nullptr);
  const MassProperties tp = convex_hull_mass_properties(*tetrahedron, m);
  EXPECT_LT(tp.center.norm(), 1e-12);
  expect_matrix_near(tp.inertia, (m * e * e / 20) * Mat3::Identity(), 1e-12);

  const double r = 0.6;
  const auto octahedron = build_convex_hull(regular_octahedron(r));
  ASSERT_NE(octahedron, nullptr);
  EXPECT_EQ(octahedron->faces.size(), 8u);
  EXPECT_EQ(octahedron->edges.size(), 12u);
  const MassProperties op = convex_hull_mass_properties(*octahedron, m);
  EXPECT_LT(op.center.norm(), 1e-12);
  expect_matrix_near(op.inertia, (m * r * r / 5) * Mat3::Identity(), 1e-12);
}

TEST(ConvexHullMassTest, TranslatedHullKeepsItsShape) {
  std::mt19937 rng(17);
  std::vector<Vec3> points;
  for (int i = 0; i < 30; ++i) points.push_back(random_vector(rng, -1.0, 1.0));
  const auto hull = build_convex_hull(points);
  ASSERT_NE(hull, nullptr);
  const Vec3 offset(0.5, -2.0, 1.0);
  const auto moved = translate_convex_hull(*hull, offset);
  ASSERT_EQ(moved->vertices.size(), hull->vertices.size());
  for (std::size_t i = 0; i < hull->vertices.size(); ++i) EXPECT_EQ(moved->vertices[i], hull->vertices[i] + offset);
  for (const ConvexHull::Face& face : moved->faces) {
    for (std::uint32_t k = 0; k < face.count; ++k) {
      EXPECT_NEAR(face.normal.dot(moved->vertices[moved->face_vertices[face.first + k]]), face.offset, 1e-12);
    }
  }
  const MassProperties before = convex_hull_mass_properties(*hull, 1.0);
  const MassProperties after = convex_hull_mass_properties(*moved, 1.0);
  EXPECT_LT((after.center - before.center - offset).norm(), 1e-12);
  expect_matrix_near(after.inertia, before.inertia, 1e-12);
  EXPECT_TRUE(moved->local_min.isApprox(hull->local_min + offset, 1e-15));
}

}  // namespace
}  // namespace tumble::physics
