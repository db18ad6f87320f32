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

// Puts the calling thread under SCHED_FIFO at `priority` (1 to 99). Threads
// it starts afterwards inherit the policy and priority (std::thread creates
// them with the default attributes, whose inherit-scheduler is
// PTHREAD_INHERIT_SCHED); threads started before keep theirs. On failure the
// thread's scheduling is unchanged and the message says what the kernel
// refused and what would grant it.
sim::Status enter_realtime(int priority);

}  // namespace tumble
