#include "scenes.h"

#include <cmath>
#include <cstdint>
#include <numbers>
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

// A sphere of `radius` and `mass` at `position`.
DynamicBody sphere(double radius, double mass, const Vec3& position) {
  DynamicBody body;
  body.shape = BodyShape::sphere;
  body.radius = radius;
  body.mass = mass;
  body.inertia = Vec3::Constant(0.4 * mass * radius * radius);  // 2/5 m r^2
  body.position = position;
  return body;
}

DynamicBody unit_sphere(const Vec3& position) { return sphere(kHalf, kUnitMass, position); }

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

// A ball joint without a cone.
SceneJoint ball(int body_a, int body_b, const Vec3& anchor) {
  SceneJoint joint;
  joint.type = JointType::ball;
  joint.body_a = body_a;
  joint.body_b = body_b;
  joint.anchor = anchor;
  return joint;
}

// chain: `chains` chains 1 m apart in z, each of `links` boxes 0.25 m long
// (1 kg) and a 0.4 m cube of 100 kg at the end. Each hangs from the world by
// a ball joint at its first link's end, 15 m up, and ball joints join every
// two neighbours at the ends they share. They start horizontal (along +x)
// and at rest, and swing down: the weight, 100 times a link's mass, pulls
// every joint apart, hardest at the bottom of the swing. Hanging straight,
// a chain of 40 links leaves its weight 4.6 m above the ground, which it
// reaches only if its joints give that much.
Scene chain(int chains, int links) {
  constexpr double kLinkHalfLength = 0.125;  // along x
  constexpr double kLinkHalfWidth = 0.03;    // in y and z
  constexpr double kLinkMass = 1.0;
  constexpr double kWeightHalf = 0.2;
  constexpr double kWeightMass = 100.0 * kLinkMass;
  constexpr double kHeight = 15.0;  // of the chains' top joints
  Scene scene;
  scene.name = "chain";
  for (int c = 0; c < chains; ++c) {
    const double z = c - 0.5 * (chains - 1);
    int previous = kWorld;
    for (int i = 0; i <= links; ++i) {
      const double start = 2 * kLinkHalfLength * i;  // x of the joint with the previous link (or the world)
      if (i < links) {
        scene.bodies.push_back(box(Vec3(kLinkHalfLength, kLinkHalfWidth, kLinkHalfWidth), kLinkMass,
                                   Vec3(start + kLinkHalfLength, kHeight, z)));
      } else {
        scene.bodies.push_back(box(Vec3::Constant(kWeightHalf), kWeightMass, Vec3(start + kWeightHalf, kHeight, z)));
      }
      const int body = static_cast<int>(scene.bodies.size()) - 1;
      scene.joints.push_back(ball(previous, body, Vec3(start, kHeight, z)));
      previous = body;
    }
  }
  return scene;
}

