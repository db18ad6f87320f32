// RunRecord: what reaches the journal and when a checkpoint is taken,
// through a real journal file read back with JournalReader.
#include "sim/run_record.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace tumble::sim {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() : path_(fs::temp_directory_path() / ("tumble-run-record-test-" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

// The ticks of the entries of the journal at `path`, the end record's included.
std::vector<std::uint64_t> journal_ticks(const std::string& path, std::vector<bool>* ends) {
  JournalReader reader;
  EXPECT_TRUE(reader.open(path).ok());
  std::vector<std::uint64_t> ticks;
  tumble::v1::JournalEntry entry;
  while (reader.next(&entry)) {
    ticks.push_back(entry.tick());
    ends->push_back(entry.end());
  }
  return ticks;
}

TEST(RunRecord, JournalsWhatChangesTheWorldAndItsEnd) {
  TempDir dir;
  JournalWriter writer;
  tumble::v1::JournalHeader header;
  header.set_format_version(kJournalFormat);
  ASSERT_TRUE(writer.open(dir.file("run.journal"), header).ok());
  RunRecord record;
  record.set_journal(&writer);

  tumble::v1::ClientMessage push;
  push.mutable_apply_force()->mutable_body()->set_name("crate");
  tumble::v1::ClientMessage list;
  list.mutable_list_bodies();
  tumble::v1::ClientMessage stats;
  stats.mutable_get_stats();
  record.record(3, push);
  record.record(3, list);
  record.record(4, stats);
  record.record(5, push);
  record.flush();
  record.finish(9);

  std::vector<bool> ends;
  EXPECT_EQ(journal_ticks(dir.file("run.journal"), &ends), (std::vector<std::uint64_t>{3, 5, 9}))
      << "ListBodies and GetStats only read the world";
  EXPECT_EQ(ends, (std::vector<bool>{false, false, true}));
}

TEST(RunRecord, CheckpointsOnlyAWorldThatChanged) {
  RunRecord record;
  int captures = 0;
  std::vector<std::uint64_t> checkpoints;  // the tick of each state handed to the sink
  // A zero interval: a checkpoint is due at every call, if the world changed.
  record.set_checkpoints(
      RunRecord::Clock::duration::zero(),
      [&](std::shared_ptr<const tumble::v1::WorldState> state, RunRecord::Clock::duration capture) {
        checkpoints.push_back(state->tick());
        EXPECT_GE(capture, RunRecord::Clock::duration::zero());
      },
      [&](tumble::v1::WorldState* state) {
        state->set_tick(static_cast<std::uint64_t>(++captures));
        return nullptr;
      });
  record.checkpoint_if_due();  // the world as it starts is not on disk yet
  record.checkpoint_if_due();
  record.checkpoint_if_due();
  record.note_change();
  record.note_change();
  record.checkpoint_if_due();
  record.checkpoint_if_due();
  EXPECT_EQ(checkpoints, (std::vector<std::uint64_t>{1, 2}));
}

TEST(RunRecord, HandsTheSinkTheTimeTheCaptureTook) {
  RunRecord record;
  RunRecord::Clock::duration took{};
  record.set_checkpoints(
      RunRecord::Clock::duration::zero(),
      [&](std::shared_ptr<const tumble::v1::WorldState>, RunRecord::Clock::duration capture) { took = capture; },
      [](tumble::v1::WorldState*) {
        const auto until = RunRecord::Clock::now() + std::chrono::milliseconds(3);
        while (RunRecord::Clock::now() < until) {
        }
        return nullptr;
      });
  record.checkpoint_if_due();
  EXPECT_GE(took, std::chrono::milliseconds(3));
  EXPECT_LT(took, std::chrono::seconds(10));
}

TEST(RunRecord, AStateKeepsWhatItPointsIntoAliveUntilItGoes) {
  RunRecord record;
  auto scene = std::make_shared<tumble::v1::Scene>();
  scene->add_bodies()->set_name("kept");
  std::shared_ptr<const tumble::v1::WorldState> saved;
  record.set_checkpoints(
      RunRecord::Clock::duration::zero(),
      [&](std::shared_ptr<const tumble::v1::WorldState> state, RunRecord::Clock::duration) { saved = state; },
      [scene](tumble::v1::WorldState* state) {
        state->unsafe_arena_set_allocated_scene(scene.get());  // in place, not a copy
        return std::shared_ptr<const void>(scene);
      });
  record.checkpoint_if_due();
  ASSERT_NE(saved, nullptr);
  const std::weak_ptr<tumble::v1::Scene> watch = scene;
  scene.reset();
  record = RunRecord{};  // the capture's own reference goes too
  ASSERT_FALSE(watch.expired()) << "the state still points into the scene";
  EXPECT_EQ(saved->scene().bodies(0).name(), "kept");
  EXPECT_EQ(&saved->scene(), watch.lock().get());
  saved.reset();
  EXPECT_TRUE(watch.expired());
}

TEST(RunRecord, WaitsForTheIntervalBeforeACheckpoint) {
  RunRecord record;
  int checkpoints = 0;
  record.set_checkpoints(
      std::chrono::hours(1),
      [&](std::shared_ptr<const tumble::v1::WorldState>, RunRecord::Clock::duration) { ++checkpoints; },
      [](tumble::v1::WorldState*) { return nullptr; });
  record.note_change();
  record.checkpoint_if_due();
  EXPECT_EQ(checkpoints, 0) << "the first is due an hour from set_checkpoints";
}

}  // namespace
}  // namespace tumble::sim
