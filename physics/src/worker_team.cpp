#include "worker_team.h"

#include <cassert>

#if defined(__linux__)
#include <pthread.h>
#endif

#include "cpu_relax.h"

namespace tumble::physics {
namespace {

// A helper looks for a next job this many times (about 30-60 us) before it
// sleeps: the phases of one step follow each other closely, the steps do
// not.
constexpr int kHelperSpins = 2000;
// The owner checks for the last tasks this many times before it sleeps on
// the count of finished tasks.
constexpr int kOwnerSpins = 4000;

// The task number of a job whose claims are closed: above any count.
constexpr std::uint32_t kClosed = 0xffffffff;

constexpr std::uint64_t pack(std::uint32_t job, std::uint32_t task) {
  return (static_cast<std::uint64_t>(job) << 32) | task;
}

}  // namespace

WorkerTeam::~WorkerTeam() { stop_helpers(); }

void WorkerTeam::stop_helpers() {
  if (helpers_.empty()) return;
  stopping_.store(true);
  wake_helpers();
  for (std::thread& helper : helpers_) helper.join();
  helpers_.clear();
  stopping_.store(false, std::memory_order_relaxed);
}

void WorkerTeam::set_thread_count(int threads) {
  const std::size_t helpers = threads > 1 ? static_cast<std::size_t>(threads - 1) : 0;
  if (helpers == helpers_.size()) return;
  stop_helpers();
  helpers_.reserve(helpers);
  for (std::size_t i = 0; i < helpers; ++i) {
    // The count of jobs as of now: a job or a stop published before the
    // thread gets to run is still new to it.
    const std::uint32_t seen = wake_.load();
    helpers_.emplace_back([this, seen] { helper_main(seen); });
#if defined(__linux__)
    pthread_setname_np(helpers_.back().native_handle(), "tumble-physics");
#endif
  }
}

void WorkerTeam::work(std::uint32_t job) {
  std::uint64_t claim = claim_.load(std::memory_order_acquire);
  for (;;) {
    if (static_cast<std::uint32_t>(claim >> 32) != job) return;
    // Read after the acquire of a claim of this job, so they belong to it
    // or to a later job; a later job closed claim_ before writing them (see
    // run()), so then the exchange below fails.
    const std::uint32_t count = count_.load(std::memory_order_acquire);
    const std::uint32_t task = static_cast<std::uint32_t>(claim);
    if (task >= count) return;
    const TaskFunction fn = fn_.load(std::memory_order_acquire);
    void* context = context_.load(std::memory_order_acquire);
    if (!claim_.compare_exchange_weak(claim, claim + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
      continue;  // claim holds the current value; look again
    }
    fn(context, task);
    done_.fetch_add(1);
    if (owner_sleeping_.load()) {
      { std::lock_guard lock(mutex_); }
      owner_wake_.notify_one();
    }
    claim = claim_.load(std::memory_order_acquire);
  }
}

void WorkerTeam::helper_main(std::uint32_t seen) {
  for (;;) {
    // Wait for a new job: spin, then sleep.
    std::uint32_t now = wake_.load(std::memory_order_acquire);
    for (int spin = 0; now == seen && spin < kHelperSpins; ++spin) {
      cpu_relax();
      now = wake_.load(std::memory_order_acquire);
    }
    if (now == seen) {
      std::unique_lock lock(mutex_);
      sleeping_helpers_.fetch_add(1);
      helpers_wake_.wait(lock, [&] { return wake_.load() != seen; });
      sleeping_helpers_.fetch_sub(1);
      now = wake_.load();
    }
    seen = now;
    if (stopping_.load(std::memory_order_acquire)) return;
    const std::uint32_t job = static_cast<std::uint32_t>(claim_.load(std::memory_order_acquire) >> 32);
    work(job);
  }
}

void WorkerTeam::run(TaskFunction fn, void* context, std::uint32_t count) {
  if (count == 0) return;
  if (helpers_.empty() || count == 1) {
    for (std::uint32_t i = 0; i < count; ++i) fn(context, i);
    return;
  }
  assert(count < kClosed);
  const std::uint32_t tasks = count;
  ++job_;
  // Close the claims first: a helper still looking at the last job must not
  // pair its (exhausted) claim with this job's larger count. A helper that
  // reads any of the values below also sees the closed claim (the fence),
  // so its exchange fails.
  claim_.store(pack(job_, kClosed), std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  fn_.store(fn, std::memory_order_release);
  context_.store(context, std::memory_order_release);
  count_.store(tasks, std::memory_order_release);
  done_.store(0, std::memory_order_relaxed);
  claim_.store(pack(job_, 0), std::memory_order_release);
  wake_helpers();

  work(job_);

  // Every task is claimed; wait for those still running on helpers.
  std::uint32_t done = done_.load(std::memory_order_acquire);
  for (int spin = 0; done != tasks && spin < kOwnerSpins; ++spin) {
    cpu_relax();
    done = done_.load(std::memory_order_acquire);
  }
  if (done != tasks) {
    std::unique_lock lock(mutex_);
    owner_sleeping_.store(true);
    owner_wake_.wait(lock, [&] { return done_.load() == tasks; });
    owner_sleeping_.store(false);
  }
}

void WorkerTeam::wake_helpers() {
  wake_.fetch_add(1);
  if (sleeping_helpers_.load() == 0) return;  // they spin, or will see wake_ before they sleep
  {
    // A helper between its check and its sleep holds the mutex: taking it
    // here means the notification cannot fall in that gap.
    std::lock_guard lock(mutex_);
  }
  helpers_wake_.notify_all();
}

}  // namespace tumble::physics
