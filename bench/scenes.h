// Scene layouts of the engine comparison. Each scene is described once here,
// engine-neutrally, and every engine builds its world from the same
// description, so the bodies, sizes, masses, inertias, positions, friction
// and time step are identical across engines.
//
// Every scene has a ground: the static plane y = 0, solid below. Units are
// SI, +Y is up.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace tumble::bench {

using Vec3 = Eigen::Vector3d;

inline constexpr double kTimeStep = 1.0 / 60.0;  // s, one step of every engine
inline constexpr double kGravity = 9.81;         // m/s^2, along -y
inline constexpr double kFriction = 0.5;         // Coulomb coefficient of every contact
inline constexpr int kSolverIterations = 10;     // Bullet's and ODE's solver iterations

enum class BodyShape { box, sphere };

// One dynamic body, starting at rest. A box uses half_extents, a sphere
// radius. inertia holds the principal moments about the centre of mass
// (kg m^2) of the uniform solid, along the body axes; orientation turns the
// body axes into the world's (unrotated unless a scene says otherwise).
struct DynamicBody {
  BodyShape shape = BodyShape::box;
  Vec3 half_extents = Vec3::Zero();
  double radius = 0;
  double mass = 0;
  Vec3 inertia = Vec3::Zero();
  Vec3 position = Vec3::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// A static, unrotated box (the walls of the spheres scene).
struct StaticBox {
  Vec3 half_extents = Vec3::Zero();
  Vec3 position = Vec3::Zero();
};

enum class JointType { ball, hinge };

// SceneJoint::body_a naming the world instead of a body.
inline constexpr int kWorld = -1;

// A joint between two dynamic bodies (indices into Scene::bodies), or
// between the world (body_a = kWorld) and a body, as it is at the start:
// anchor and axis are a world point and a world direction at the bodies'
// starting poses. Each engine fixes them to the bodies there.
//   ball   anchors coincide; with a cone, the angle between the axis as
//          fixed to body_a and as fixed to body_b stays within cone
//   hinge  anchors coincide and the axes stay aligned; the angle of body_b
//          about the axis relative to body_a (0 at the start, positive
//          counter-clockwise about the axis) stays within [lower, upper]
struct SceneJoint {
  JointType type = JointType::ball;
  int body_a = kWorld;
  int body_b = 0;
  Vec3 anchor = Vec3::Zero();
  Vec3 axis = Vec3::UnitX();                              // unit
  double cone = std::numeric_limits<double>::infinity();  // rad, ball only; infinity: none
  double lower = 0;                                       // rad, hinge only
  double upper = 0;                                       // rad, hinge only
};

// Everything an engine builds, plus the number of steps to run. Bodies a
// joint connects do not collide with each other in any engine.
struct Scene {
  std::string name;
  std::vector<DynamicBody> bodies;
  std::vector<StaticBox> walls;
  std::vector<SceneJoint> joints;
  int steps = 0;
};

// A world point in a body's frame (relative to its centre of mass) at the
// body's starting pose.
Vec3 body_point(const DynamicBody& body, const Vec3& world_point);

// The scene names, in the order they run by default: pile, pyramid, spheres,
// landing, chain, ragdolls.
const std::vector<std::string>& scene_names();

// Builds a named scene (one of scene_names()). smoke gives a small version of
// it (a few dozen bodies, 10 steps) for a quick check that everything runs.
Scene make_scene(std::string_view name, bool smoke);

}  // namespace tumble::bench
