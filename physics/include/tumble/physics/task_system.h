// TaskSystem: the interface through which a World runs the parallel phases
// of a step (the narrowphase's runs of pairs, the contact solver's groups
// of islands) on threads the embedder provides, in the manner of Box2D v3's
// enqueueTask/finishTask or Jolt's JobSystem. Without one, a World uses its
// own helper threads (World::set_thread_count).
//
// Contract:
//   - run(fn, context, count) calls fn(context, i) exactly once for every i
//     in [0, count), on any threads (the caller's included), in any order,
//     concurrently or not, and returns only when every call has returned;
//     what the calls wrote must then be visible to the caller (joining them
//     through a mutex, an atomic with acquire/release or a thread join does
//     it). Tasks write disjoint data, so the order does not matter: the
//     World's results are bit-identical for every task system.
//   - The World calls run() only from the thread that calls World::step(),
//     only during step(), never while another run() of the same World is
//     in progress, and only when thread_count() > 1 (with 1 it runs every
//     task on its own thread). run() must not call back into the World.
//   - thread_count() is how many threads run() uses, the caller's included:
//     the World sizes nothing by it, it only decides whether to split work.
//   - The World does not own the task system; it must outlive its use by
//     the World (World::set_task_system(nullptr) ends that use).
#pragma once

#include <cstdint>

namespace tumble::physics {

// One task of a run: context as given to run(), task in [0, count).
using TaskFunction = void (*)(void* context, std::uint32_t task);

class TaskSystem {
 public:
  virtual ~TaskSystem() = default;

  // Threads run() spreads tasks over, the caller's included; at least 1.
  virtual int thread_count() const = 0;

  // Calls fn(context, i) once for each i in [0, task_count) and returns
  // when all have finished (see the contract above).
  virtual void run(TaskFunction fn, void* context, std::uint32_t task_count) = 0;
};

}  // namespace tumble::physics
