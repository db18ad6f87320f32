// Scene files: defaults, strictness, and error messages that name the field.
#include <gtest/gtest.h>

#include <memory>

#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim_driver.h"
#include "test_paths.h"
#include "tumble/physics/convex_hull.h"

namespace tumble::sim {
namespace {

Status parse(const std::string& json, tumble::v1::Scene* scene) { return parse_scene_json(json, scene); }

TEST(SceneFile, ParsesTheExampleFromTheReadme) {
  tumble::v1::Scene scene;
  const Status status = parse(R"({"gravity": [0, -9.81, 0],
     "bodies": [{"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2.0,
                 "position": [0, 0, 0], "orientation": [1, 0, 0, 0],
                 "linear_velocity": [0, 0, 0], "angular_velocity": [0, 0, 0]}]})",
                              &scene);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(scene.bodies_size(), 1);
  EXPECT_EQ(scene.bodies(0).name(), "crate");
  EXPECT_DOUBLE_EQ(scene.bodies(0).shape().box().half_extents().y(), 0.5);
  EXPECT_DOUBLE_EQ(scene.bodies(0).mass(), 2.0);
  EXPECT_DOUBLE_EQ(scene.gravity().y(), -9.81);
}

TEST(SceneFile, MissingFieldsTakeTheirDefaults) {
  tumble::v1::Scene scene;
  ASSERT_TRUE(parse(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 3}]})", &scene).ok());
  EXPECT_DOUBLE_EQ(scene.gravity().x(), 0);
  EXPECT_DOUBLE_EQ(scene.gravity().y(), -9.81);
  EXPECT_DOUBLE_EQ(scene.gravity().z(), 0);
  std::unique_ptr<Simulation> sim;
  ASSERT_TRUE(Simulation::create(scene, SimConfig{}, &sim).ok());
  const physics::BodyId id = sim->world().body_id_at(0);
  EXPECT_TRUE(sim->world().orientation(id).isApprox(physics::Quat::Identity()));
  EXPECT_TRUE(sim->world().linear_velocity(id).isZero());
  EXPECT_TRUE(sim->world().angular_velocity(id).isZero());
  EXPECT_TRUE(sim->world().position(id).isZero());
}

TEST(SceneFile, ShapesMapToTheirMassProperties) {
  tumble::v1::Scene scene;
  ASSERT_TRUE(parse(R"({"bodies": [
      {"name": "b", "shape": {"box": {"half_extents": [1, 2, 3]}}, "mass": 3},
      {"name": "c", "shape": {"capsule": {"radius": 0.5, "half_height": 1}}, "mass": 2},
      {"name": "p", "shape": {"points": {"masses": [1, 1, 2], "positions": [[0,0,0],[2,0,0],[0,2,0]]}},
       "position": [10, 0, 0]}]})",
                    &scene)
                  .ok());
  std::unique_ptr<Simulation> sim;
  ASSERT_TRUE(Simulation::create(scene, SimConfig{}, &sim).ok());
  const auto& world = sim->world();
  // Box: I_xx = m/3 (hy^2 + hz^2).
  EXPECT_NEAR(world.inertia_body(world.body_id_at(0))(0, 0), 3.0 / 3.0 * (4 + 9), 1e-12);
  EXPECT_DOUBLE_EQ(world.mass(world.body_id_at(1)), 2.0);
  // Points: the mass is their sum and the position places their centre of mass.
  EXPECT_DOUBLE_EQ(world.mass(world.body_id_at(2)), 4.0);
  EXPECT_TRUE(world.position(world.body_id_at(2)).isApprox(physics::Vec3(10, 0, 0)));
}

