// Saved worlds: a world written to a state file and read back is the same
// world bit for bit; writes are atomic; bad files get clear errors; the
// command journal reads back what was recorded and survives a torn end.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "sim/body_spec.h"
#include "sim/journal.h"
#include "sim/scene_file.h"
#include "sim/state_file.h"
#include "sim/world_state.h"
#include "temp_dir.h"

namespace tumble::sim {
namespace {

namespace fs = std::filesystem;

// The world of `scene_json` with its directory, as the simulation builds it.
struct Built {
  physics::World world;
  BodyDirectory directory;
  JointDirectory joints;
  BodyLoads loads;
};

void build(const std::string& scene_json, Built* out) {
  tumble::v1::Scene scene;
  ASSERT_TRUE(parse_scene_json(scene_json, &scene).ok());
  out->world.set_gravity({scene.gravity().x(), scene.gravity().y(), scene.gravity().z()});
  for (int i = 0; i < scene.bodies_size(); ++i) {
    physics::BodyDesc desc;
    ASSERT_TRUE(body_desc_from_spec(scene.bodies(i), "bodies", &desc).ok());
    const physics::BodyId id = out->world.add_body(desc);
    const auto& spec = scene.bodies(i);
    out->directory.add(id, BodyEntry{spec.name(), spec.shape(), spec.mass()});
  }
}

constexpr const char* kPile = R"({"bodies": [
  {"name": "ground", "static": true, "shape": {"plane": {}}},
  {"name": "a", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 1, "position": [0, 0.5, 0]},
  {"name": "b", "shape": {"box": {"half_extents": [0.5, 0.5, 0.5]}}, "mass": 1, "position": [0, 1.5, 0]},
  {"name": "ball", "shape": {"sphere": {"radius": 0.3}}, "mass": 2, "restitution": 0.5, "friction": 0.2,
   "position": [3, 20, 0], "angular_velocity": [1, 2, 3]},
  {"name": "gem", "shape": {"convex": {"points": [[0,1,0],[0,-1,0],[1,0,0],[-1,0,0],[0,0,1],[0,0,-1]]}},
   "mass": 1, "position": [-3, 1, 0]},
  {"name": "spinner", "kinematic": true, "shape": {"capsule": {"radius": 0.2, "half_height": 1}},
   "position": [6, 1, 0], "angular_velocity": [0, 1, 0]},
  {"name": "dumbbell", "shape": {"points": {"masses": [1, 1, 1], "positions": [[1,0,0],[-1,0,0],[0,1,0]]}},
   "position": [0, 50, 9], "linear_velocity": [0, 3, 0], "angular_velocity": [0.1, 4, 0.2]}]})";

void expect_same_world(const physics::World& a, const physics::World& b) {
  ASSERT_EQ(a.body_count(), b.body_count());
  EXPECT_EQ(a.next_body_id(), b.next_body_id());
  for (std::size_t i = 0; i < a.body_count(); ++i) {
    const physics::BodyId id = a.body_id_at(i);
    ASSERT_EQ(b.body_id_at(i), id);
    EXPECT_EQ(a.position(id), b.position(id)) << id;
    EXPECT_EQ(a.orientation(id).coeffs(), b.orientation(id).coeffs()) << id;
    EXPECT_EQ(a.linear_momentum(id), b.linear_momentum(id)) << id;
    EXPECT_EQ(a.angular_momentum(id), b.angular_momentum(id)) << id;
    EXPECT_EQ(a.linear_velocity(id), b.linear_velocity(id)) << id;
    EXPECT_EQ(a.is_awake(id), b.is_awake(id)) << id;
    EXPECT_EQ(a.motion_type(id), b.motion_type(id)) << id;
    EXPECT_EQ(a.friction(id), b.friction(id)) << id;
    EXPECT_EQ(a.restitution(id), b.restitution(id)) << id;
    EXPECT_EQ(a.inertia_body(id), b.inertia_body(id)) << id;
  }
}

