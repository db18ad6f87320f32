// The physical ranges of body_limits.h, each at its boundaries, as every
// path that makes a body meets them: through body_desc_from_spec, with the
// error naming the field and the range.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "sim/body_limits.h"
#include "sim/body_spec.h"
#include "sim/scene_file.h"

namespace tumble::sim {
namespace {

// The error body_desc_from_spec gives the body of a one-body scene, "" if it takes it.
std::string body_error(const std::string& body_json) {
  tumble::v1::Scene scene;
  const Status parsed = parse_scene_json(R"({"bodies": [)" + body_json + "]}", &scene);
  if (!parsed.ok()) return "unparsed: " + parsed.message();
  physics::BodyDesc desc;
  return body_desc_from_spec(scene.bodies(0), "bodies[0]", &desc).message();
}

std::string sphere(double radius, double mass) {
  return R"({"shape": {"sphere": {"radius": )" + format_number(radius) + R"(}}, "mass": )" + format_number(mass) + "}";
}

std::string box(double hx, double hy, double hz, double mass, bool is_static = false) {
  return R"({"shape": {"box": {"half_extents": [)" + format_number(hx) + ", " + format_number(hy) + ", " +
         format_number(hz) + R"(]}}, "mass": )" + format_number(mass) + (is_static ? R"(, "static": true})" : "}");
}

TEST(BodyLimits, NumbersPrintShortestWithPlainExponents) {
  EXPECT_EQ(format_number(1e-40), "1e-40");
  EXPECT_EQ(format_number(1e9), "1e9");
  EXPECT_EQ(format_number(1e-6), "1e-6");
  EXPECT_EQ(format_number(3e10), "3e10");
  EXPECT_EQ(format_number(1e30), "1e30");
  EXPECT_EQ(format_number(0.001), "0.001");
  EXPECT_EQ(format_number(2.5), "2.5");
  EXPECT_EQ(format_number(-1e9), "-1e9");
  EXPECT_EQ(format_number(1e100), "1e100");
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN()), "nan");
}

TEST(BodyLimits, MassFromOneMicrogramToAMillionTonnes) {
  // Sizes that keep the density in range (1.9e-3 and 1.9e3 kg/m^3).
  EXPECT_EQ(body_error(sphere(0.05, 1e-6)), "");
  EXPECT_EQ(body_error(sphere(50, 1e9)), "");
  EXPECT_EQ(body_error(sphere(1, 0.99e-6)), "bodies[0].mass: 9.9e-7 kg is outside 1e-6 .. 1e9 kg");
  EXPECT_EQ(body_error(sphere(1, 1.01e9)), "bodies[0].mass: 1.01e9 kg is outside 1e-6 .. 1e9 kg");
  // What the range is for: a tiny positive mass used to turn the body into NaN in a tick;
  // a huge one used to be told it was not a positive finite number.
  EXPECT_EQ(body_error(sphere(0.3, 1e-40)), "bodies[0].mass: 1e-40 kg is outside 1e-6 .. 1e9 kg");
  EXPECT_EQ(body_error(sphere(0.3, 1e30)), "bodies[0].mass: 1e30 kg is outside 1e-6 .. 1e9 kg");
  EXPECT_EQ(body_error(sphere(1, 0)), "bodies[0].mass: 0 kg is outside 1e-6 .. 1e9 kg");
  EXPECT_EQ(body_error(sphere(1, -1)), "bodies[0].mass: -1 kg is outside 1e-6 .. 1e9 kg");
  // Static bodies have no mass to check: whatever is given is ignored.
  EXPECT_EQ(body_error(box(1, 1, 1, 1e-40, true)), "");
}

