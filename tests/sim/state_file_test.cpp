// State files of version 2: every truncation and every single-byte change
// of a saved world is refused or gives the very same world; each kind of
// damage is named; version 1 still reads; a write keeps the file it
// replaces as <file>.prev, and a start falls back to it when <file> is
// damaged, keeping the damaged file as evidence.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "sim/scene_file.h"
#include "sim/simulation.h"
#include "sim/state_file.h"
#include "sim/state_resume.h"
#include "sim/world_state.h"
#include "temp_dir.h"

namespace tumble::sim {
namespace {

namespace fs = std::filesystem;

// A small world with a body of each kind, a load and some history.
tumble::v1::WorldState small_world(int ticks = 30) {
  tumble::v1::Scene scene;
  EXPECT_TRUE(parse_scene_json(R"({"bodies": [
    {"name": "ground", "static": true, "shape": {"plane": {}}},
    {"name": "crate", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 1, "position": [0, 3.5, 0]},
    {"name": "ball", "shape": {"sphere": {"radius": 0.3}}, "mass": 2, "position": [3, 1, 0],
     "angular_velocity": [1, 2, 3]}]})",
                               &scene)
                  .ok());
  std::unique_ptr<Simulation> sim;
  EXPECT_TRUE(Simulation::create(scene, SimConfig{}, &sim).ok());
  tumble::v1::ClientMessage force;
  force.mutable_apply_force()->mutable_body()->set_name("ball");
  force.mutable_apply_force()->mutable_force()->set_x(1);
  force.mutable_apply_force()->set_persistent(true);
  sim->submit(Command{force, nullptr, nullptr});
  for (int i = 0; i < ticks; ++i) sim->run_tick();
  tumble::v1::WorldState state;
  sim->capture(&state);
  return state;
}

std::string encoded(const tumble::v1::WorldState& state) {
  std::string bytes;
  EXPECT_TRUE(encode_state_file(state, &bytes));
  return bytes;
}

// The error parse_state_file gives `bytes`, or "" when it accepts them.
std::string state_file_error(std::string_view bytes, tumble::v1::WorldState* state = nullptr) {
  tumble::v1::WorldState read;
  StateFileFormat format{};
  const Status status = parse_state_file(bytes, state != nullptr ? state : &read, &format);
  return status.message();
}

// What an error is about: its words up to the first ':' or '('.
std::string kind_of(const std::string& error) { return error.substr(0, error.find_first_of(":(")); }

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

std::string read_bytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

TEST(StateFile, EveryTruncationIsRefused) {
  const tumble::v1::WorldState original = small_world();
  const std::string bytes = encoded(original);
  ASSERT_EQ(state_file_error(bytes), "");
  std::map<std::string, int> kinds;
  for (std::size_t size = 0; size < bytes.size(); ++size) {
    const std::string error = state_file_error(std::string_view(bytes).substr(0, size));
    ASSERT_NE(error, "") << "cut to " << size << " of " << bytes.size() << " bytes, the file was accepted";
    ++kinds[kind_of(error)];
  }
  // Cut inside the magic, before the length ends, then anywhere after.
  EXPECT_EQ(kinds["the file is empty"], 1);
  EXPECT_EQ(kinds["cut short inside its magic "], 15);
  EXPECT_EQ(kinds["cut short"], static_cast<int>(bytes.size()) - 16);
  EXPECT_EQ(kinds.size(), 3u);
}

TEST(StateFile, EverySingleByteChangeIsRefusedOrGivesTheSameWorld) {
  const tumble::v1::WorldState original = small_world();
  const std::string bytes = encoded(original);
  const std::size_t payload_end = bytes.size() - 4;
  std::map<std::string, int> kinds;
  int changes = 0;
  int accepted = 0;     // as the same world
  int other_world = 0;  // as another world: what the checks are for
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    for (int value = 0; value < 256; ++value) {
      if (static_cast<char>(value) == bytes[at]) continue;
      ++changes;
      std::string damaged = bytes;
      damaged[at] = static_cast<char>(value);
      tumble::v1::WorldState read;
      const std::string error = state_file_error(damaged, &read);
      if (error.empty()) {
        ++(read.SerializeAsString() == original.SerializeAsString() ? accepted : other_world);
        continue;
      }
      ++kinds[kind_of(error)];
      // A change in the payload or the stored checksum is a checksum failure.
      if (at >= 24) {
        EXPECT_EQ(kind_of(error), "bad checksum") << "byte " << at << " set to " << value;
      }
    }
  }
  EXPECT_EQ(other_world, 0) << "of " << changes << " single-byte changes";
  EXPECT_EQ(accepted, 0);
  EXPECT_EQ(kinds["bad checksum"], static_cast<int>(payload_end - 24 + 4) * 255);
  // The one change of the magic that makes a version 1 magic is caught too.
  EXPECT_EQ(kinds["its magic says version 1 but the rest is a version 2 file"], 1);
  EXPECT_EQ(kinds["not a tumble state file "], 16 * 255 - 1);
  // A length changed in any of its 8 bytes no longer fits the file.
  EXPECT_EQ(kinds["cut short"] + kinds["too long"] + kinds["bad length"], 8 * 255);
}