TEST(WorldState, RoundTripThroughAFileIsExact) {
  TempDir dir;
  Built original;
  build(kPile, &original);
  // Some history: a removed body (its id stays unused), loads of each kind,
  // and time for the column to fall asleep while the ball still flies.
  original.world.remove_body(original.directory.id_of("b"));
  original.directory.remove(2);
  original.loads.add_force(original.directory.id_of("gem"), {1, 0, 0}, {0, 0.5, 0}, BodyLoad::kPersistent);
  original.loads.add_torque(original.directory.id_of("ball"), {0, 0, 0.1}, 1000);
  for (int i = 0; i < 240; ++i) {
    original.loads.apply(original.world);
    original.world.step(1.0 / 240);
  }
  ASSERT_FALSE(original.world.is_awake(original.directory.id_of("a")));

  tumble::v1::WorldState state;
  capture_world(original.world, original.directory, original.joints, original.loads, &state);
  state.set_tick(240);
  ASSERT_TRUE(write_state_file(dir.file("world.state"), state).ok());
  EXPECT_FALSE(fs::exists(dir.file("world.state.tmp")));

  tumble::v1::WorldState read;
  bool exists = false;
  const Status status = read_state_file(dir.file("world.state"), &read, &exists);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_TRUE(exists);
  EXPECT_EQ(read.tick(), 240u);
  Built restored;
  const Status restore = restore_world(read, &restored.world, &restored.directory, &restored.joints, &restored.loads);
  ASSERT_TRUE(restore.ok()) << restore.message();
  expect_same_world(original.world, restored.world);
  EXPECT_EQ(restored.directory.id_of("b"), physics::kInvalidBodyId);
  EXPECT_EQ(restored.directory.name_of(restored.directory.id_of("gem")), "gem");
  ASSERT_EQ(restored.loads.size(), 2u);
  EXPECT_TRUE(restored.loads.loads()[0].persistent());
  EXPECT_EQ(restored.loads.loads()[1].ticks_left, original.loads.loads()[1].ticks_left);

  // The bodies that touch nothing go on identically.
  for (int i = 0; i < 120; ++i) {
    for (Built* built : {&original, &restored}) {
      built->loads.apply(built->world);
      built->world.step(1.0 / 240);
    }
  }
  for (const char* name : {"ball", "dumbbell", "spinner"}) {
    const physics::BodyId id = original.directory.id_of(name);
    EXPECT_EQ(original.world.position(id), restored.world.position(id)) << name;
    EXPECT_EQ(original.world.orientation(id).coeffs(), restored.world.orientation(id).coeffs()) << name;
  }
}

TEST(WorldState, ABodyThatCouldNotBeRestoredIsNeverSaved) {
  Built original;
  build(kPile, &original);
  const physics::BodyId a = original.directory.id_of("a");
  const physics::BodyId b = original.directory.id_of("b");
  const physics::BodyId ball = original.directory.id_of("ball");
  original.loads.add_force(a, {1, 0, 0}, {0, 0, 0}, BodyLoad::kPersistent);
  original.loads.add_force(ball, {0, 1, 0}, {0, 0, 0}, BodyLoad::kPersistent);
  // What only a failing guard could leave: a NaN position, and a speed beyond the ranges.
  original.world.set_state(a, {std::nan(""), 0.5, 0}, physics::Quat::Identity(), physics::Vec3::Zero(),
                           physics::Vec3::Zero());
  original.world.set_state(b, {0, 1.5, 0}, physics::Quat::Identity(), {2e9, 0, 0}, physics::Vec3::Zero());

  tumble::v1::WorldState state;
  EXPECT_EQ(capture_world(original.world, original.directory, original.joints, original.loads, &state), 2u);
  ASSERT_EQ(state.bodies_size(), static_cast<int>(original.world.body_count()) - 2);
  for (const tumble::v1::SavedBody& saved : state.bodies()) {
    EXPECT_NE(saved.id(), a);
    EXPECT_NE(saved.id(), b);
  }
  // The load of the body left out goes with it; the other stays.
  ASSERT_EQ(state.loads_size(), 1);
  EXPECT_EQ(state.loads(0).body(), ball);
  // What was saved restores, and the ids left out are never handed out again.
  Built restored;
  const Status status = restore_world(state, &restored.world, &restored.directory, &restored.joints, &restored.loads);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(restored.world.body_count(), original.world.body_count() - 2);
  EXPECT_EQ(restored.world.next_body_id(), original.world.next_body_id());
}

