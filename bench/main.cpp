// physics_compare: runs the same scenes in tumble, Bullet and ODE and prints,
// per scene and engine, the median wall time of a step, how deep bodies
// sank into the ground and into each other, and, in scenes with joints, how
// far the joints came apart. See README.md.
//
// The engines of a scene run in lockstep: every engine advances one step,
// then every engine the next, in an order that rotates from step to step, so
// a burst of load from elsewhere on the machine lands on all of them alike.
// Each step is timed alone with steady_clock; reading the poses and
// measuring penetration after it are not timed.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "engine.h"
#include "joint_separation.h"
#include "penetration.h"
#include "scenes.h"

namespace tumble::bench {
namespace {

// One engine's measurements over every step of every repetition of a scene.
struct EngineResult {
  std::string engine;
  std::vector<double> step_ms;   // wall time of each step
  Penetration worst;             // deepest overlaps after any step
  Penetration end;               // overlaps after the last step
  std::size_t below_ground = 0;  // after the last step
  std::size_t awake = 0;         // after the last step
  double worst_separation = 0;   // largest joint separation after any step (m)
  double end_separation = 0;     // after the last step
};

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  // Even count: the mean of the two middle values; the lower one is the
  // largest of the lower half.
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid)));
}

double mean(const std::vector<double>& values) {
  return values.empty() ? 0 : std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

// Runs one scene in every engine, `repetitions` times, in lockstep.
std::vector<EngineResult> run_scene(const Scene& scene, const std::vector<std::string>& engines,
                                    const EngineOptions& options, int repetitions) {
  std::vector<EngineResult> results(engines.size());
  for (std::size_t e = 0; e < engines.size(); ++e) {
    results[e].engine = engines[e];
    results[e].step_ms.reserve(static_cast<std::size_t>(scene.steps) * static_cast<std::size_t>(repetitions));
  }
  std::vector<Pose> poses;
  for (int rep = 0; rep < repetitions; ++rep) {
    std::vector<std::unique_ptr<Engine>> worlds;
    std::vector<PenetrationProbe> probes;
    const JointSeparationProbe joints(scene);
    for (const std::string& name : engines) {
      worlds.push_back(make_engine(name, scene, options));
      probes.emplace_back(scene);
    }
    const std::size_t count = worlds.size();
    for (int step = 0; step < scene.steps; ++step) {
      for (std::size_t k = 0; k < count; ++k) {
        // Rotate the order with the step (and the repetition) so no engine
        // always follows the same one.
        const std::size_t e = (k + static_cast<std::size_t>(step + rep)) % count;
        const auto start = std::chrono::steady_clock::now();
        worlds[e]->step();
        const auto stop = std::chrono::steady_clock::now();
        results[e].step_ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());

        worlds[e]->read_poses(poses);
        const Penetration now = probes[e].measure(poses);
        results[e].worst.ground = std::max(results[e].worst.ground, now.ground);
        results[e].worst.bodies = std::max(results[e].worst.bodies, now.bodies);
        const double separation = joints.measure(poses);
        results[e].worst_separation = std::max(results[e].worst_separation, separation);
        if (step + 1 == scene.steps) {
          results[e].end = now;
          results[e].end_separation = separation;
          results[e].below_ground = count_below_ground(poses);
          results[e].awake = worlds[e]->awake_count();
        }
      }
    }
  }
  return results;
}

// Keeps the first occurrence of each name, in order.
std::vector<std::string> without_repeats(const std::vector<std::string>& names) {
  std::vector<std::string> unique;
  for (const std::string& name : names) {
    if (std::find(unique.begin(), unique.end(), name) == unique.end()) unique.push_back(name);
  }
  return unique;
}

int run(int argc, char** argv) {
  CLI::App app{
      "Runs the same rigid-body scenes in tumble, Bullet and ODE at 60 steps per second on one thread (tumble "
      "on --tumble-threads), and "
      "prints per scene and engine the median ms per step, the deepest penetration, the bodies that "
      "fell through the ground and the largest joint separation."};
  std::vector<std::string> scenes = scene_names();
  std::vector<std::string> engines = engine_names();
  int steps = 0;
  int repetitions = 1;
  bool smoke = false;
  bool no_sleep = false;
  int tumble_threads = 1;
  app.add_option("--scene", scenes, "Scenes to run, repeatable or comma-separated; all when absent")
      ->delimiter(',')
      ->check(CLI::IsMember(scene_names()));
  app.add_option("--engine", engines, "Engines to run, repeatable or comma-separated; all when absent")
      ->delimiter(',')
      ->check(CLI::IsMember(engine_names()));
  app.add_option("--steps", steps, "Steps per scene instead of the scene's own count")
      ->check(CLI::Range(1, 1000000))
      ->type_name("N");
  app.add_option("--repetitions", repetitions, "Runs of each scene; the median is over every step of every run")
      ->check(CLI::Range(1, 1000000))
      ->type_name("R");
  app.add_flag("--smoke", smoke, "Small scenes and 10 steps: a quick check that everything runs");
  app.add_flag("--no-sleep", no_sleep, "Turn sleeping off in every engine: every body is simulated every step");
  app.add_option("--tumble-threads", tumble_threads,
                 "Threads tumble solves its contact islands on (Bullet and ODE always use one)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str()
      ->type_name("N");
  CLI11_PARSE(app, argc, argv);

  EngineOptions options;
  options.sleeping = !no_sleep;
  options.tumble_threads = tumble_threads;
  bool all_finite = true;
  for (const std::string& name : without_repeats(scenes)) {
    Scene scene = make_scene(name, smoke);
    if (steps > 0) scene.steps = steps;
    std::fprintf(stderr,
                 "# %s: %zu bodies, %zu walls, %zu joints, %d steps of %.4f s, %d repetition(s), sleeping %s, tumble "
                 "on %d thread(s)\n",
                 scene.name.c_str(), scene.bodies.size(), scene.walls.size(), scene.joints.size(), scene.steps,
                 kTimeStep, repetitions, options.sleeping ? "on" : "off", options.tumble_threads);
    for (const EngineResult& result : run_scene(scene, without_repeats(engines), options, repetitions)) {
      const double worst = std::max(result.worst.ground, result.worst.bodies);
      all_finite = all_finite && std::isfinite(worst) && std::isfinite(result.worst_separation);
      std::printf(
          "scene=%s engine=%s ms_per_step=%.4f max_penetration=%.4f below_ground=%zu mean_ms_per_step=%.4f "
          "ground_penetration=%.4f body_penetration=%.4f end_penetration=%.4f awake_end=%zu",
          scene.name.c_str(), result.engine.c_str(), median(result.step_ms), worst, result.below_ground,
          mean(result.step_ms), result.worst.ground, result.worst.bodies,
          std::max(result.end.ground, result.end.bodies), result.awake);
      // Scenes without joints keep the line they always had.
      if (!scene.joints.empty()) {
        std::printf(" max_joint_separation=%.4f end_joint_separation=%.4f", result.worst_separation,
                    result.end_separation);
      }
      std::printf("\n");
      std::fflush(stdout);
    }
  }
  // A body with a non-finite pose means an engine blew up: fail, so the smoke
  // test catches it.
  return all_finite ? 0 : 1;
}

}  // namespace
}  // namespace tumble::bench

int main(int argc, char** argv) { return tumble::bench::run(argc, argv); }
