// Scenes shared by the tests of the server.
#pragma once

#include <sstream>
#include <string>

namespace tumble::test {

// A 2 kg crate (a 1 m cube) at the origin, in zero gravity: it stays where
// it is until a client pushes it.
inline constexpr const char* kCrateScene = R"({"gravity": [0, 0, 0], "bodies": [
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2}]})";

// kCrateScene with a 1 kg ball of radius 0.5 m at x = 3 m beside it.
inline constexpr const char* kCrateAndBallScene = R"({"gravity": [0, 0, 0], "bodies": [
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2},
    {"name": "ball", "shape": {"sphere": {"radius": 0.5}}, "mass": 1, "position": [3, 0, 0]}]})";

// The crate under the default gravity, with no ground: it falls for ever.
inline constexpr const char* kFallingCrateScene =
    R"({"bodies": [{"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 2}]})";

// `count` spheres of 1 kg in a row 3 m apart, in zero gravity: big frames
// and body lists, and nothing for the physics to collide.
inline std::string row_of_spheres(int count) {
  std::ostringstream scene;
  scene << R"({"gravity": [0, 0, 0], "bodies": [)";
  for (int i = 0; i < count; ++i) {
    scene << (i ? "," : "") << R"({"name": "s)" << i << R"(", "shape": {"sphere": {"radius": 0.5}}, "mass": 1,)"
          << R"( "position": [)" << 3 * i << ", 0, 0]}";
  }
  scene << "]}";
  return scene.str();
}

}  // namespace tumble::test
