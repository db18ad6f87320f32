#include "scenes.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace tumble::bench {
namespace {

constexpr double kUnitMass = 1.0;
constexpr double kHalf = 0.5;  // half extent of a unit box, radius of the spheres

// A box of half extents h and mass m, unrotated at `position`.
DynamicBody box(const Vec3& half, double mass, const Vec3& position) {
  DynamicBody body;
  body.shape = BodyShape::box;
  body.half_extents = half;
  body.mass = mass;
  // Solid box: I_xx = m/3 (hy^2 + hz^2), and likewise for y and z.
  body.inertia = Vec3(half.y() * half.y() + half.z() * half.z(), half.x() * half.x() + half.z() * half.z(),
                      half.x() * half.x() + half.y() * half.y()) *
                 (mass / 3.0);
  body.position = position;
  return body;
}

DynamicBody unit_box(const Vec3& position) { return box(Vec3::Constant(kHalf), kUnitMass, position); }

DynamicBody unit_sphere(const Vec3& position) {
  DynamicBody body;
  body.shape = BodyShape::sphere;
  body.radius = kHalf;
  body.mass = kUnitMass;
  body.inertia = Vec3::Constant(0.4 * kUnitMass * kHalf * kHalf);  // 2/5 m r^2
  body.position = position;
  return body;
}

// pile: columns x columns columns of `height` unit boxes, 1.1 m apart in x, y
// and z, the lowest box 0.1 m above the ground. The columns fall 0.1 m,
// land, and stand side by side with 0.1 m gaps.
Scene pile(int columns, int height) {
  constexpr double kSpacing = 1.1;
  Scene scene;
  scene.name = "pile";
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < columns; ++x) {
      for (int z = 0; z < columns; ++z) {
        const double centre = 0.5 * (columns - 1);
        scene.bodies.push_back(
            unit_box(Vec3((x - centre) * kSpacing, kHalf + 0.1 + y * kSpacing, (z - centre) * kSpacing)));
      }
    }
  }
  return scene;
}

// pyramid: rows of base, base - 1, ..., 1 unit boxes in the plane z = 0,
// 5 cm apart within a row, each row centred on the one below and resting on
// it (the layout of the physics tests' pyramid). 210 boxes for base 20.
Scene pyramid(int base) {
  constexpr double kSpacing = 1.05;
  Scene scene;
  scene.name = "pyramid";
  for (int row = 0; row < base; ++row) {
    const int count = base - row;
    for (int k = 0; k < count; ++k) {
      scene.bodies.push_back(unit_box(Vec3((k - 0.5 * (count - 1)) * kSpacing, kHalf + row, 0.0)));
    }
  }
  return scene;
}

// Deterministic jitter in [-amplitude, amplitude]: a 32-bit linear
// congruential generator (Numerical Recipes constants), so every engine and
// every run gets the same layout without depending on <random>'s
// distributions, whose output is implementation-defined.
class Jitter {
 public:
  explicit Jitter(double amplitude) : amplitude_(amplitude) {}
  double next() {
    state_ = state_ * 1664525u + 1013904223u;
    const double unit = static_cast<double>(state_ >> 8) / static_cast<double>(1u << 24);  // [0, 1)
    return amplitude_ * (2.0 * unit - 1.0);
  }

 private:
  double amplitude_;
  std::uint32_t state_ = 12345u;
};

// spheres: columns x columns columns of `height` spheres of radius 0.5, 1.1 m
// apart, each moved by up to 5 cm in x and z so the columns topple into a
// pile, inside four static walls (0.5 m thick, 30 m tall) that leave a
// 1 m gap around the grid. The lowest sphere starts 0.1 m above the ground.
Scene spheres(int columns, int height) {
  constexpr double kSpacing = 1.1;
  Scene scene;
  scene.name = "spheres";
  Jitter jitter(0.05);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < columns; ++x) {
      for (int z = 0; z < columns; ++z) {
        const double centre = 0.5 * (columns - 1);
        const double dx = jitter.next();
        const double dz = jitter.next();
        scene.bodies.push_back(
            unit_sphere(Vec3((x - centre) * kSpacing + dx, kHalf + 0.1 + y * kSpacing, (z - centre) * kSpacing + dz)));
      }
    }
  }
  // Inner faces of the walls at +-(half the grid's width + 1 m).
  const double inner = 0.5 * columns * kSpacing + 1.0;
  constexpr double kThickness = 0.25;              // half thickness
  constexpr double kHeight = 15.0;                 // half height
  const double length = inner + 2.0 * kThickness;  // half length, overlapping at the corners
  scene.walls = {
      {Vec3(kThickness, kHeight, length), Vec3(inner + kThickness, kHeight, 0.0)},
      {Vec3(kThickness, kHeight, length), Vec3(-inner - kThickness, kHeight, 0.0)},
      {Vec3(length, kHeight, kThickness), Vec3(0.0, kHeight, inner + kThickness)},
      {Vec3(length, kHeight, kThickness), Vec3(0.0, kHeight, -inner - kThickness)},
  };
  return scene;
}

// landing: the world of net_load's cubes (bench/net/load_world.cpp), the
// server's heaviest stream benchmark: side x side cubes of 0.3 m and 1 kg,
// 0.4 m apart, dropped from 0.4, 0.95 or 1.5 m (neighbours differ) in
// tilted orientations that vary from cube to cube, and a level 1 m cube of
// 10 kg dropped from 2.3 m onto the middle. They land, tumble into each
// other and come to rest within about 2 s: every body is in the solver at
// once.
Scene landing(unsigned side) {
  Scene scene;
  scene.name = "landing";
  const double centre = 0.4 * (side - 1) / 2;
  for (unsigned i = 0; i < side * side; ++i) {
    const unsigned column = i % side;
    const unsigned row = i / side;
    DynamicBody body = box(Vec3::Constant(0.15), 1.0,
                           Vec3(0.4 * column - centre, 0.4 + 0.55 * ((column + row) % 3), 0.4 * row - centre));
    // The tilt of load_world.cpp's set_tilt: an angle of 0.3 to 1 rad about
    // an axis turned by the golden angle from cube to cube.
    const double angle = 0.3 + 0.7 * static_cast<double>((i * 37) % 100) / 100;
    const Vec3 axis(std::cos(i * 2.39996), 0.5, std::sin(i * 2.39996));
    body.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
    scene.bodies.push_back(body);
  }
  scene.bodies.push_back(box(Vec3::Constant(0.5), 10.0, Vec3(0.0, 2.3, 0.0)));
  return scene;
}

}  // namespace

const std::vector<std::string>& scene_names() {
  static const std::vector<std::string> names = {"pile", "pyramid", "spheres", "landing"};
  return names;
}

Scene make_scene(std::string_view name, bool smoke) {
  constexpr int kSmokeSteps = 10;
  Scene scene;
  if (name == "pile") {
    scene = smoke ? pile(3, 3) : pile(10, 10);
    scene.steps = 600;
  } else if (name == "pyramid") {
    scene = smoke ? pyramid(5) : pyramid(20);
    scene.steps = 600;
  } else if (name == "spheres") {
    scene = smoke ? spheres(4, 4) : spheres(20, 25);
    scene.steps = 300;
  } else if (name == "landing") {
    scene = smoke ? landing(4) : landing(30);
    scene.steps = 180;
  } else {
    throw std::invalid_argument("unknown scene: " + std::string(name));
  }
  if (smoke) scene.steps = kSmokeSteps;
  return scene;
}

}  // namespace tumble::bench
