// Keeps the machine's CPUs from halting while tumbled runs
// (tumbled --keep-cpus-awake).
//
// A virtual machine's CPU that has nothing to run halts, and the
// hypervisor may give its physical core to someone else; when a timer or a
// packet is due for it, the guest waits until the hypervisor runs it
// again. On the machine of bench/README that wait was often 2-15 ms, a few
// hundred times a minute on a mostly idle machine: a tick that starts
// late, a command read late, a frame sent late, whatever tumbled's own
// priority. A CPU that never halts is never waited for. This runs one
// thread per CPU of the process's affinity mask, pinned to that CPU, that
// spins under SCHED_IDLE: any other thread of any process preempts it at
// once, so it takes only time the CPU would have spent halted.
//
// The cost: the CPUs read as fully busy (top, the hypervisor's
// accounting), and on a shared host the cores hold time that other guests
// could have had; power on a physical machine. The kernel's own way to the
// same end, a cpuidle driver kept from deep states through
// /dev/cpu_dma_latency, does not help a guest that idles by halting.
//
// Linux only. Unprivileged: SCHED_IDLE lowers a thread's priority.
// Thread: start() and stop() from one thread (tumbled's main thread).
#pragma once

#include <atomic>
#include <thread>
#include <vector>

#include "sim/status.h"

namespace tumble {

class CpuKeepAwake {
 public:
  CpuKeepAwake() = default;
  CpuKeepAwake(const CpuKeepAwake&) = delete;
  CpuKeepAwake& operator=(const CpuKeepAwake&) = delete;
  ~CpuKeepAwake() { stop(); }

  // Starts a spinner on each CPU of the calling thread's affinity mask and
  // returns once each one runs pinned under SCHED_IDLE (threads named
  // "tumbled-awake"). A spinner that cannot be pinned or lowered never
  // spins: the others are stopped and the message says what failed.
  sim::Status start();

  // Stops and joins the spinners; nothing when none run.
  void stop();

  // Spinners running: the CPUs of the mask after start(), else 0.
  std::size_t spinner_count() const { return spinners_.size(); }

 private:
  std::atomic<bool> stopping_{false};
  std::vector<std::thread> spinners_;
};

}  // namespace tumble
