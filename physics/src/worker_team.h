// WorkerTeam: a few helper threads that run the tasks of one parallel phase
// of a step together with the thread that calls run(); the World's built-in
// TaskSystem (task_system.h), made by World::set_thread_count.
//
// run(fn, context, count) calls fn(context, i) once for every task i in
// [0, count): the caller and the helpers claim tasks one at a time, in index
// order, from a shared counter, and run() returns once every task has
// finished. The caller never waits for a helper that has not started: a
// helper that is slow to wake (asleep, or waiting for a core) simply claims
// nothing, so a team of one thread and a team whose helpers never get a
// core take the same time. Which thread runs which task is left to chance;
// callers make tasks that write disjoint data, so results do not depend on
// it (the narrowphase's runs of pairs, world_contacts.cpp; the contact
// solver's groups of islands, contact_solver.h).
//
// Helpers spin briefly after a phase, since the next phase of a step
// usually follows within microseconds, then sleep on a condition variable
// until the next run(); the caller likewise spins, then sleeps, while the
// last tasks finish. Neither pays for a wake-up unless the other sleeps.
//
// Thread: run() and set_thread_count() from one owning thread only; the
// tasks run on any of the team's threads. No allocation in run().
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "tumble/physics/task_system.h"

namespace tumble::physics {

class WorkerTeam final : public TaskSystem {
 public:
  WorkerTeam() = default;
  ~WorkerTeam() override;
  WorkerTeam(const WorkerTeam&) = delete;
  WorkerTeam& operator=(const WorkerTeam&) = delete;

  // Threads that run tasks, the caller of run() included: 1 (the default)
  // runs every task on the caller. Values below 1 count as 1. Starts or
  // stops helpers; must not be called during run().
  void set_thread_count(int threads);
  int thread_count() const override { return static_cast<int>(helpers_.size()) + 1; }

  // Runs fn(context, i) for i in [0, count) and returns when all have
  // finished.
  void run(TaskFunction fn, void* context, std::uint32_t count) override;

 private:
  // seen: the value of wake_ when the helper was made.
  void helper_main(std::uint32_t seen);
  // Claims and runs tasks of the job `job` until none is left.
  void work(std::uint32_t job);
  void stop_helpers();
  // Announces a new job (or a stop) to the helpers, waking those asleep.
  void wake_helpers();

  std::vector<std::thread> helpers_;

  // The current job. claim_ packs the job number (high 32 bits) with the
  // next task to hand out (low 32 bits), so a helper that wakes late, after
  // its job has ended, cannot claim a task of another job: its
  // compare-exchange expects the old number. A new job first closes claim_
  // (task number kClosed), then writes fn_, context_ and count_, then
  // publishes claim_: a claim that succeeds read the matching values.
  std::atomic<std::uint64_t> claim_{0};
  std::atomic<TaskFunction> fn_{nullptr};
  std::atomic<void*> context_{nullptr};
  std::atomic<std::uint32_t> count_{0};
  std::atomic<std::uint32_t> done_{0};  // tasks of the current job finished
  std::uint32_t job_ = 0;               // owner's count of jobs started

  // wake_ counts jobs published; helpers wait for it to change, stopping_
  // ends them. Sleepers announce themselves in sleeping_helpers_ and
  // owner_sleeping_ before they check their condition under mutex_, so a
  // waker that sees no sleeper needs no lock (both sides use sequentially
  // consistent operations: one of them sees the other's write).
  std::atomic<std::uint32_t> wake_{0};
  std::atomic<bool> stopping_{false};
  std::atomic<int> sleeping_helpers_{0};
  std::atomic<bool> owner_sleeping_{false};
  std::mutex mutex_;
  std::condition_variable helpers_wake_;
  std::condition_variable owner_wake_;
};

}  // namespace tumble::physics
