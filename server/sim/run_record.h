// What the sim thread keeps of its run, for tumbled --record and crash
// recovery: the journal of every request that can change the world, with
// the tick it is executed at (flushed once a pass), and checkpoints, a
// capture of the whole world handed to a sink every interval of wall time
// while the world changes.
//
// Thread: the setters before the sim thread starts; everything else on the
// sim thread (or the thread that runs the sim without its clock).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>

#include "sim/journal.h"
#include "tumble/v1/protocol.pb.h"
#include "tumble/v1/state.pb.h"

namespace tumble::sim {

class RunRecord {
 public:
  using Clock = std::chrono::steady_clock;
  // Takes a captured world and how long the capture took on the sim thread.
  using CheckpointSink = std::function<void(std::shared_ptr<const tumble::v1::WorldState>, Clock::duration)>;
  // Fills a state that lives on a protobuf arena; returns what the state
  // points into and must outlive it (or null).
  using Capture = std::function<std::shared_ptr<const void>(tumble::v1::WorldState*)>;

  // Not owned; must outlive the record, or until finish().
  void set_journal(JournalWriter* journal) { journal_ = journal; }

  // The first checkpoint is due `interval` from now; `capture` fills a
  // state with the world as it is, `sink` takes it and must not block.
  void set_checkpoints(Clock::duration interval, CheckpointSink sink, Capture capture);

  // Journals `message`, executed at `tick`, unless it only reads the world.
  void record(std::uint64_t tick, const tumble::v1::ClientMessage& message);
  // Hands what record() wrote since the last flush to the operating system.
  void flush();
  // Ends the journal at `tick`; a later call writes nothing.
  void finish(std::uint64_t tick);

  // The world was stepped or a command executed on it.
  void note_change() { ++world_version_; }
  // Captures the world and hands it to the sink when the interval is up,
  // unless nothing changed since the last checkpoint.
  void checkpoint_if_due();

 private:
  JournalWriter* journal_ = nullptr;
  bool journal_dirty_ = false;  // recorded since the last flush
  Clock::duration checkpoint_interval_{};
  CheckpointSink checkpoint_sink_;
  Capture capture_;
  Clock::time_point next_checkpoint_{};
  std::uint64_t world_version_ = 1;         // grows with every change (note_change)
  std::uint64_t checkpointed_version_ = 0;  // world_version_ at the last checkpoint
};

}  // namespace tumble::sim
