// Scene files: defaults, strictness, and error messages that name the field.
#include <gtest/gtest.h>

#include <memory>

#include "sim/scene_file.h"
#include "sim/simulation.h"

namespace tumble::sim {
namespace {

Status parse(const std::string& json, tumble::v1::Scene* scene) { return parse_scene_json(json, scene); }

// The message of creating a simulation from `json`, or "" when it loads.
std::string load_error(const std::string& json) {
  tumble::v1::Scene scene;
  if (Status status = parse(json, &scene); !status.ok()) return status.message();
  std::unique_ptr<Simulation> sim;
  Status status = Simulation::create(scene, SimConfig{}, &sim);
  return status.ok() ? "" : status.message();
}

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

TEST(SceneFile, ErrorsNameTheField) {
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"box": {"half_extents": [1, 1]}}, "mass": 1}]})"),
            "bodies[0].shape.box.half_extents: expected an array of 3 numbers [x, y, z]");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": -1}]})"),
            "bodies[0].mass: must be a positive finite number");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 1},
                                      {"shape": {"sphere": {"radius": 0}}, "mass": 1}]})"),
            "bodies[1].shape.sphere.radius: must be a positive finite number");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"sphere": {"radius": 1}}, "mass": 1, "colour": "red"}]})"),
            "bodies[0]: unknown field 'colour'");
  EXPECT_EQ(load_error(R"({"bodies": [{"mass": 1}]})"), "bodies[0]: missing field 'shape'");
  EXPECT_EQ(load_error(R"({"bodies": [{"shape": {"cube": {}}, "mass": 1}]})"),
            "bodies[0].shape: unknown field 'cube'");
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
  EXPECT_EQ(load_error(R"({"gravity": [0, "down", 0]})"), "gravity[1]: expected a number");
}

TEST(SceneFile, NotJsonSaysWhere) {
  tumble::v1::Scene scene;
  const Status status = parse("{\"bodies\": [}", &scene);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("not valid JSON"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("line 1"), std::string::npos) << status.message();
}

TEST(SceneFile, MissingFileNamesThePath) {
  tumble::v1::Scene scene;
  const Status status = load_scene_file("/nonexistent/world.json", &scene);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.message(), "/nonexistent/world.json: cannot open the file");
}

TEST(SceneFile, TheShippedDemoSceneLoads) {
  tumble::v1::Scene scene;
  const Status status = load_scene_file(TUMBLE_SCENES_DIR "/demo.json", &scene);
  ASSERT_TRUE(status.ok()) << status.message();
  std::unique_ptr<Simulation> sim;
  const Status created = Simulation::create(scene, SimConfig{}, &sim);
  ASSERT_TRUE(created.ok()) << created.message();
  EXPECT_GE(sim->body_count(), 1u);
}

}  // namespace
}  // namespace tumble::sim
