// StateSaver: writes checkpoints of the world (--checkpoint-interval) to the
// state file, or through a writer of the caller's (a JetStream bucket), on
// a thread of its own, so the sim thread never waits on the disk or the
// network. Latest wins: a checkpoint offered while an older one is still
// waiting replaces it; one being written is finished first.
//
// Thread: offer() from any thread (the sim thread); stop() from the owner.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "sim/status.h"
#include "tumble/v1/state.pb.h"

namespace tumble::sim {

class StateSaver {
 public:
  // Writes to the state file at `path` (sim/state_file.h).
  explicit StateSaver(std::string path);
  // Writes with `write`, on the saver's thread; `destination` names where,
  // for the log.
  using Writer = std::function<Status(const tumble::v1::WorldState&)>;
  StateSaver(std::string destination, Writer write);
  ~StateSaver();  // stop()

  StateSaver(const StateSaver&) = delete;
  StateSaver& operator=(const StateSaver&) = delete;

  // Queues `state` to be written; never blocks on the disk. `capture` is
  // how long the sim thread took to capture it, for the report.
  void offer(std::shared_ptr<const tumble::v1::WorldState> state,
             std::chrono::steady_clock::duration capture = std::chrono::steady_clock::duration::zero());

  // Writes what is still waiting, then ends the thread. Idempotent.
  void stop();

  // Checkpoints written so far (for logs and tests).
  std::uint64_t written() const;

  // What the saver has done so far, for Stats.
  struct Report {
    std::uint64_t written = 0;
    std::uint64_t failed = 0;
    std::uint64_t last_tick = 0;   // of the last checkpoint written
    std::uint64_t last_bytes = 0;  // its WorldState, encoded
    double last_write_ms = 0;      // encoding and writing it
    double write_ms_max = 0;
    double last_capture_ms = 0;  // the sim thread's capture of the last one offered
    double capture_ms_max = 0;
  };
  Report report() const;
  const std::string& destination() const { return destination_; }

 private:
  void run();

  const std::string destination_;
  const Writer write_;
  mutable std::mutex mutex_;
  std::condition_variable wakeup_;
  std::shared_ptr<const tumble::v1::WorldState> waiting_;
  bool stopping_ = false;
  Report report_;
  std::thread thread_;
};

}  // namespace tumble::sim
