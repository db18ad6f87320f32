// Fuzz target: a whole state file, as tumbled --state reads it (either
// version: mutations of a version 1 seed reach the world checks, which a
// version 2 checksum keeps most mutations from). A file is either refused,
// or it is a valid world:
//  - every number of the world it builds is finite;
//  - the world is what the file says: the same clock, the same bodies in
//    the same order with the same ids, and each dynamic body's pose and
//    momenta to the bit;
//  - saved again and read back it builds a world that saves to the same
//    bytes (the round trip is exact).
// The world is then stepped a few ticks and must stay finite.
// A broken property aborts with what broke, which libFuzzer reports.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>

#include "quiet_logs.h"
#include "sim/simulation.h"
#include "sim/state_file.h"
#include "tumble/v1/state.pb.h"

namespace {

using tumble::v1::WorldState;

// Ticks a world that loads is stepped.
constexpr int kTicks = 8;
// Bigger worlds only repeat what small ones exercise, slower.
constexpr int kMaxBodies = 64;

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "state_fuzz: %s\n", what.c_str());
  std::abort();
}

bool finite(const tumble::v1::Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

bool same(const tumble::v1::Vec3& a, const tumble::v1::Vec3& b) {
  return a.x() == b.x() && a.y() == b.y() && a.z() == b.z();
}

// Every number a captured world holds is finite.
bool all_finite(const WorldState& state) {
  if (!std::isfinite(state.sim_time()) || !std::isfinite(state.tick_rate_hz()) || !finite(state.gravity())) {
    return false;
  }
  for (const auto& body : state.bodies()) {
    const auto& spec = body.spec();
    const auto& q = spec.orientation();
    if (!finite(spec.position()) || !finite(spec.linear_velocity()) || !finite(spec.angular_velocity()) ||
        !std::isfinite(q.w()) || !std::isfinite(q.x()) || !std::isfinite(q.y()) || !std::isfinite(q.z()) ||
        !std::isfinite(spec.mass()) || !finite(body.linear_momentum()) || !finite(body.angular_momentum()) ||
        !std::isfinite(body.sleep_time()) || !finite(body.rest_position()) || !std::isfinite(body.last_speed()) ||
        !std::isfinite(body.rise_start_speed()) || !std::isfinite(body.rest_orientation().w()) ||
        !std::isfinite(body.rest_orientation().x()) || !std::isfinite(body.rest_orientation().y()) ||
        !std::isfinite(body.rest_orientation().z())) {
      return false;
    }
  }
  for (const auto& load : state.loads()) {
    if (!finite(load.force()) || !finite(load.local_point()) || !finite(load.torque())) return false;
  }
  return true;
}

// The world `loaded` builds is the one `file` says.
bool matches_file(const WorldState& file, const WorldState& loaded) {
  if (loaded.tick() != file.tick() || loaded.paused() != file.paused() ||
      loaded.tick_rate_hz() != file.tick_rate_hz() || loaded.next_body_id() != file.next_body_id() ||
      loaded.bodies_size() != file.bodies_size() || loaded.loads_size() != file.loads_size()) {
    return false;
  }
  for (int i = 0; i < file.bodies_size(); ++i) {
    const auto& a = file.bodies(i);
    const auto& b = loaded.bodies(i);
    if (a.id() != b.id() || a.spec().name() != b.spec().name()) return false;
    if (b.spec().motion() != tumble::v1::MOTION_DYNAMIC) continue;
    if (!same(a.spec().position(), b.spec().position()) || !same(a.linear_momentum(), b.linear_momentum()) ||
        !same(a.angular_momentum(), b.angular_momentum())) {
      return false;
    }
  }
  return true;
}

// Builds the world of `state` into *sim, or says why not.
tumble::sim::Status build(const WorldState& state, std::unique_ptr<tumble::sim::Simulation>* sim) {
  tumble::sim::SimConfig config;
  config.max_bodies = kMaxBodies;
  return tumble::sim::Simulation::create_from_state(state, config, sim);
}

std::string saved(const tumble::sim::Simulation& sim) {
  WorldState state;
  sim.capture(&state);
  std::string bytes;
  if (!tumble::sim::encode_state_file(state, &bytes)) fail("a loaded world does not encode");
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) { return tumble::fuzz::silence_logs(); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  WorldState file;
  tumble::sim::StateFileFormat format{};
  if (!tumble::sim::parse_state_file(bytes, &file, &format).ok()) return 0;
  std::unique_ptr<tumble::sim::Simulation> sim;
  if (!build(file, &sim).ok()) return 0;

  WorldState loaded;
  sim->capture(&loaded);
  if (!all_finite(loaded)) fail("a loaded world holds a number that is not finite");
  if (!matches_file(file, loaded)) fail("a loaded world is not the one its file says");

  const std::string first = saved(*sim);
  WorldState again;
  if (auto status = tumble::sim::parse_state_file(first, &again, &format); !status.ok()) {
    fail("a saved world does not read back: " + status.message());
  }
  std::unique_ptr<tumble::sim::Simulation> rebuilt;
  if (auto status = build(again, &rebuilt); !status.ok())
    fail("a saved world does not load again: " + status.message());
  if (saved(*rebuilt) != first) fail("a saved world loads as another world");

  for (int i = 0; i < kTicks; ++i) sim->run_tick();
  WorldState stepped;
  sim->capture(&stepped);
  if (!all_finite(stepped)) fail("a loaded world stepped to a number that is not finite");
  return 0;
}