TEST(WorldState, AMissingFileIsNotAnError) {
  tumble::v1::WorldState state;
  bool exists = true;
  EXPECT_TRUE(read_state_file("/nonexistent-dir/world.state", &state, &exists).ok());
  EXPECT_FALSE(exists);
}

TEST(WorldState, DamagedFilesAreClearErrors) {
  TempDir dir;
  tumble::v1::WorldState state;
  bool exists = false;
  std::ofstream(dir.file("json")) << R"({"bodies": []})";
  Status status = read_state_file(dir.file("json"), &state, &exists);
  EXPECT_EQ(status.message(), dir.file("json") +
                                  ": not a tumble state file (it does not start with 'tumble-state-v2' or "
                                  "'tumble-state-v1')");
  std::ofstream(dir.file("torn"), std::ios::binary) << "tumble-state-v1\n" << std::string("\x0a\xff\xff", 3);
  status = read_state_file(dir.file("torn"), &state, &exists);
  EXPECT_EQ(status.message(), dir.file("torn") + ": the payload does not parse as a WorldState");
}

TEST(WorldState, InconsistentStatesAreRefused) {
  Built original;
  build(kPile, &original);
  tumble::v1::WorldState good;
  capture_world(original.world, original.directory, original.joints, original.loads, &good);

  auto error_of = [](const tumble::v1::WorldState& state) {
    Built target;
    return restore_world(state, &target.world, &target.directory, &target.joints, &target.loads).message();
  };
  EXPECT_EQ(error_of(good), "");
  tumble::v1::WorldState bad = good;
  bad.set_format_version(7);
  EXPECT_EQ(error_of(bad), "format_version: expected 1, got 7");
  bad = good;
  bad.mutable_bodies(2)->set_id(1);
  EXPECT_EQ(error_of(bad), "bodies[2].id: 1 is used by another body");
  bad = good;
  bad.set_next_body_id(3);
  EXPECT_EQ(error_of(bad), "bodies[3].id: 3 is not below next_body_id");
  bad = good;
  bad.set_next_body_id(0xfffffff0);  // restoring it would index 2^32 ids
  EXPECT_EQ(error_of(bad), "next_body_id: 4294967280 is more than the 67108864 ids a world may hand out");
  bad = good;
  bad.mutable_bodies(1)->mutable_linear_momentum()->set_x(std::nan(""));
  EXPECT_EQ(error_of(bad), "bodies[1]: momenta and sleep_time must be finite");
  bad = good;
  bad.mutable_bodies(1)->set_last_speed(std::numeric_limits<double>::infinity());
  EXPECT_EQ(error_of(bad),
            "bodies[1]: rest_position, last_speed and rise_start_speed must be finite, rest_orientation a unit "
            "quaternion");
  bad = good;
  bad.mutable_bodies(1)->mutable_rest_orientation()->set_w(2);
  EXPECT_EQ(error_of(bad),
            "bodies[1]: rest_position, last_speed and rise_start_speed must be finite, rest_orientation a unit "
            "quaternion");
  // A file from before the rest pose was saved restores, the count's pose
  // starting at the body's own.
  tumble::v1::WorldState older = good;
  older.mutable_bodies(1)->clear_rest_position();
  older.mutable_bodies(1)->clear_rest_orientation();
  EXPECT_EQ(error_of(older), "");
  bad = good;
  bad.mutable_bodies(1)->mutable_spec()->mutable_shape()->mutable_box()->mutable_half_extents()->set_x(-1);
  EXPECT_EQ(error_of(bad), "bodies[1].spec.shape.box.half_extents.x: -1 m is outside 0.001 .. 1e6 m");
  // A body outside the physical ranges (body_limits.h), as a file of an
  // older server could hold: refused, naming the body and the range.
  bad = good;
  bad.mutable_bodies(1)->mutable_spec()->set_mass(1e-40);
  EXPECT_EQ(error_of(bad), "bodies[1].spec.mass: 1e-40 kg is outside 1e-6 .. 1e9 kg");
  bad = good;
  bad.mutable_bodies(1)->mutable_spec()->mutable_position()->set_y(std::nan(""));
  EXPECT_EQ(error_of(bad), "bodies[1].spec.position.y: nan m is outside -1e9 .. 1e9 m");
  bad = good;
  bad.mutable_bodies(3)->mutable_spec()->set_name("a");
  EXPECT_EQ(error_of(bad), "bodies[3].spec.name: 'a' is used by another body");
  bad = good;
  tumble::v1::SavedLoad* load = bad.add_loads();
  load->set_body(99);
  load->set_ticks_left(1);
  EXPECT_EQ(error_of(bad), "loads[0].body: no body 99");
}

