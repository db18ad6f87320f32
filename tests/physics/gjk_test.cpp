// GJK distance (gjk.h) and convex hull collision: distances between cubes
// by region, random hull pairs against a brute-force feature search, hull
// separations against analytic gaps, a box built as a hull colliding exactly
// like a box shape, and hulls dropped on the ground resting on a face at the
// analytic height.
#include "gjk.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "collide.h"
#include "geometry_helpers.h"
#include "scene_helpers.h"
#include "segment.h"
#include "tumble/physics/convex_hull.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::box_corners;
using testing::centred_hull;
using testing::hull_surface_height;
using testing::kContactMargin;
using testing::kPi;
using testing::pose;
using testing::random_rotation;
using testing::random_vector;
using testing::regular_octahedron;
using testing::regular_tetrahedron;
using testing::rotation_about;

std::vector<Vec3> moved(std::vector<Vec3> points, const Transform& t) {
  for (Vec3& p : points) p = t.apply(p);
  return points;
}

// ---------------------------------------------------------------- GJK

TEST(GjkTest, CubeDistancesByRegion) {
  const std::vector<Vec3> cube = box_corners(Vec3::Constant(0.5));
  // Face to face: B's -x face 1 m from A's +x face.
  {
    const GjkResult g = gjk_distance(cube, moved(cube, pose(Vec3(2.0, 0.3, -0.2))));
    ASSERT_FALSE(g.overlap);
    EXPECT_NEAR(g.distance, 1.0, 1e-12);
    EXPECT_NEAR(g.point_a.x(), 0.5, 1e-12);
    EXPECT_NEAR(g.point_b.x(), 1.5, 1e-12);
    EXPECT_NEAR((g.point_b - g.point_a).norm(), g.distance, 1e-12);
  }
  // Edge to edge: 1 m apart in x and y, overlapping in z: sqrt(2).
  {
    const GjkResult g = gjk_distance(cube, moved(cube, pose(Vec3(2.0, 2.0, 0.1))));
    ASSERT_FALSE(g.overlap);
    EXPECT_NEAR(g.distance, std::sqrt(2.0), 1e-12);
  }
  // Corner to corner: sqrt(3), between (0.5, 0.5, 0.5) and (1.5, 1.5, 1.5).
  {
    const GjkResult g = gjk_distance(cube, moved(cube, pose(Vec3(2.0, 2.0, 2.0))));
    ASSERT_FALSE(g.overlap);
    EXPECT_NEAR(g.distance, std::sqrt(3.0), 1e-12);
    EXPECT_LT((g.point_a - Vec3::Constant(0.5)).norm(), 1e-12);
    EXPECT_LT((g.point_b - Vec3::Constant(1.5)).norm(), 1e-12);
  }
}

TEST(GjkTest, PointAndSegmentAgainstBox) {
  const std::vector<Vec3> cube = box_corners(Vec3(0.5, 0.5, 0.5));
  // A point outside an edge region: closest box point (0.5, 0.5, 0.2).
  const Vec3 point(1.5, 2.0, 0.2);
  const GjkResult g = gjk_distance(std::vector<Vec3>{point}, cube);
  ASSERT_FALSE(g.overlap);
  EXPECT_NEAR(g.distance, std::sqrt(1.0 + 2.25), 1e-12);
  EXPECT_LT((g.point_b - Vec3(0.5, 0.5, 0.2)).norm(), 1e-12);
  // A segment passing over the top face at height 1: distance 0.5.
  const std::vector<Vec3> segment = {Vec3(-2.0, 1.0, 0.1), Vec3(2.0, 1.0, 0.1)};
  EXPECT_NEAR(gjk_distance(segment, cube).distance, 0.5, 1e-12);
}

TEST(GjkTest, OverlapIsReported) {
  const std::vector<Vec3> cube = box_corners(Vec3::Constant(0.5));
  EXPECT_TRUE(gjk_distance(cube, moved(cube, pose(Vec3(0.5, 0.2, -0.3), rotation_about(Vec3(1, 1, 0), 0.7)))).overlap);
  EXPECT_TRUE(gjk_distance(std::vector<Vec3>{Vec3(0.1, -0.2, 0.3)}, cube).overlap);
  // Just apart is not overlap.
  EXPECT_FALSE(gjk_distance(cube, moved(cube, pose(Vec3(1.001, 0.0, 0.0)))).overlap);
}

