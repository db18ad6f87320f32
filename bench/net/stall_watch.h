// Stalls of the machine itself: moments when no thread of this machine
// could run, whatever its priority. On a shared virtual machine the
// hypervisor takes a virtual CPU away now and then, for a millisecond or
// for tens of them; a latency sample that spans such a moment measures the
// host, not tumbled.
//
// The watch is one thread per CPU the process may use, each pinned to its
// CPU under SCHED_FIFO at priority 90 (above tumbled's --realtime-priority
// and anything the fair scheduler runs), sleeping 1 ms at a time to an
// absolute deadline. Nothing in this machine's scheduler can keep such a
// thread waiting, so a wake-up more than kStallMs after its deadline is a
// stall of that CPU: the hypervisor, or the kernel's own work (interrupts,
// and the network receive work that runs before any thread). The bound of
// 2 ms leaves out the short delays the kernel's work can cause: the
// receive work of net_load's loopback traffic, a few megabits a second,
// takes microseconds a turn. On the machine of bench/README, idle, the
// watcher of one CPU alone saw 11 wake-ups later than 1 ms in 20 s, the
// latest 11 ms: stalls that nothing on the machine caused.
// Each wake-up preempts whatever ran on its CPU for a few microseconds:
// about 2000 a second on two CPUs, a small disturbance, which is why the
// watch is asked for (net_load --stall-watch), not always on.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tumble::bench {

inline constexpr double kStallMs = 2.0;  // a wake-up later than this past its deadline is a stall

// One stall: from the deadline the watcher missed to when it ran, in
// seconds after the measured window's start, and the CPU it was on.
struct Stall {
  double start_s = 0;
  double end_s = 0;
  int cpu = 0;
};

// Empty when this process may run threads under SCHED_FIFO at priority 90
// (root, or an RLIMIT_RTPRIO of at least 90); otherwise why not.
std::string stall_watch_refusal();

// Watches every CPU of the process's affinity mask from now until `end`
// and returns the stalls seen, ordered by start, with times relative to
// `start`. Blocks until `end`. Throws std::runtime_error when a watcher
// cannot be placed on its CPU or given its priority.
std::vector<Stall> watch_stalls(std::chrono::steady_clock::time_point start, std::chrono::steady_clock::time_point end);

// True when [from_s, to_s] overlaps any of `stalls` (ordered by start).
bool overlaps_stall(const std::vector<Stall>& stalls, double from_s, double to_s);

// The figures a report gives of a run's stalls, in hundredths of a
// millisecond (the report's 2 decimals). Each stall's length is rounded
// first and the total is the sum of the rounded lengths, so the printed
// figures agree exactly: longest <= total <= longest * count, and every
// stall, longer than kStallMs, counts at least kStallMs.
struct StallFigures {
  std::size_t count = 0;
  std::int64_t longest_cms = 0;  // 0.01 ms
  std::int64_t total_cms = 0;    // 0.01 ms
};
StallFigures stall_figures(const std::vector<Stall>& stalls);

}  // namespace tumble::bench