TEST(WorldState, NamesThisServerRefusesAreClearedNotTheWorld) {
  // A file written before names had limits: the bodies stay, without those names.
  Built original;
  build(kPile, &original);
  tumble::v1::WorldState saved;
  capture_world(original.world, original.directory, original.joints, original.loads, &saved);
  saved.mutable_bodies(1)->mutable_spec()->set_name("123");
  saved.mutable_bodies(2)->mutable_spec()->set_name(std::string(1000000, 'b'));
  Built restored;
  ASSERT_TRUE(restore_world(saved, &restored.world, &restored.directory, &restored.joints, &restored.loads).ok());
  expect_same_world(original.world, restored.world);
  EXPECT_EQ(restored.directory.name_of(saved.bodies(1).id()), "");
  EXPECT_EQ(restored.directory.name_of(saved.bodies(2).id()), "");
  EXPECT_EQ(restored.directory.name_of(saved.bodies(3).id()), "ball");

  // The scene kept for Reset likewise.
  tumble::v1::Scene scene;
  ASSERT_TRUE(parse_scene_json(kPile, &scene).ok());
  scene.mutable_bodies(1)->set_name("0");
  const tumble::v1::Scene allowed = restorable_scene(scene);
  ASSERT_EQ(allowed.bodies_size(), scene.bodies_size());
  EXPECT_EQ(allowed.bodies(1).name(), "");
  EXPECT_EQ(allowed.bodies(2).name(), "b");
}

TEST(WorldState, MomentaThatGiveAVelocityOutsideTheRangesAreRefused) {
  // p / m = 1e12 m/s: finite, but a world that took it would save a file it
  // could not load again.
  Built original;
  build(kPile, &original);
  tumble::v1::WorldState state;
  capture_world(original.world, original.directory, original.joints, original.loads, &state);
  const physics::BodyId id = state.bodies(3).id();
  state.mutable_bodies(3)->mutable_linear_momentum()->set_x(1e12 * original.world.mass(id));
  Built restored;
  const Status status = restore_world(state, &restored.world, &restored.directory, &restored.joints, &restored.loads);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("bodies[3]: its momenta give a velocity of [1000000000000.000000"), std::string::npos)
      << status.message();
}

TEST(WorldState, ABodySavedWithoutAnOrientationIsRestoredUpright) {
  Built original;
  build(kPile, &original);
  tumble::v1::WorldState state;
  capture_world(original.world, original.directory, original.joints, original.loads, &state);
  state.mutable_bodies(1)->mutable_spec()->clear_orientation();
  Built restored;
  ASSERT_TRUE(restore_world(state, &restored.world, &restored.directory, &restored.joints, &restored.loads).ok());
  const physics::BodyId id = state.bodies(1).id();
  EXPECT_EQ(restored.world.orientation(id).coeffs(), physics::Quat::Identity().coeffs());
  // And saved again, it restores again.
  tumble::v1::WorldState again;
  capture_world(restored.world, restored.directory, restored.joints, restored.loads, &again);
  Built twice;
  const Status status = restore_world(again, &twice.world, &twice.directory, &twice.joints, &twice.loads);
  EXPECT_TRUE(status.ok()) << status.message();
}

