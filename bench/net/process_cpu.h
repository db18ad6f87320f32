// CPU time of a process on this machine, read from Linux's /proc: the load
// generator's own and tumbled's, when it runs here.
#pragma once

#include <sys/types.h>

#include <optional>

namespace tumble::bench {

// User plus system CPU time a process has used so far, in seconds
// (utime + stime of /proc/<pid>/stat), less that of its threads now under
// SCHED_IDLE (tumbled --keep-cpus-awake: they spin on the time nothing
// else wants, and are not the process's work); nullopt when the process
// cannot be read (gone, or another user's without permission).
std::optional<double> process_cpu_seconds(pid_t pid);

// Share of one core a process used between two readings, in percent:
// 100 * cpu seconds / wall seconds.
double cpu_percent(double cpu_seconds, double wall_seconds);

}  // namespace tumble::bench
