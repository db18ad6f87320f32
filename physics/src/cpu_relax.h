// A pause for spin-wait loops: the physics helpers waiting for a job, and
// tumbled's CPU keep-awake spinners.
#pragma once

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#else
#include <thread>
#endif

namespace tumble::physics {

// Tells the core this is a wait loop: on x86 the pause instruction slows
// the loop and frees the core's shared resources for a sibling
// hyperthread; elsewhere the thread yields to the scheduler.
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

}  // namespace tumble::physics
