// WorkerTeam: every task runs exactly once per run(), on the caller and the
// helpers, job after job, and the team can grow, shrink and stop.
#include <gtest/gtest.h>

#include <sys/types.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "run_tasks.h"
#include "worker_team.h"

namespace tumble::physics {
namespace {

// Runs `jobs` jobs of `count` tasks, each task adding one to its slot;
// returns the slots.
std::vector<int> run_jobs(WorkerTeam& team, std::size_t count, int jobs) {
  std::vector<int> hits(count, 0);
  for (int job = 0; job < jobs; ++job) {
    auto task = [&](std::size_t i) { ++hits[i]; };  // slots are disjoint: no two tasks share one
    run_tasks(team, count, task);
  }
  return hits;
}

TEST(WorkerTeamTest, EveryTaskRunsOncePerJob) {
  for (int threads : {1, 2, 3, 8}) {
    WorkerTeam team;
    team.set_thread_count(threads);
    EXPECT_EQ(team.thread_count(), threads);
    for (std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{7}, std::size_t{1000}}) {
      const std::vector<int> hits = run_jobs(team, count, 50);
      for (std::size_t i = 0; i < count; ++i) {
        ASSERT_EQ(hits[i], 50) << "task " << i << " of " << count << " with " << threads << " threads";
      }
    }
  }
}

// Many short jobs back to back: a helper that wakes for one job while the
// caller has already started the next must neither run a task twice nor
// take one from the wrong job.
TEST(WorkerTeamTest, BackToBackJobsNeverMixUp) {
  WorkerTeam team;
  team.set_thread_count(3);
  std::vector<std::atomic<int>> hits(16);
  for (int job = 0; job < 20000; ++job) {
    const std::size_t count = 1 + static_cast<std::size_t>(job % 16);
    for (std::size_t i = 0; i < count; ++i) hits[i].store(0, std::memory_order_relaxed);
    auto task = [&](std::size_t i) { hits[i].fetch_add(1, std::memory_order_relaxed); };
    run_tasks(team, count, task);
    for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(hits[i].load(), 1) << "job " << job << " task " << i;
  }
}

// Tasks that take a while are shared: a helper has 200 ms to wake and take
// some, however busy the machine.
TEST(WorkerTeamTest, HelpersTakeTasks) {
  WorkerTeam team;
  team.set_thread_count(2);
  std::mutex mutex;
  std::set<std::thread::id> runners;
  auto task = [&](std::size_t) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::lock_guard lock(mutex);
    runners.insert(std::this_thread::get_id());
  };
  run_tasks(team, 200, task);
  EXPECT_EQ(runners.size(), 2u);
  EXPECT_EQ(runners.count(std::this_thread::get_id()), 1u);
}

// One thread: everything on the caller, in order.
TEST(WorkerTeamTest, OneThreadRunsInOrderOnTheCaller) {
  WorkerTeam team;
  std::vector<std::size_t> order;
  bool on_caller = true;
  const std::thread::id caller = std::this_thread::get_id();
  auto task = [&](std::size_t i) {
    order.push_back(i);
    on_caller = on_caller && std::this_thread::get_id() == caller;
  };
  run_tasks(team, 5, task);
  EXPECT_EQ(order, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  EXPECT_TRUE(on_caller);
}

// The ids of this process's threads named "tumble-physics": the team's
// helpers (worker_team.cpp names them so).
std::set<pid_t> helper_tids() {
  std::set<pid_t> tids;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (std::getline(comm, name) && name == "tumble-physics") tids.insert(std::stoi(task.path().filename().string()));
  }
  return tids;
}

// Waits up to 10 s for exactly `count` helper threads: a helper that has
// been joined may linger in /proc for a moment before the kernel reaps it,
// and a new one is named just after it starts.
bool helper_count_becomes(std::size_t count) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (helper_tids().size() != count) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

TEST(WorkerTeamTest, GrowsShrinksAndStops) {
  ASSERT_TRUE(helper_count_becomes(0)) << "helpers of another team are still running";
  const pid_t caller = static_cast<pid_t>(::gettid());
  {
    WorkerTeam team;
    for (int threads : {4, 2, 1, 0, 3, 3, 1}) {
      team.set_thread_count(threads);
      const int expected = threads < 1 ? 1 : threads;
      EXPECT_EQ(team.thread_count(), expected);
      ASSERT_TRUE(helper_count_becomes(static_cast<std::size_t>(expected - 1)))
          << helper_tids().size() << " helper threads for a team of " << expected;
      std::set<pid_t> allowed = helper_tids();
      allowed.insert(caller);

      // Every task once per job, and only on the caller and the helpers
      // running now: a helper that was stopped runs nothing.
      std::vector<int> hits(64, 0);
      std::mutex mutex;
      std::set<pid_t> runners;
      auto task = [&](std::size_t i) {
        ++hits[i];
        std::lock_guard lock(mutex);
        runners.insert(static_cast<pid_t>(::gettid()));
      };
      for (int job = 0; job < 10; ++job) run_tasks(team, hits.size(), task);
      for (int h : hits) ASSERT_EQ(h, 10);
      for (pid_t runner : runners) EXPECT_EQ(allowed.count(runner), 1u) << "task ran on thread " << runner;
      if (expected == 1) {
        EXPECT_EQ(runners, std::set<pid_t>{caller});
      }
    }
    team.set_thread_count(4);
    ASSERT_TRUE(helper_count_becomes(3));
  }
  // The destructor stops helpers that sleep between jobs: every one of them exits.
  EXPECT_TRUE(helper_count_becomes(0)) << helper_tids().size() << " helper threads outlived their team";
}

}  // namespace
}  // namespace tumble::physics