// Closest point of triangle abc to p (Ericson 5.1.5, ClosestPtPointTriangle).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Distance between two disjoint convex polyhedra by brute force: the
// closest points of disjoint convex polytopes are a vertex and a face or
// two edges, so the minimum over those pairs is the distance.
double brute_force_distance(const ConvexHull& a, const Transform& ta, const ConvexHull& b, const Transform& tb) {
  double best = INFINITY;
  auto vertex_to_faces = [&](const ConvexHull& from, const Transform& tf, const ConvexHull& to, const Transform& tt) {
    for (const Vec3& v : from.vertices) {
      const Vec3 p = tf.apply(v);
      for (const ConvexHull::Face& face : to.faces) {
        const Vec3 a0 = tt.apply(to.vertices[to.face_vertices[face.first]]);
        for (std::uint32_t k = 1; k + 1 < face.count; ++k) {
          const Vec3 a1 = tt.apply(to.vertices[to.face_vertices[face.first + k]]);
          const Vec3 a2 = tt.apply(to.vertices[to.face_vertices[face.first + k + 1]]);
          best = std::min(best, (closest_point_on_triangle(p, a0, a1, a2) - p).norm());
        }
      }
    }
  };
  vertex_to_faces(a, ta, b, tb);
  vertex_to_faces(b, tb, a, ta);
  for (const ConvexHull::Edge& ea : a.edges) {
    for (const ConvexHull::Edge& eb : b.edges) {
      Vec3 ca, cb;
      closest_points_of_segments(ta.apply(a.vertices[ea.v0]), ta.apply(a.vertices[ea.v1]), tb.apply(b.vertices[eb.v0]),
                                 tb.apply(b.vertices[eb.v1]), &ca, &cb);
      best = std::min(best, (cb - ca).norm());
    }
  }
  return best;
}

std::shared_ptr<const ConvexHull> random_hull(std::mt19937& rng, int count) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i) {
    points.push_back(std::cbrt(unit(rng)) * Vec3(normal(rng), normal(rng), normal(rng)).normalized());
  }
  return build_convex_hull(points);
}

TEST(GjkTest, RandomHullPairsMatchBruteForceDistance) {
  // Hulls inside unit balls whose centres are at least 2 apart: disjoint.
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> apart(2.0, 2.6);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const auto a = random_hull(rng, 8 + trial % 13);
    const auto b = random_hull(rng, 8 + trial % 7);
    ASSERT_TRUE(a && b);
    const Transform ta = pose(random_vector(rng, -3.0, 3.0), random_rotation(rng));
    const Vec3 direction = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const Transform tb = pose(ta.position + apart(rng) * direction, random_rotation(rng));
    const std::vector<Vec3> wa = moved(a->vertices, ta), wb = moved(b->vertices, tb);
    const GjkResult g = gjk_distance(wa, wb);
    ASSERT_FALSE(g.overlap) << "trial " << trial;
    const double expected = brute_force_distance(*a, ta, *b, tb);
    EXPECT_NEAR(g.distance, expected, 1e-9 * (1.0 + expected)) << "trial " << trial;
    // The closest points lie on the hulls.
    EXPECT_LT(std::abs(hull_surface_height(ta.apply_inverse(g.point_a), *a)), 1e-9) << "trial " << trial;
    EXPECT_LT(std::abs(hull_surface_height(tb.apply_inverse(g.point_b), *b)), 1e-9) << "trial " << trial;
  }
}

// ---------------------------------------------------------------- hull pairs

