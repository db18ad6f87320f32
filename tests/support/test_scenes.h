// Scenes shared by the tests of the server.
#pragma once

#include <sstream>
#include <string>

namespace tumble::test {

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
