// Fuzz target: a scene file as tumbled --scene reads it. The text is parsed
// with parse_scene_json; a scene that parses has each body checked with
// body_desc_from_spec, and is built into a Simulation that then runs a few
// ticks, so that whatever the checks let through is also stepped.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "quiet_logs.h"
#include "sim/body_spec.h"
#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "tumble/v1/scene.pb.h"

namespace {

// Steps run on a scene that loads.
constexpr int kTicks = 8;

// Bigger scenes only repeat what small ones exercise, slower.
constexpr int kMaxBodies = 64;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) { return tumble::fuzz::silence_logs(); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  tumble::v1::Scene scene;
  if (!tumble::sim::parse_scene_json(text, &scene).ok()) return 0;

  for (int i = 0; i < scene.bodies_size(); ++i) {
    tumble::physics::BodyDesc desc;
    (void)tumble::sim::body_desc_from_spec(scene.bodies(i), "bodies[" + std::to_string(i) + "]", &desc);
  }

  tumble::sim::SimConfig config;
  config.max_bodies = kMaxBodies;
  std::unique_ptr<tumble::sim::Simulation> sim;
  if (!tumble::sim::Simulation::create(scene, config, &sim).ok()) return 0;
  for (int i = 0; i < kTicks; ++i) sim->run_tick();
  return 0;
}
