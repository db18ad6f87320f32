// Engine: the small interface each compared physics engine implements. An
// engine builds its world from a Scene when it is created, advances it one
// step of kTimeStep at a time, and reports the poses of the scene's dynamic
// bodies so every measurement is taken the same way for every engine.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "scenes.h"

namespace tumble::bench {

// How every engine of a run is set up beyond the scene.
struct EngineOptions {
  // Each engine's own sleeping with its default thresholds: tumble's
  // sleep_enabled, Bullet's deactivation, ODE's auto-disable. Off, every body
  // is simulated every step.
  bool sleeping = true;
  // Threads tumble solves its contact islands on (World::set_thread_count);
  // Bullet and ODE always step on one.
  int tumble_threads = 1;
};

// Where a body is: centre of mass and orientation (body -> world), world frame.
struct Pose {
  Vec3 position = Vec3::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

class Engine {
 public:
  virtual ~Engine() = default;
  // Advances the world by kTimeStep: collision detection, solver, integration
  // and sleeping, everything the engine does in a step.
  virtual void step() = 0;
  // Poses of scene.bodies, in scene order; resizes poses to fit.
  virtual void read_poses(std::vector<Pose>& poses) const = 0;
  // Dynamic bodies not asleep (Bullet: active; ODE: enabled).
  virtual std::size_t awake_count() const = 0;
};

// The engine names, in the order they run by default: tumble, bullet, ode.
const std::vector<std::string>& engine_names();

// Builds the named engine's world for a scene; throws std::invalid_argument
// for a name not in engine_names().
std::unique_ptr<Engine> make_engine(std::string_view name, const Scene& scene, const EngineOptions& options);

// One per engine_*.cpp.
std::unique_ptr<Engine> make_tumble_engine(const Scene& scene, const EngineOptions& options);
std::unique_ptr<Engine> make_bullet_engine(const Scene& scene, const EngineOptions& options);
std::unique_ptr<Engine> make_ode_engine(const Scene& scene, const EngineOptions& options);

}  // namespace tumble::bench
