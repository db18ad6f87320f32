// Startup: from tumbled's options to a world ready to run.
//
// Chooses where the world starts: the start of the journal given to
// --replay, else the --state file when it exists, else the checkpoint
// --nats-state found in its bucket, else the --scene (or an empty world
// with gravity). Loads and checks it, builds the simulation,
// replays the journal, opens the journal of --record and starts the
// checkpoint writer of --checkpoint-interval. Logs each step on `log`;
// stops at the first failure with a Status whose sentence names the file.
//
// Thread: tumbled's main thread, before the sim thread starts.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <spdlog/logger.h>

#include "options.h"
#include "sim/journal.h"
#include "sim/simulation.h"
#include "sim/state_saver.h"
#include "sim/status.h"

namespace tumble::server {

// A world ready to start, and what writes it down while it runs. Members
// go in reverse order: the checkpoint writer, then the sim (which writes
// the journal's last entry when it stops), then the journal.
struct ReadyWorld {
  std::unique_ptr<sim::JournalWriter> journal;   // with --record; else null
  std::unique_ptr<sim::Simulation> sim;          // built, not started
  std::unique_ptr<sim::StateSaver> checkpoints;  // with --state and --checkpoint-interval; else null
};

// Where --nats-state keeps the world: the checkpoint read at start, and
// what writes new ones. Read before the world is built.
struct KeptState {
  std::optional<tumble::v1::WorldState> saved;  // the checkpoint to resume from; none: start from the scene
  std::string from;                             // where it came from, for the log
  std::string destination;                      // where checkpoints go, for the log
  sim::StateSaver::Writer write;                // writes one checkpoint, on the saver's thread
};

// Fills `world` from `options` (already checked by parse_server_options)
// and `kept` (with --nats-state; else null). On failure `world` holds what
// was made before it.
sim::Status start_world(const ServerOptions& options, spdlog::logger& log, ReadyWorld* world,
                        const KeptState* kept = nullptr);

}  // namespace tumble::server
