#include "sim/replay.h"

#include <string>

namespace tumble::sim {
namespace {

// Runs passes until the world reaches `tick`. A paused world advances only
// through a Step under way; a pass that does not move the tick while the
// tick is short means the journal asks for a tick the world cannot reach.
Status run_until(Simulation& sim, std::uint64_t tick) {
  while (sim.tick() < tick) {
    const std::uint64_t before = sim.tick();
    sim.run_tick();
    if (sim.tick() == before) {
      return Status::error("the journal expects tick " + std::to_string(tick) + " but the world stays at tick " +
                           std::to_string(before) + " (paused)");
    }
  }
  if (sim.tick() > tick) {
    return Status::error("the journal has a command at tick " + std::to_string(tick) +
                         " but the world is past it, at " + std::to_string(sim.tick()));
  }
  return {};
}

}  // namespace

Status replay_journal(JournalReader& journal, Simulation& sim, ReplaySummary* summary) {
  *summary = ReplaySummary{};
  tumble::v1::JournalEntry entry;
  bool pending = false;  // commands submitted and not yet applied by a pass
  Status status;
  while (journal.next(&entry)) {
    if (pending && sim.tick() < entry.tick()) {
      // Apply the commands of the current tick in one pass, then go on.
      sim.run_tick();
      pending = false;
    }
    if (!(status = run_until(sim, entry.tick())).ok()) break;
    if (entry.end()) {
      summary->complete = true;
      break;
    }
    sim.submit(Command{entry.command(), nullptr, nullptr});
    pending = true;
    ++summary->commands;
  }
  // A damaged record ends the replay: the commands after it are unknown.
  if (status.ok() && !journal.status().ok()) status = journal.status();
  if (status.ok() && pending) sim.run_tick();
  if (status.ok() && summary->complete && sim.tick() != entry.tick()) {
    status = Status::error("the journal ends at tick " + std::to_string(entry.tick()) + " but the replay reached " +
                           std::to_string(sim.tick()));
  }
  // Stay where the recorded run stopped.
  if (status.ok() && !sim.paused()) {
    tumble::v1::ClientMessage pause;
    pause.mutable_pause();
    sim.submit(Command{pause, nullptr, nullptr});
    sim.run_tick();
  }
  summary->end_tick = sim.tick();
  return status;
}

}  // namespace tumble::sim