// Adds one ragdoll of 11 bodies and 10 joints, built standing in its own
// frame (feet at y = 0, facing +z, arms stretched out along x, 75 kg)
// and placed lying on its back: its frame turned by `turn` and the point
// between its hips (1 m up) moved to `centre`. Neighbouring parts are
// joined a few centimetres apart, so no two parts overlap at the start.
// Joints: ball joints with cones at the spine (pelvis to torso), neck and
// shoulders (torso to head and upper arms) and hips (pelvis to upper legs),
// the cones about the child bone's direction; hinges at the elbows (0 to
// 2.4 rad, the forearm folding forward) and knees (0 to 2.4 rad, the shin
// folding back).
void add_ragdoll(Scene& scene, const Eigen::Quaterniond& turn, const Vec3& centre) {
  const Vec3 origin(0, 1.0, 0);  // the ragdoll's frame point that goes to `centre`
  const auto place = [&](const Vec3& point) { return Vec3(centre + turn * (point - origin)); };
  const auto add = [&](DynamicBody body) {
    body.position = place(body.position);
    body.orientation = turn;
    scene.bodies.push_back(body);
    return static_cast<int>(scene.bodies.size()) - 1;
  };
  const int pelvis = add(box(Vec3(0.16, 0.08, 0.1), 10.0, Vec3(0, 1.04, 0)));
  const int torso = add(box(Vec3(0.17, 0.21, 0.1), 25.0, Vec3(0, 1.37, 0)));
  const int head = add(sphere(0.11, 5.0, Vec3(0, 1.73, 0)));
  const auto add_ball = [&](int parent, int child, const Vec3& anchor, const Vec3& axis, double cone) {
    SceneJoint joint = ball(parent, child, place(anchor));
    joint.axis = turn * axis;
    joint.cone = cone;
    scene.joints.push_back(joint);
  };
  const auto add_hinge = [&](int parent, int child, const Vec3& anchor, const Vec3& axis) {
    SceneJoint joint;
    joint.type = JointType::hinge;
    joint.body_a = parent;
    joint.body_b = child;
    joint.anchor = place(anchor);
    joint.axis = turn * axis;
    joint.lower = 0;
    joint.upper = 2.4;
    scene.joints.push_back(joint);
  };
  add_ball(pelvis, torso, Vec3(0, 1.14, 0), Vec3::UnitY(), 0.5);
  add_ball(torso, head, Vec3(0, 1.60, 0), Vec3::UnitY(), 0.7);
  for (const double side : {-1.0, 1.0}) {
    const int upper_arm = add(box(Vec3(0.13, 0.05, 0.05), 2.5, Vec3(side * 0.36, 1.52, 0)));
    const int lower_arm = add(box(Vec3(0.12, 0.045, 0.045), 2.0, Vec3(side * 0.64, 1.52, 0)));
    const int upper_leg = add(box(Vec3(0.07, 0.21, 0.07), 8.0, Vec3(side * 0.1, 0.71, 0)));
    const int lower_leg = add(box(Vec3(0.06, 0.21, 0.06), 5.0, Vec3(side * 0.1, 0.25, 0)));
    add_ball(torso, upper_arm, Vec3(side * 0.2, 1.52, 0), Vec3(side, 0, 0), 1.3);
    // About -y on the right (+x) and +y on the left, a positive angle
    // swings the forearm forward (+z) on both sides.
    add_hinge(upper_arm, lower_arm, Vec3(side * 0.5, 1.52, 0), Vec3(0, -side, 0));
    add_ball(pelvis, upper_leg, Vec3(side * 0.1, 0.94, 0), -Vec3::UnitY(), 1.0);
    // A positive angle about +x swings the foot back (-z).
    add_hinge(upper_leg, lower_leg, Vec3(side * 0.1, 0.48, 0), Vec3::UnitX());
  }
}

// ragdolls: columns x columns columns of `layers` ragdolls (add_ragdoll)
// lying on their backs, 1.4 m apart, each turned about the vertical by the
// golden angle from the one before. Within a column they lie 0.6 m apart,
// the lowest 0.3 m up; every other column is 0.3 m higher, so neighbouring
// columns, which reach over each other, interleave without touching (a
// ragdoll is 0.22 m thick and reaches at most 0.98 m from its centre, and
// columns at the same heights are 1.98 m apart). They fall onto each other
// into one heap.
Scene ragdolls(int columns, int layers) {
  constexpr double kSpacing = 1.4;
  Scene scene;
  scene.name = "ragdolls";
  const Eigen::Quaterniond on_back(Eigen::AngleAxisd(-0.5 * std::numbers::pi, Vec3::UnitX()));  // facing +y
  int count = 0;
  for (int layer = 0; layer < layers; ++layer) {
    for (int x = 0; x < columns; ++x) {
      for (int z = 0; z < columns; ++z) {
        const double centre = 0.5 * (columns - 1);
        const double height = 0.3 + 0.6 * layer + 0.3 * ((x + z) % 2);
        const Eigen::Quaterniond yaw(Eigen::AngleAxisd(2.39996 * count++, Vec3::UnitY()));
        add_ragdoll(scene, yaw * on_back, Vec3((x - centre) * kSpacing, height, (z - centre) * kSpacing));
      }
    }
  }
  return scene;
}

}  // namespace

Vec3 body_point(const DynamicBody& body, const Vec3& world_point) {
  return body.orientation.conjugate() * (world_point - body.position);
}

const std::vector<std::string>& scene_names() {
  static const std::vector<std::string> names = {"pile", "pyramid", "spheres", "landing", "chain", "ragdolls"};
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
  } else if (name == "chain") {
    scene = smoke ? chain(2, 5) : chain(20, 40);
    scene.steps = 600;
  } else if (name == "ragdolls") {
    scene = smoke ? ragdolls(2, 2) : ragdolls(5, 4);
    scene.steps = 300;
  } else {
    throw std::invalid_argument("unknown scene: " + std::string(name));
  }
  if (smoke) scene.steps = kSmokeSteps;
  return scene;
}

}  // namespace tumble::bench
