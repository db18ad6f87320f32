// StateSaver: writes checkpoints of the world (--checkpoint-interval) to the
// state file, or through a writer of the caller's (a JetStream bucket), on
// a thread of its own, so the sim thread never waits on the disk or the
// network. Latest wins: a checkpoint offered while an older one is still
// waiting replaces it; one being written is finished first.
//
// Thread: offer() from any thread (the sim thread); stop() from the owner.
#pragma once

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

  // Queues `state` to be written; never blocks on the disk.
  void offer(std::shared_ptr<const tumble::v1::WorldState> state);

  // Writes what is still waiting, then ends the thread. Idempotent.
  void stop();

  // Checkpoints written so far (for logs and tests).
  std::uint64_t written() const;

 private:
  void run();

  const std::string destination_;
  const Writer write_;
  mutable std::mutex mutex_;
  std::condition_variable wakeup_;
  std::shared_ptr<const tumble::v1::WorldState> waiting_;
  bool stopping_ = false;
  std::uint64_t written_ = 0;
  std::thread thread_;
};

}  // namespace tumble::sim