TEST(HullCollideTest, TetrahedronVertexOverFaceAtTheGap) {
  // A: a regular tetrahedron turned over (face up at y = h/4). B: one
  // turned over above it, its apex (3h/4 below its centre) g above the
  // middle of A's top face. GJK and the contact both measure g.
  const double edge = 1.0;
  const double h = edge * std::sqrt(2.0 / 3.0);
  const auto tetrahedron = build_convex_hull(regular_tetrahedron(edge));
  ASSERT_NE(tetrahedron, nullptr);
  const Quat over = rotation_about(Vec3::UnitX(), kPi);
  for (double gap : {0.3, 0.01, -0.005}) {
    const Transform ta = pose(Vec3::Zero(), over);
    const Transform tb = pose(Vec3(0.0, h + gap, 0.0), over * rotation_about(Vec3::UnitY(), 0.4));
    if (gap > 0) {
      const GjkResult g = gjk_distance(moved(tetrahedron->vertices, ta), moved(tetrahedron->vertices, tb));
      EXPECT_NEAR(g.distance, gap, 1e-12);
    }
    Manifold m;
    collide(convex_hull_shape(tetrahedron), ta, convex_hull_shape(tetrahedron), tb, kContactMargin, m);
    if (gap > kContactMargin) {
      EXPECT_EQ(m.point_count, 0);
      continue;
    }
    ASSERT_EQ(m.point_count, 1) << "gap " << gap;
    EXPECT_LT((m.normal - Vec3::UnitY()).norm(), 1e-12);
    EXPECT_NEAR(m.points[0].separation, gap, 1e-12);
    EXPECT_LT((m.points[0].point_b - Vec3(0.0, 0.25 * h + gap, 0.0)).norm(), 1e-12) << "B's apex";
  }
}

TEST(HullCollideTest, CubeHullsCornerToCornerAndFaceToFace) {
  const std::vector<Vec3> corners = box_corners(Vec3::Constant(0.5));
  const auto cube = build_convex_hull(corners);
  ASSERT_NE(cube, nullptr);
  std::mt19937 rng(4);
  const Quat turn = random_rotation(rng);
  // Corner to corner, g apart along each axis: distance g sqrt(3).
  const double g = 0.1;
  const Transform ta = pose(Vec3(1, 2, 3), turn);
  const Transform tb = pose(ta.apply(Vec3::Constant(1.0 + g)), turn);
  EXPECT_NEAR(gjk_distance(moved(cube->vertices, ta), moved(cube->vertices, tb)).distance, g * std::sqrt(3.0), 1e-12);
  // Face to face, 0.01 apart: four points at separation 0.01.
  const Transform tc = pose(ta.apply(Vec3(0.3, 1.01, -0.2)), turn);
  Manifold m;
  collide(convex_hull_shape(cube), ta, convex_hull_shape(cube), tc, kContactMargin, m);
  ASSERT_EQ(m.point_count, 4);
  EXPECT_LT((m.normal - turn * Vec3::UnitY()).norm(), 1e-12);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(m.points[k].separation, 0.01, 1e-12);
}

TEST(HullCollideTest, SixtyFourSidedFaceOnBoxKeepsItsDeepest) {
  // A prism over a 64-gon (the largest face the clipper takes whole,
  // face_clipping.h) tilted by 0.004 rad on a wide box: whichever way it
  // leans, the deepest point of the manifold is the lowest vertex, 3 mm
  // into the box.
  const auto hull = centred_hull(testing::polygon_prism(64, 1.0, 0.5));
  ASSERT_NE(hull, nullptr);
  const Shape prism = convex_hull_shape(hull);
  const double depth = 0.003;
  for (const testing::Lean& lean : testing::leaning_poses(*hull, 0.004, depth)) {
    Manifold m;
    collide(box_shape(Vec3(3.0, 0.5, 3.0)), pose(Vec3(0.0, -0.5, 0.0)), prism, lean.pose, kContactMargin, m);
    ASSERT_EQ(m.point_count, 4);
    EXPECT_NEAR(testing::deepest_separation(m), -depth, 1e-12) << "leaning towards " << lean.direction << " rad";
  }
}