TEST(StateFile, EachKindOfDamageIsNamed) {
  const std::string bytes = encoded(small_world());
  EXPECT_EQ(state_file_error("tumble-state-v2\n"), "cut short: 16 bytes end before its 8-byte payload length");
  EXPECT_EQ(state_file_error("tumble-state-v1\n"), "nothing after its magic: the file holds no world");
  EXPECT_EQ(state_file_error("tumble-s"), "cut short inside its magic (8 bytes)");
  EXPECT_EQ(state_file_error(bytes + "x"), "too long: " + std::to_string(bytes.size() + 1) +
                                               " bytes, where its length field makes " + std::to_string(bytes.size()));
  std::string huge = bytes;
  huge[16 + 7] = '\x01';  // the length's top byte
  EXPECT_EQ(state_file_error(huge), "bad length: its length field says " +
                                        std::to_string((std::uint64_t{1} << 56) + (bytes.size() - 28)) +
                                        " bytes, more than the 1 GiB a state file may hold");
  std::string flipped = bytes;
  flipped[40] ^= 0x01;
  EXPECT_EQ(state_file_error(flipped).substr(0, 40), "bad checksum: the payload's CRC32C is 0x");
  EXPECT_NE(state_file_error(flipped).find("(the file is damaged)"), std::string::npos);

  // A payload that is whole and checksummed but not a world state.
  tumble::v1::WorldState no_version;
  no_version.set_tick(5);
  EXPECT_EQ(state_file_error(encoded(no_version)), "the payload holds no world state (it has no format_version)");
  tumble::v1::WorldState future;
  future.set_format_version(9);
  EXPECT_EQ(state_file_error(encoded(future)), "the payload is a world state of format 9; this tumbled reads format 1");
}

TEST(StateFile, AVersion1FileStillReads) {
  TempDir dir;
  const tumble::v1::WorldState original = small_world();
  write_bytes(dir.file("old.state"), "tumble-state-v1\n" + original.SerializeAsString());
  tumble::v1::WorldState read;
  bool exists = false;
  StateFileFormat format = StateFileFormat::v2;
  const Status status = read_state_file(dir.file("old.state"), &read, &exists, &format);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(format, StateFileFormat::v1);
  EXPECT_EQ(read.SerializeAsString(), original.SerializeAsString());
}

TEST(StateFile, AWriteKeepsTheFileItReplacesAsPrev) {
  TempDir dir;
  const std::string path = dir.file("world.state");
  tumble::v1::WorldState state = small_world();
  state.set_tick(1);
  ASSERT_TRUE(write_state_file(path, state).ok());
  EXPECT_FALSE(fs::exists(path + ".prev"));
  state.set_tick(2);
  ASSERT_TRUE(write_state_file(path, state).ok());
  state.set_tick(3);
  ASSERT_TRUE(write_state_file(path, state).ok());
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  tumble::v1::WorldState read;
  bool exists = false;
  ASSERT_TRUE(read_state_file(path, &read, &exists).ok());
  EXPECT_EQ(read.tick(), 3u);
  ASSERT_TRUE(read_state_file(path + ".prev", &read, &exists).ok());
  EXPECT_EQ(read.tick(), 2u);
}

// A start from <path>: resume_state with a world built from what it accepts.
struct Resumption {
  Status status;
  ResumedState resumed;
  std::uint64_t built_tick = 0;  // the tick of the world accepted
};

Resumption start(const std::string& path) {
  Resumption result;
  const auto build = [&](const tumble::v1::WorldState& state) {
    std::unique_ptr<Simulation> sim;
    Status status = Simulation::create_from_state(state, SimConfig{}, &sim);
    if (status.ok()) result.built_tick = sim->tick();
    return status;
  };
  result.status = resume_state(path, build, &result.resumed);
  return result;
}

// Saves the small world at tick 30 and then at tick 60: <path> holds tick
// 60 and <path>.prev tick 30.
void save_twice(const std::string& path) {
  ASSERT_TRUE(write_state_file(path, small_world(30)).ok());
  ASSERT_TRUE(write_state_file(path, small_world(60)).ok());
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& line : lines) out += line + "\n";
  return out;
}

TEST(StateResume, AGoodFileIsResumedAndNothingIsRenamed) {
  TempDir dir;
  const std::string path = dir.file("world.state");
  save_twice(path);
  const Resumption result = start(path);
  ASSERT_TRUE(result.status.ok()) << result.status.message();
  EXPECT_TRUE(result.resumed.resumed);
  EXPECT_EQ(result.resumed.from, path);
  EXPECT_EQ(result.built_tick, 60u);
  EXPECT_TRUE(result.resumed.warnings.empty()) << joined(result.resumed.warnings);
  EXPECT_FALSE(fs::exists(path + ".damaged"));
}

