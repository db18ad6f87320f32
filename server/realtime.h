// Real-time scheduling for tumbled's tick and network threads.
//
// On a machine shared with other busy processes, the kernel's fair
// scheduler gives the sim thread and the I/O thread their share of a core
// only: a command or a frame can wait several milliseconds for other work's
// time slice to end. Under SCHED_FIFO they run as soon as they are
// runnable, ahead of every ordinary process. Both threads sleep between
// ticks and between messages, so the rest of the machine keeps the time
// they leave; a server that falls behind still leaves the kernel's
// real-time reserve (/proc/sys/kernel/sched_rt_runtime_us, 5% by default).
//
// Linux only. Needs CAP_SYS_NICE, or an RLIMIT_RTPRIO of at least the
// priority (`ulimit -r`; `docker run --ulimit rtprio=N` for the image's
// unprivileged user); and, on a host with cgroup v1 real-time group
// scheduling, real-time time for the process's control group
// (cpu.rt_runtime_us, `docker run --cpu-rt-runtime`).
#pragma once

#include "sim/status.h"

namespace tumble {

constexpr int kMinRealtimePriority = 1;
constexpr int kMaxRealtimePriority = 99;

// The time slice request_short_slice() asks for.
constexpr long kShortSliceNanoseconds = 100'000;

// Asks the kernel's fair scheduler for a short time slice for the calling
// thread (sched_setattr's sched_runtime; honoured by EEVDF, Linux 6.12 and
// later, ignored before). The sim and I/O threads run in short bursts and
// must start on time: with the default slice (0.7 ms times a factor for
// the cores) a CPU-bound ordinary thread that a tick's wake-up finds on
// the core may run out its slice first, and a lower priority does not
// shorten it. A task with a short slice gets an early deadline and cuts
// the running task's protected slice to its own. Threads started
// afterwards inherit it. Unprivileged; changes no priority or share.
sim::Status request_short_slice();

// Puts the calling thread under SCHED_FIFO at `priority` (1 to 99). Threads
// it starts afterwards inherit the policy and priority (std::thread creates
// them with the default attributes, whose inherit-scheduler is
// PTHREAD_INHERIT_SCHED); threads started before keep theirs. On failure the
// thread's scheduling is unchanged and the message says what the kernel
// refused and what would grant it.
sim::Status enter_realtime(int priority);

}  // namespace tumble