// Compares two manifolds of the same contact: normal and separations to
// 1e-9 and the same number of points; with compare_points, also the points
// as sets.
void expect_same_manifold(const Manifold& got, const Manifold& want, bool compare_points, const std::string& what) {
  ASSERT_EQ(got.point_count, want.point_count) << what;
  if (want.point_count == 0) return;
  EXPECT_LT((got.normal - want.normal).norm(), 1e-9)
      << what << ": normal " << got.normal.transpose() << " vs " << want.normal.transpose();
  std::vector<double> sa, sb;
  for (int k = 0; k < got.point_count; ++k) sa.push_back(got.points[k].separation);
  for (int k = 0; k < want.point_count; ++k) sb.push_back(want.points[k].separation);
  std::sort(sa.begin(), sa.end());
  std::sort(sb.begin(), sb.end());
  for (std::size_t k = 0; k < sa.size(); ++k) EXPECT_NEAR(sa[k], sb[k], 1e-9) << what << ": separation " << k;
  if (!compare_points) return;
  for (int k = 0; k < want.point_count; ++k) {
    double nearest = INFINITY;
    for (int j = 0; j < got.point_count; ++j) {
      nearest = std::min(nearest, (got.points[j].point_a - want.points[k].point_a).norm() +
                                      (got.points[j].point_b - want.points[k].point_b).norm());
    }
    EXPECT_LT(nearest, 1e-9) << what << ": point " << k << " has no match";
  }
}

struct PosePair {
  const char* name;
  Transform ta;
  Transform tb;
  bool reduced;  // the clip has more than four points (which four are kept may depend on vertex order)
};

TEST(HullCollideTest, BoxHullCollidesLikeBoxShape) {
  const Vec3 ha(0.8, 0.4, 0.7), hb(0.5, 0.5, 0.5);
  const std::vector<Vec3> corners_a = box_corners(ha), corners_b = box_corners(hb);
  const Shape box_a = box_shape(ha), box_b = box_shape(hb);
  const Shape hull_a = convex_hull_shape(build_convex_hull(corners_a));
  const Shape hull_b = convex_hull_shape(build_convex_hull(corners_b));
  ASSERT_TRUE(hull_a.hull && hull_b.hull);

  const double r = std::sqrt(0.5);
  std::vector<PosePair> poses = {
      {"stacked", pose(Vec3::Zero()), pose(Vec3(0.1, 0.9 - 0.004, 0.05), rotation_about(Vec3::UnitY(), 0.2)), false},
      {"turned 45", pose(Vec3::Zero()), pose(Vec3(0.0, 0.9 - 0.004, 0.0), rotation_about(Vec3::UnitY(), kPi / 4)),
       true},
      // A turned 45 degrees about z has its top edge (x = 0.4 r, along z) at
      // (0.8 + 0.4) r; B turned about x has its bottom edge (along x) r below
      // its centre.
      {"edge on edge", pose(Vec3::Zero(), rotation_about(Vec3::UnitZ(), kPi / 4)),
       pose(Vec3(0.05, 1.2 * r + r - 0.003, 0.0), rotation_about(Vec3::UnitX(), kPi / 4)), false},
      // B's corner (-1, -1, -1)/2 turned straight down, sqrt(3)/2 below its
      // centre, 0.01 into A's top face.
      {"corner into face", pose(Vec3::Zero()),
       pose(Vec3(0.1, 0.4 + std::sqrt(0.75) - 0.01, 0.0),
            Quat::FromTwoVectors(Vec3(-1, -1, -1).normalized(), -Vec3::UnitY())),
       false},
  };
  for (const PosePair& p : poses) {
    Manifold want, got;
    collide(box_a, p.ta, box_b, p.tb, kContactMargin, want);
    ASSERT_GT(want.point_count, 0) << p.name;
    collide(box_a, p.ta, hull_b, p.tb, kContactMargin, got);
    expect_same_manifold(got, want, !p.reduced, std::string(p.name) + " box-hull");
    collide(hull_a, p.ta, hull_b, p.tb, kContactMargin, got);
    expect_same_manifold(got, want, !p.reduced, std::string(p.name) + " hull-hull");
    collide(hull_a, p.ta, box_b, p.tb, kContactMargin, got);
    expect_same_manifold(got, want, !p.reduced, std::string(p.name) + " hull-box");
  }

  // Random poses, touching or nearly: the same axis, reference face and
  // clip, so the same points.
  std::mt19937 rng(77);
  int compared = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Transform ta = pose(random_vector(rng, -1.0, 1.0), random_rotation(rng));
    const Transform tb = pose(ta.position + random_vector(rng, -1.1, 1.1), random_rotation(rng));
    Manifold want, got;
    collide(box_a, ta, box_b, tb, kContactMargin, want);
    if (want.point_count == 0) continue;
    ++compared;
    collide(box_a, ta, hull_b, tb, kContactMargin, got);
    expect_same_manifold(got, want, true, "random box-hull " + std::to_string(trial));
    collide(hull_a, ta, hull_b, tb, kContactMargin, got);
    expect_same_manifold(got, want, true, "random hull-hull " + std::to_string(trial));
  }
  EXPECT_GT(compared, 100);
}

