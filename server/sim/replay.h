// Replaying a journal (tumbled --replay): the recorded run again, command by
// command at the ticks they were executed at, as fast as the machine steps,
// ending paused at the tick where the recorded run stopped. On the same
// binary the world then equals the recorded one bit for bit.
//
// Thread: the caller's, before the simulation's thread is started.
#pragma once

#include <cstdint>

#include "sim/journal.h"
#include "sim/simulation.h"

namespace tumble::sim {

struct ReplaySummary {
  std::uint64_t commands = 0;  // recorded commands executed again
  std::uint64_t end_tick = 0;  // the tick the replay stopped at
  bool complete = false;       // the journal ended with its end record (not torn)
};

// Feeds the rest of `journal` (its header already read, `sim` built from
// it) into `sim`, stepping with run_tick() between commands. A torn last
// record ends the replay there (see journal.torn()). Fails at a damaged
// record, with the journal's status (the record and its offset), and when
// the journal does not fit the world (e.g. a command recorded at a tick a
// paused world cannot reach).
Status replay_journal(JournalReader& journal, Simulation& sim, ReplaySummary* summary);

}  // namespace tumble::sim