TEST(WorldState, AFailedWriteKeepsTheOldFile) {
  TempDir dir;
  tumble::v1::WorldState state;
  state.set_format_version(kWorldStateFormat);
  state.set_tick(1);
  ASSERT_TRUE(write_state_file(dir.file("world.state"), state).ok());
  // A directory where the temporary file would go makes the next write fail.
  fs::create_directory(dir.file("world.state.tmp"));
  state.set_tick(2);
  const Status status = write_state_file(dir.file("world.state"), state);
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("world.state.tmp: cannot create"), std::string::npos) << status.message();
  tumble::v1::WorldState read;
  bool exists = false;
  ASSERT_TRUE(read_state_file(dir.file("world.state"), &read, &exists).ok());
  EXPECT_EQ(read.tick(), 1u);
}

TEST(Journal, ReadsBackWhatWasRecorded) {
  TempDir dir;
  JournalWriter writer;
  tumble::v1::JournalHeader header;
  header.set_format_version(kJournalFormat);
  header.set_tick_rate_hz(240);
  header.mutable_scene()->mutable_gravity()->set_y(-9.81);
  ASSERT_TRUE(writer.open(dir.file("run.journal"), header).ok());
  tumble::v1::ClientMessage push;
  push.set_request_id(7);
  push.mutable_apply_force()->mutable_body()->set_name("crate");
  push.mutable_apply_force()->mutable_force()->set_x(10);
  writer.record(3, push);
  writer.record(3, push);
  writer.record(9, push);
  writer.finish(20);
  ASSERT_TRUE(writer.status().ok());

  JournalReader reader;
  ASSERT_TRUE(reader.open(dir.file("run.journal")).ok());
  EXPECT_EQ(reader.header().tick_rate_hz(), 240);
  EXPECT_DOUBLE_EQ(reader.header().scene().gravity().y(), -9.81);
  std::vector<std::uint64_t> ticks;
  tumble::v1::JournalEntry entry;
  while (reader.next(&entry)) {
    ticks.push_back(entry.tick());
    if (!entry.end()) {
      EXPECT_EQ(entry.command().apply_force().body().name(), "crate");
    }
  }
  EXPECT_EQ(ticks, (std::vector<std::uint64_t>{3, 3, 9, 20}));
  EXPECT_TRUE(entry.end());
  EXPECT_FALSE(reader.torn());
}

TEST(Journal, ATornLastRecordEndsTheJournal) {
  TempDir dir;
  {
    JournalWriter writer;
    tumble::v1::JournalHeader header;
    header.set_format_version(kJournalFormat);
    ASSERT_TRUE(writer.open(dir.file("run.journal"), header).ok());
    tumble::v1::ClientMessage pause;
    pause.set_request_id(1);
    writer.record(5, pause);
    writer.flush();
  }  // no finish(): as if killed
  // Half a record at the end, as a kill in the middle of a write leaves.
  std::ofstream(dir.file("run.journal"), std::ios::binary | std::ios::app) << std::string("\x10\x08", 2);
  JournalReader reader;
  ASSERT_TRUE(reader.open(dir.file("run.journal")).ok());
  tumble::v1::JournalEntry entry;
  ASSERT_TRUE(reader.next(&entry));
  EXPECT_EQ(entry.tick(), 5u);
  EXPECT_FALSE(reader.next(&entry));
  EXPECT_TRUE(reader.torn());
}

TEST(Journal, NotAJournalIsAClearError) {
  TempDir dir;
  std::ofstream(dir.file("x")) << "hello";
  JournalReader reader;
  EXPECT_EQ(reader.open(dir.file("x")).message(),
            dir.file("x") + ": not a tumble journal (no 'tumble-journal-v2' or 'tumble-journal-v1' at its start)");
}

}  // namespace
}  // namespace tumble::sim