TEST(HullCollideTest, SphereOnBoxHullLikeSphereOnBox) {
  // Sphere against a hull goes through GJK; against a box, through the
  // closed form. Outside or inside, they must agree.
  const Vec3 half(0.6, 0.4, 0.5);
  const std::vector<Vec3> corners = box_corners(half);
  const Shape hull = convex_hull_shape(build_convex_hull(corners));
  const Shape box = box_shape(half);
  std::mt19937 rng(9);
  const Transform t = pose(Vec3(0.3, -0.2, 0.1), random_rotation(rng));
  int compared = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Shape sphere = sphere_shape(std::uniform_real_distribution<double>(0.05, 0.5)(rng));
    const Transform ts = pose(t.apply(random_vector(rng, -1.0, 1.0)));
    Manifold want, got;
    collide(sphere, ts, box, t, kContactMargin, want);
    collide(sphere, ts, hull, t, kContactMargin, got);
    if (want.point_count > 0) ++compared;
    expect_same_manifold(got, want, true, "sphere " + std::to_string(trial));
  }
  EXPECT_GT(compared, 200);
}

// ---------------------------------------------------------------- resting

// Drops a hull body flat on the face whose outward normal is face_normal
// (body frame) from 0.2 m above the ground, runs 2 s, and checks that it
// rests with that face on the plane: every vertex of the face within 5 mm
// of y = 0, the centre at rest_height (the distance from the centre of mass
// to the face), the face still facing down.
void expect_rests_on_face(const std::vector<Vec3>& points, const Vec3& face_normal, double rest_height) {
  const auto hull = centred_hull(points);
  ASSERT_NE(hull, nullptr);
  World world;
  world.add_body(testing::ground_plane());
  BodyDesc desc;
  desc.shape = convex_hull_shape(hull);
  desc.mass_properties = convex_hull_mass_properties(*hull, 1.0);
  desc.orientation = Quat::FromTwoVectors(face_normal.normalized(), -Vec3::UnitY());
  desc.position = Vec3(0.3, rest_height + 0.2, -0.1);
  const BodyId body = world.add_body(desc);
  for (int i = 0; i < 2 * 240; ++i) world.step(testing::kTick);

  const Transform t = pose(world.position(body), world.orientation(body));
  EXPECT_NEAR(world.position(body).y(), rest_height, 0.005);
  const Vec3 n = face_normal.normalized();
  double lowest = INFINITY;
  int on_ground = 0;
  for (const Vec3& v : hull->vertices) {
    const double y = t.apply(v).y();
    lowest = std::min(lowest, y);
    if (std::abs(n.dot(v) - rest_height) < 1e-9) {  // a vertex of the resting face
      EXPECT_NEAR(y, 0.0, 0.005) << "face vertex " << v.transpose();
      ++on_ground;
    }
  }
  EXPECT_EQ(on_ground, 3) << "vertices of the resting face";
  EXPECT_GT(lowest, -0.005);
  EXPECT_GT((t.rotation * n).dot(-Vec3::UnitY()), std::cos(0.01));
  EXPECT_LT(world.linear_velocity(body).norm(), 0.01);
}

TEST(HullRestingTest, TetrahedronRestsOnAFace) {
  // Regular tetrahedron of edge 0.5: height e sqrt(2/3); the centroid rests
  // a quarter of it above the face.
  const double edge = 0.5;
  expect_rests_on_face(regular_tetrahedron(edge), -Vec3::UnitY(), 0.25 * edge * std::sqrt(2.0 / 3.0));
}

TEST(HullRestingTest, OctahedronRestsOnAFace) {
  // Octahedron |x| + |y| + |z| <= r: the face with normal (1, 1, 1)/sqrt 3
  // lies r / sqrt 3 from the centre.
  const double r = 0.4;
  expect_rests_on_face(regular_octahedron(r), Vec3(-1.0, -1.0, -1.0), r / std::sqrt(3.0));
}

}  // namespace
}  // namespace tumble::physics