TEST(SceneFile, MaterialsMotionTypesPlanesAndHulls) {
  tumble::v1::Scene scene;
  const Status parsed = parse(R"({"bodies": [
      {"name": "ground", "static": true, "shape": {"plane": {"normal": [0, 2, 0], "offset": -1}}},
      {"name": "ramp", "static": true, "shape": {"box": {"half_extents": [2, 0.1, 2]}}, "friction": 0.9},
      {"name": "lift", "kinematic": true, "shape": {"box": {"half_extents": [1, 0.1, 1]}},
       "linear_velocity": [0, 0.5, 0]},
      {"name": "ball", "shape": {"sphere": {"radius": 0.5}}, "mass": 1, "restitution": 0.8},
      {"name": "wedge", "shape": {"convex": {"points": [[0,0,0],[3,0,0],[0,3,0],[0,0,3]]}}, "mass": 6,
       "position": [5, 5, 5]}]})",
                              &scene);
  ASSERT_TRUE(parsed.ok()) << parsed.message();
  std::unique_ptr<Simulation> sim;
  const Status created = Simulation::create(scene, SimConfig{}, &sim);
  ASSERT_TRUE(created.ok()) << created.message();
  const auto& world = sim->world();
  const physics::BodyId ground = world.body_id_at(0);
  EXPECT_EQ(world.motion_type(ground), physics::MotionType::static_body);
  // The normal is normalised; the plane stays where the file put it.
  EXPECT_TRUE(world.shape(ground).plane_normal.isApprox(physics::Vec3::UnitY()));
  EXPECT_DOUBLE_EQ(world.shape(ground).plane_offset, -1.0);
  EXPECT_DOUBLE_EQ(world.friction(ground), 0.5);  // the default
  EXPECT_EQ(world.motion_type(world.body_id_at(1)), physics::MotionType::static_body);
  EXPECT_DOUBLE_EQ(world.friction(world.body_id_at(1)), 0.9);
  EXPECT_EQ(world.motion_type(world.body_id_at(2)), physics::MotionType::kinematic_body);
  EXPECT_TRUE(world.linear_velocity(world.body_id_at(2)).isApprox(physics::Vec3(0, 0.5, 0)));
  EXPECT_DOUBLE_EQ(world.restitution(world.body_id_at(3)), 0.8);
  EXPECT_DOUBLE_EQ(world.restitution(world.body_id_at(0)), 0.0);  // the default
  // The hull is re-centred on its centre of mass, a quarter of the way along
  // each leg of this right tetrahedron. The tetrahedron is unchanged by any
  // permutation of the axes, so its inertia about that centre has equal
  // diagonal entries.
  const physics::BodyId wedge = world.body_id_at(4);
  EXPECT_EQ(world.shape(wedge).type, physics::ShapeType::convex_hull);
  EXPECT_TRUE(world.position(wedge).isApprox(physics::Vec3(5, 5, 5)));
  const physics::Mat3& inertia = world.inertia_body(wedge);
  EXPECT_NEAR(inertia(0, 0), inertia(1, 1), 1e-9);
  EXPECT_NEAR(inertia(1, 1), inertia(2, 2), 1e-9);
  // Each vertex of the centred hull is the file's point minus the centroid (3/4, 3/4, 3/4).
  bool found_origin_corner = false;
  for (const physics::Vec3& v : world.shape(wedge).hull->vertices) {
    found_origin_corner = found_origin_corner || v.isApprox(physics::Vec3(-0.75, -0.75, -0.75));
  }
  EXPECT_TRUE(found_origin_corner);
}

TEST(SceneFile, ErrorsNameTheField) {
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"box": {"half_extents": [1, 1]}}, "mass": 1}]})"),
            "bodies[0].shape.box.half_extents: expected an array of 3 numbers [x, y, z]");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": -1}]})"),
            "bodies[0].mass: -1 kg is outside 1e-6 .. 1e9 kg");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 1},
                                      {"shape": {"sphere": {"radius": 0}}, "mass": 1}]})"),
            "bodies[1].shape.sphere.radius: 0 m is outside 0.001 .. 1e6 m");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 1, "colour": "red"}]})"),
            "bodies[0]: unknown field 'colour'");
  EXPECT_EQ(load_error(R"({"bodies": [{"mass": 1}]})"), "bodies[0]: missing field 'shape'");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"cube": {}}, "mass": 1}]})"), "bodies[0].shape: unknown field 'cube'");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 1,
                                      "orientation": [2, 0, 0, 0]}]})"),
            "bodies[0].orientation: must be a unit quaternion [w, x, y, z]");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": "heavy"}]})"),
            "bodies[0].mass: expected a number");
  EXPECT_EQ(load_error(R"({"bodies": [{"name": "a", "shape": {"sphere": {"radius": 1}}, "mass": 1},
                                      {"name": "a", "shape": {"sphere": {"radius": 1}}, "mass": 1}]})"),
            "bodies[1].name: 'a' is used by another body");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"points": {"masses": [1, 1],
                                      "positions": [[0,0,0],[1,0,0]]}}}]})"),
            "bodies[0].shape.points: the points are collinear, so the body has no rotational inertia about one "
            "axis");
  // Positive, but so small that the moments of inertia would underflow to 0
  // or the inverse mass overflow: outside the ranges (body_limits.h).
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"capsule": {"radius": 1e-200, "half_height": 0}}, "mass": 1}]})"),
            "bodies[0].shape.capsule.radius: 1e-200 m is outside 0.001 .. 1e6 m");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 1e-310}]})"),
            "bodies[0].mass: 1e-310 kg is outside 1e-6 .. 1e9 kg");
  EXPECT_EQ(load_error(R"({"gravity": [0, "down", 0]})"), "gravity[1]: expected a number");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"plane": {}}}]})"),
            "bodies[0].shape.plane: a plane must be static (\"static\": true)");
  EXPECT_EQ(load_error(R"({"bodies": [{"static": true, "shape": {"plane": {"normal": [0, 0, 0]}}}]})"),
            "bodies[0].shape.plane.normal: must not be zero");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"convex": {"points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}},
                                      "mass": 1}]})"),
            "bodies[0].shape.convex.points: the points span no volume (all coplanar)");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"convex": {"points": [[0,0,0],[1,0,0],[0,1,0]]}}, "mass": 1}]})"),
            "bodies[0].shape.convex.points: needs at least four points");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 1, "friction": -0.1}]})"),
            "bodies[0].friction: must be a finite number >= 0");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 1, "restitution": 1.5}]})"),
            "bodies[0].restitution: must be between 0 and 1");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "static": true, "kinematic": true}]})"),
            "bodies[0]: a body cannot be both static and kinematic");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "static": "yes"}]})"),
            "bodies[0].static: expected true or false");
}