TEST(BodyLimits, SizesFromAMillimetreToAThousandKilometres) {
  EXPECT_EQ(body_error(box(1e-3, 1e-3, 1e-3, 1e-6)), "");
  EXPECT_EQ(body_error(box(1e6, 1e6, 1e6, 0, true)), "");
  EXPECT_EQ(body_error(box(1, 0.99e-3, 1, 1)),
            "bodies[0].shape.box.half_extents.y: 0.00099 m is outside 0.001 .. 1e6 m");
  EXPECT_EQ(body_error(box(1, 1, 1.01e6, 1e9)),
            "bodies[0].shape.box.half_extents.z: 1.01e6 m is outside 0.001 .. 1e6 m");
  // Statics too: a static box is a collision shape like any other.
  EXPECT_EQ(body_error(box(1e-4, 1, 1, 0, true)),
            "bodies[0].shape.box.half_extents.x: 0.0001 m is outside 0.001 .. 1e6 m");
  EXPECT_EQ(body_error(sphere(1e-200, 1)), "bodies[0].shape.sphere.radius: 1e-200 m is outside 0.001 .. 1e6 m");
  EXPECT_EQ(body_error(R"({"shape": {"capsule": {"radius": 0.1, "half_height": 0}}, "mass": 1})"), "");
  EXPECT_EQ(body_error(R"({"shape": {"capsule": {"radius": 0.1, "half_height": -0.1}}, "mass": 1})"),
            "bodies[0].shape.capsule.half_height: -0.1 m is outside 0 .. 1e6 m");
  EXPECT_EQ(body_error(R"({"shape": {"capsule": {"radius": 1e7, "half_height": 1}}, "mass": 1})"),
            "bodies[0].shape.capsule.radius: 1e7 m is outside 0.001 .. 1e6 m");
  // A convex hull: its thickness across each face, and its reach from its centre of mass.
  EXPECT_EQ(body_error(R"({"shape": {"convex": {"points": [[0,0,0],[1,0,0],[0,1,0],[0,0,0.002]]}}, "mass": 1e-4})"),
            "");
  EXPECT_EQ(body_error(R"({"shape": {"convex": {"points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0.0005]]}}, "static": true})"),
            "bodies[0].shape.convex.points: the hull is 0.0005 m thick, less than 0.001 m");
  EXPECT_EQ(body_error(R"({"shape": {"convex": {"points": [[0,0,0],[3e6,0,0],[0,3e6,0],[0,0,3e6]]}}, "static": true})"),
            "bodies[0].shape.convex.points: a vertex 2.48747e6 m from the centre of mass, more than 1e6 m");
}

TEST(BodyLimits, DensityFromAirlessToNeutronStarlike) {
  // A 1 m cube holds 8 m^3.
  EXPECT_EQ(body_error(box(1, 1, 1, 8e-6)), "");
  EXPECT_EQ(body_error(box(1, 1, 1, 7.9e-6)),
            "bodies[0].mass: 7.9e-6 kg in 8 m^3 is a density of 9.875e-7 kg/m^3, outside 1e-6 .. 3e10 kg/m^3");
  // A 1 cm cube holds 8e-6 m^3: 2.4e5 kg is 3e10 kg/m^3.
  EXPECT_EQ(body_error(box(0.01, 0.01, 0.01, 2.39e5)), "");
  EXPECT_EQ(body_error(box(0.01, 0.01, 0.01, 2.5e5)),
            "bodies[0].mass: 250000 kg in 8e-6 m^3 is a density of 3.125e10 kg/m^3, outside 1e-6 .. 3e10 kg/m^3");
  // A convex hull's volume: the corner tetrahedron of side 10 m holds 1000/6 m^3.
  EXPECT_EQ(body_error(R"({"shape": {"convex": {"points": [[0,0,0],[10,0,0],[0,10,0],[0,0,10]]}}, "mass": 1e-4})"),
            "bodies[0].mass: 0.0001 kg in 166.667 m^3 is a density of 6e-7 kg/m^3, outside 1e-6 .. 3e10 kg/m^3");
}

