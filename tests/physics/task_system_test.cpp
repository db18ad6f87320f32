// TaskSystem: a World whose parallel phases run on the embedder's task
// system gives the bits of a World stepped on one thread, whatever order and
// threads the tasks run in, and really hands its phases to that system.
#include <gtest/gtest.h>

#include <cstdint>
#include <thread>
#include <vector>

#include "scene_helpers.h"
#include "tumble/physics/task_system.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::add_loose_pile;
using testing::disturb_loose_pile;
using testing::ground_plane;
using testing::kLoosePileSteps;
using testing::kTick;
using testing::state_hash;

// Counts what the World asks of it; the tasks themselves are run by
// run_all().
class CountingTaskSystem : public TaskSystem {
 public:
  explicit CountingTaskSystem(int threads) : threads_(threads) {}
  int thread_count() const override { return threads_; }
  void run(TaskFunction fn, void* context, std::uint32_t task_count) override {
    ++runs;
    tasks += task_count;
    if (task_count > largest_run) largest_run = task_count;
    run_all(fn, context, task_count);
  }

  int runs = 0;
  std::uint64_t tasks = 0;
  std::uint32_t largest_run = 0;

 private:
  virtual void run_all(TaskFunction fn, void* context, std::uint32_t task_count) {
    for (std::uint32_t i = 0; i < task_count; ++i) fn(context, i);
  }
  int threads_;
};

// Last task first, all on the caller.
class ReverseTaskSystem final : public CountingTaskSystem {
 public:
  ReverseTaskSystem() : CountingTaskSystem(4) {}

 private:
  void run_all(TaskFunction fn, void* context, std::uint32_t task_count) override {
    for (std::uint32_t i = task_count; i-- > 0;) fn(context, i);
  }
};

// Three threads started for each run, task i on thread i % 3, joined before
// run() returns; the caller runs none.
class SpawningTaskSystem final : public CountingTaskSystem {
 public:
  SpawningTaskSystem() : CountingTaskSystem(3) {}

 private:
  void run_all(TaskFunction fn, void* context, std::uint32_t task_count) override {
    std::vector<std::thread> threads;
    for (std::uint32_t t = 0; t < 3; ++t) {
      threads.emplace_back([=] {
        for (std::uint32_t i = t; i < task_count; i += 3) fn(context, i);
      });
    }
    for (std::thread& thread : threads) thread.join();
  }
};

// 100 boxes and spheres dropped in a loose block with varied orientations,
// a push and a removal on the way, kLoosePileSteps at 240 Hz; returns the
// hash after every half second.
std::vector<std::uint64_t> run_pile_on(TaskSystem* tasks) {
  World world;
  world.set_task_system(tasks);
  world.add_body(ground_plane());
  const std::vector<BodyId> ids = add_loose_pile(world);
  std::vector<std::uint64_t> hashes;
  for (int i = 0; i < kLoosePileSteps; ++i) {
    disturb_loose_pile(world, ids, i);
    world.step(kTick);
    if ((i + 1) % 120 == 0) hashes.push_back(state_hash(world));
  }
  return hashes;
}

TEST(TaskSystemTest, TasksInReverseOrderGiveTheBitsOfOneThread) {
  const std::vector<std::uint64_t> one = run_pile_on(nullptr);
  ReverseTaskSystem reverse;
  EXPECT_EQ(run_pile_on(&reverse), one);
  // The World handed it its phases, some split into several tasks (else the
  // order could not have mattered).
  EXPECT_GT(reverse.runs, 0);
  EXPECT_GT(reverse.largest_run, 1u);
  EXPECT_NE(one.front(), one.back());
}

TEST(TaskSystemTest, TasksOnThreadsItStartsGiveTheBitsOfOneThread) {
  const std::vector<std::uint64_t> one = run_pile_on(nullptr);
  SpawningTaskSystem spawning;
  EXPECT_EQ(run_pile_on(&spawning), one);
  EXPECT_GT(spawning.runs, 0);
  EXPECT_GT(spawning.largest_run, 1u);
}

// thread_count() is the task system's; with 1 the World runs everything
// itself and never calls run(); nullptr goes back to the built-in threads.
TEST(TaskSystemTest, ThreadCountAndTheWayBack) {
  World world;
  world.set_thread_count(2);
  EXPECT_EQ(world.thread_count(), 2);
  ReverseTaskSystem reverse;
  world.set_task_system(&reverse);
  EXPECT_EQ(world.thread_count(), 4);
  world.set_task_system(nullptr);
  EXPECT_EQ(world.thread_count(), 2);

  CountingTaskSystem single(1);
  EXPECT_EQ(run_pile_on(&single), run_pile_on(nullptr));
  EXPECT_EQ(single.runs, 0);
}

}  // namespace
}  // namespace tumble::physics