TEST(SceneFile, NotJsonSaysWhere) {
  tumble::v1::Scene scene;
  const Status status = parse("{\"bodies\": [}", &scene);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("not valid JSON"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("line 1"), std::string::npos) << status.message();
}

TEST(SceneFile, ANumberBeyondADoubleIsAnErrorNotAnException) {
  tumble::v1::Scene scene;
  const Status status = parse(R"({"gravity": [0, 1e400, 0]})", &scene);
  EXPECT_EQ(status.message(), "not valid JSON: number overflow parsing '1e400'");
}

TEST(SceneFile, MissingFileNamesThePath) {
  tumble::v1::Scene scene;
  const Status status = load_scene_file("/nonexistent/world.json", &scene);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.message(), "/nonexistent/world.json: cannot open the file");
}

class ShippedScene : public ::testing::TestWithParam<const char*> {};

TEST_P(ShippedScene, Loads) {
  tumble::v1::Scene scene;
  const Status status = load_scene_file(std::string(test::scenes_dir()) + "/" + GetParam(), &scene);
  ASSERT_TRUE(status.ok()) << status.message();
  std::unique_ptr<Simulation> sim;
  const Status created = Simulation::create(scene, SimConfig{}, &sim);
  ASSERT_TRUE(created.ok()) << created.message();
  EXPECT_GE(sim->body_count(), 1u);
}

// The playground is the collision showcase: after 20 s every dynamic body
// is resting on or above the ground, the crate column still stands, the ball
// has stopped bouncing and the rider has gone round with the turntable.
TEST(SceneFile, ThePlaygroundSettles) {
  tumble::v1::Scene scene;
  ASSERT_TRUE(load_scene_file(std::string(test::scenes_dir()) + "/playground.json", &scene).ok());
  std::unique_ptr<Simulation> sim;
  ASSERT_TRUE(Simulation::create(scene, SimConfig{}, &sim).ok());
  for (int i = 0; i < 20 * 240; ++i) sim->run_tick();
  const auto& world = sim->world();
  for (std::size_t i = 0; i < world.body_count(); ++i) {
    const physics::BodyId id = world.body_id_at(i);
    if (world.motion_type(id) != physics::MotionType::dynamic_body) continue;
    EXPECT_GT(world.position(id).y(), 0.15) << scene.bodies(static_cast<int>(id)).name();
  }
  // Crates 1..4 are bodies 3..6: the column stands where it was put.
  for (int k = 0; k < 4; ++k) {
    const physics::Vec3 expected(0, 0.5 + k, 0);
    EXPECT_LT((world.position(world.body_id_at(3 + static_cast<std::size_t>(k))) - expected).norm(), 0.02)
        << "crate" << k + 1;
  }
  EXPECT_LT(world.linear_velocity(world.body_id_at(7)).norm(), 0.05) << "ball";
  // The rider started 0.8 m from the turntable's axis on +x: turning with it
  // it has left the x axis but stayed on the table.
  const physics::Vec3 rider = world.position(world.body_id_at(11)) - physics::Vec3(6, 0, 4);
  EXPECT_GT(std::abs(rider.z()), 0.1);
  EXPECT_LT(std::hypot(rider.x(), rider.z()), 1.5);
}

// The three ragdolls of scenes/ragdoll.json (one standing, one dropped
// lying, one diving) fall, land and all sleep within 10 s (2.6 s as
// measured), held still by their joints' friction; without it they are
// still awake after the 10 s (tried).
TEST(SceneFile, TheRagdollsComeToRest) {
  tumble::v1::Scene scene;
  ASSERT_TRUE(load_scene_file(std::string(test::scenes_dir()) + "/ragdoll.json", &scene).ok());
  std::unique_ptr<Simulation> sim;
  ASSERT_TRUE(Simulation::create(scene, SimConfig{}, &sim).ok());
  const auto& world = sim->world();
  const std::size_t dynamic = world.body_count() - 1;  // all but the ground
  int ticks = 0;
  for (; ticks < 10 * 240 && world.sleeping_body_count() < dynamic; ++ticks) sim->run_tick();
  EXPECT_EQ(world.sleeping_body_count(), dynamic) << "after " << ticks << " ticks";
  EXPECT_EQ(world.joint_count(), 30u);
  for (std::size_t i = 1; i < world.body_count(); ++i) {
    EXPECT_GT(world.position(world.body_id_at(i)).y(), 0.0) << scene.bodies(static_cast<int>(i)).name();
  }
}

INSTANTIATE_TEST_SUITE_P(SceneFile, ShippedScene,
                         ::testing::Values("demo.json", "playground.json", "pendulums.json", "chain.json",
                                           "ragdoll.json", "arm.json"),
                         [](const ::testing::TestParamInfo<const char*>& param_info) {
                           std::string name = param_info.param;
                           return name.substr(0, name.find('.'));
                         });

}  // namespace
}  // namespace tumble::sim
