// Fuzz target: the contents of a state file after its 16-byte magic (what
// read_state_file parses), as tumbled --state resumes from it. The bytes
// are parsed as a WorldState, restored with restore_world into a fresh
// physics World, and a world that restores is stepped a few times with its
// loads applied, as the simulation would.
#include <cstddef>
#include <cstdint>

#include "quiet_logs.h"
#include "sim/body_directory.h"
#include "sim/body_loads.h"
#include "sim/world_state.h"
#include "tumble/physics/world.h"
#include "tumble/v1/state.pb.h"

namespace {

// Steps run on a world that restores, at the default tick rate.
constexpr int kSteps = 8;
constexpr double kDt = 1.0 / 240;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) { return tumble::fuzz::silence_logs(); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tumble::v1::WorldState state;
  if (!state.ParseFromArray(data, static_cast<int>(size))) return 0;

  tumble::physics::World world;
  tumble::sim::BodyDirectory directory;
  tumble::sim::BodyLoads loads;
  if (!tumble::sim::restore_world(state, &world, &directory, &loads).ok()) return 0;
  for (int i = 0; i < kSteps; ++i) {
    loads.apply(world);
    world.step(kDt);
  }
  return 0;
}
