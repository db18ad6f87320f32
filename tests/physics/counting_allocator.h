// The global operator new and delete, replaced to count allocations
// (counting_allocator.cpp). Linked only into physics_alloc_tests: the
// replacement is program-wide. The operators live in a translation unit of
// their own so that the compiler never inlines them into a caller's
// new-expression and mistakes malloc/free underneath for a mismatch.
#pragma once

#include <cstddef>

namespace tumble::physics::testing {

// Counts the allocations made, on any thread, while it lives. One at a time.
class AllocationCounter {
 public:
  AllocationCounter();
  ~AllocationCounter();
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;
  std::size_t count() const;
};

}  // namespace tumble::physics::testing
