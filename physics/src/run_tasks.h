// run_tasks: runs a callable f(std::size_t task) as `count` tasks of a
// TaskSystem (task_system.h) and returns when all have finished.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>

#include "tumble/physics/task_system.h"

namespace tumble::physics {

template <typename F>
void run_tasks(TaskSystem& tasks, std::size_t count, F& f) {
  assert(count <= UINT32_MAX);
  tasks.run([](void* context, std::uint32_t task) { (*static_cast<F*>(context))(task); }, &f,
            static_cast<std::uint32_t>(count));
}

}  // namespace tumble::physics