TEST(StateResume, ADamagedFileFallsBackToPrevAndIsKeptAsEvidence) {
  TempDir dir;
  const std::string path = dir.file("world.state");
  save_twice(path);
  std::string bytes = read_bytes(path);
  bytes[bytes.size() / 2] ^= 0x40;
  write_bytes(path, bytes);
  write_bytes(path + ".damaged", "an earlier damaged file");

  const Resumption result = start(path);
  ASSERT_TRUE(result.status.ok()) << result.status.message();
  EXPECT_EQ(result.resumed.from, path + ".prev");
  EXPECT_EQ(result.resumed.tick, 30u);
  EXPECT_EQ(result.built_tick, 30u);
  ASSERT_EQ(result.resumed.warnings.size(), 1u);
  const std::string& warning = result.resumed.warnings[0];
  EXPECT_EQ(warning.rfind("THE STATE FILE IS DAMAGED: " + path + ": bad checksum", 0), 0u) << warning;
  EXPECT_NE(warning.find("saved at tick 30"), std::string::npos) << warning;
  EXPECT_NE(warning.find("kept as " + path + ".damaged.1"), std::string::npos) << warning;
  // The evidence is kept, the earlier one too; the good file stays in place.
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(read_bytes(path + ".damaged.1"), bytes);
  EXPECT_EQ(read_bytes(path + ".damaged"), "an earlier damaged file");
  EXPECT_TRUE(fs::exists(path + ".prev"));
}

TEST(StateResume, AStateThatDoesNotBuildAWorldCountsAsDamaged) {
  TempDir dir;
  const std::string path = dir.file("world.state");
  save_twice(path);
  tumble::v1::WorldState bad = small_world(60);
  bad.set_tick_rate_hz(0);
  write_bytes(path, encoded(bad));
  const Resumption result = start(path);
  ASSERT_TRUE(result.status.ok()) << result.status.message();
  EXPECT_EQ(result.built_tick, 30u);
  ASSERT_FALSE(result.resumed.warnings.empty());
  EXPECT_NE(result.resumed.warnings[0].find(path + ": tick_rate_hz: must be from 1 to 10000 Hz"), std::string::npos)
      << result.resumed.warnings[0];
}

TEST(StateResume, BothDamagedIsAnErrorGivingBothReasonsAndRenamesNothing) {
  TempDir dir;
  const std::string path = dir.file("world.state");
  save_twice(path);
  write_bytes(path, "tumble-state-v2\n");
  const std::string prev = read_bytes(path + ".prev");
  write_bytes(path + ".prev", prev.substr(0, prev.size() - 1));
  const Resumption result = start(path);
  EXPECT_EQ(result.status.message(),
            path +
                ": cut short: 16 bytes end before its 8-byte payload length; and the previous state file is "
                "unusable too: " +
                path + ".prev: cut short: " + std::to_string(prev.size() - 1) +
                " bytes, where its length field makes " + std::to_string(prev.size()));
  EXPECT_FALSE(result.resumed.resumed);
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".damaged"));

  fs::remove(path + ".prev");
  EXPECT_EQ(start(path).status.message(),
            path +
                ": cut short: 16 bytes end before its 8-byte payload length; and the previous state file is "
                "unusable too: " +
                path + ".prev does not exist");
}

TEST(StateResume, AMissingFileWithAGoodPrevResumesPrev) {
  TempDir dir;
  const std::string path = dir.file("world.state");
  save_twice(path);
  fs::remove(path);  // as a crash between a save's two renames leaves it
  const Resumption result = start(path);
  ASSERT_TRUE(result.status.ok()) << result.status.message();
  EXPECT_EQ(result.built_tick, 30u);
  ASSERT_EQ(result.resumed.warnings.size(), 1u);
  EXPECT_EQ(result.resumed.warnings[0].rfind(path + " does not exist", 0), 0u) << result.resumed.warnings[0];
}

TEST(StateResume, NoFileAtAllIsAFirstStart) {
  TempDir dir;
  const Resumption result = start(dir.file("world.state"));
  EXPECT_TRUE(result.status.ok()) << result.status.message();
  EXPECT_FALSE(result.resumed.resumed);
  EXPECT_TRUE(result.resumed.warnings.empty());
}

TEST(StateResume, AVersion1FileIsResumedWithAWarning) {
  TempDir dir;
  const std::string path = dir.file("world.state");
  write_bytes(path, "tumble-state-v1\n" + small_world().SerializeAsString());
  const Resumption result = start(path);
  ASSERT_TRUE(result.status.ok()) << result.status.message();
  EXPECT_EQ(result.resumed.from, path);
  ASSERT_EQ(result.resumed.warnings.size(), 1u);
  EXPECT_NE(result.resumed.warnings[0].find("carries no checksum"), std::string::npos);
}

}  // namespace
}  // namespace tumble::sim