TEST(BodyLimits, MomentsOfInertiaAndTheirRatio) {
  // Point masses carry no volume; their moments are checked directly.
  EXPECT_EQ(body_error(R"({"shape": {"points": {"masses": [1e-6, 1e-6, 1e-6],
                         "positions": [[0,0,0], [1e-4,0,0], [0,1e-4,0]]}}})"),
            "bodies[0]: its principal moment of inertia 3.33333e-15 kg m^2 is outside 1e-14 .. 1e22 kg m^2");
  EXPECT_EQ(body_error(R"({"shape": {"points": {"masses": [1e-6, 1e-6, 1e-6],
                         "positions": [[0,0,0], [1e-3,0,0], [0,1e-3,0]]}}})"),
            "");
  EXPECT_EQ(body_error(R"({"shape": {"points": {"masses": [1e9, 1e9, 1e9],
                         "positions": [[0,0,0], [1e6,0,0], [0,1e6,0]]}}})"),
            "bodies[0].shape.points.masses (their sum): 3e9 kg is outside 1e-6 .. 1e9 kg");
  // The heaviest and largest set of points stays below the largest moment
  // (about 4e20 kg m^2); the bound holds for any tensor the shapes might make.
  EXPECT_EQ(body_error(R"({"shape": {"points": {"masses": [3e8, 3e8, 3e8],
                         "positions": [[0,0,0], [1e6,0,0], [0,1e6,0]]}}})"),
            "");
  physics::MassProperties heavy;
  heavy.mass = 1;
  heavy.inertia = physics::Mat3::Identity() * 2e22;
  EXPECT_EQ(check_mass_properties(heavy, 0, "b").message(),
            "b: its principal moment of inertia 2e22 kg m^2 is outside 1e-14 .. 1e22 kg m^2");
  heavy.inertia(0, 0) = std::nan("");
  EXPECT_EQ(check_mass_properties(heavy, 0, "b").message(), "b: its moments of inertia are not finite numbers");
  // A rod: the moments along and across differ by about (length / thickness)^2 / 2.
  EXPECT_EQ(body_error(box(0.001, 0.001, 1, 1)), "");  // 5e5
  EXPECT_EQ(body_error(box(0.001, 0.001, 1.5, 1)),
            "bodies[0]: its principal moments of inertia 6.66667e-7 kg m^2 and 0.75 kg m^2 differ by a factor of "
            "1.125e6, more than 1e6 (a shape too thin for its length, or point masses nearly in a line)");
  // Static and kinematic bodies do not turn under forces: no moments to check.
  EXPECT_EQ(body_error(box(0.001, 0.001, 10, 0, true)), "");
}

TEST(BodyLimits, PositionsAndVelocitiesWithinABillion) {
  EXPECT_EQ(body_error(R"({"shape": {"sphere": {"radius": 1}}, "mass": 1, "position": [1e9, -1e9, 0],
                        "linear_velocity": [1e9, 0, 0], "angular_velocity": [0, 0, -1e9]})"),
            "");
  EXPECT_EQ(body_error(R"({"shape": {"sphere": {"radius": 1}}, "mass": 1, "position": [0, 1.5e9, 0]})"),
            "bodies[0].position.y: 1.5e9 m is outside -1e9 .. 1e9 m");
  EXPECT_EQ(body_error(R"({"shape": {"sphere": {"radius": 1}}, "mass": 1, "linear_velocity": [0, 0, -2e9]})"),
            "bodies[0].linear_velocity.z: -2e9 m/s is outside -1e9 .. 1e9 m/s");
  EXPECT_EQ(body_error(R"({"shape": {"sphere": {"radius": 1}}, "mass": 1, "angular_velocity": [1e10, 0, 0]})"),
            "bodies[0].angular_velocity.x: 1e10 rad/s is outside -1e9 .. 1e9 rad/s");
}

TEST(BodyLimits, CheckRangeNamesThePathAndTheRange) {
  EXPECT_TRUE(check_range(1, kMassRange, "x").ok());
  EXPECT_EQ(check_range(std::nan(""), kMassRange, "spawn.mass").message(),
            "spawn.mass: nan kg is outside 1e-6 .. 1e9 kg");
  EXPECT_EQ(check_range(std::numeric_limits<double>::infinity(), kSizeRange, "r").message(),
            "r: inf m is outside 0.001 .. 1e6 m");
}

}  // namespace
}  // namespace tumble::sim
