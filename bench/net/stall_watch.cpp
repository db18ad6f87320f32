#include "stall_watch.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace tumble::bench {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kWatchPriority = 90;
constexpr auto kWatchPeriod = std::chrono::milliseconds(1);

// Gives the calling thread SCHED_FIFO at kWatchPriority; 0 or an errno.
int become_realtime() {
  sched_param param{};
  param.sched_priority = kWatchPriority;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
}

// steady_clock is CLOCK_MONOTONIC on Linux, so its time points are
// deadlines clock_nanosleep understands.
timespec to_timespec(Clock::time_point t) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / 1000000000);
  ts.tv_nsec = static_cast<long>(ns % 1000000000);
  return ts;
}

}  // namespace

std::string stall_watch_refusal() {
  int failed = 0;
  std::thread probe([&] { failed = become_realtime(); });
  probe.join();
  if (failed == 0) return "";
  return std::string("SCHED_FIFO at priority 90 refused (") + std::strerror(failed) +
         "): run as root or with an RLIMIT_RTPRIO of 90 (ulimit -r 90)";
}

std::vector<Stall> watch_stalls(Clock::time_point start, Clock::time_point end) {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) throw std::runtime_error("sched_getaffinity failed");

  std::mutex mutex;
  std::vector<Stall> stalls;
  std::string error;
  std::vector<std::thread> watchers;
  for (std::size_t cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (!CPU_ISSET(cpu, &allowed)) continue;
    watchers.emplace_back([&, cpu] {
      cpu_set_t one;
      CPU_ZERO(&one);
      CPU_SET(cpu, &one);
      int failed = pthread_setaffinity_np(pthread_self(), sizeof one, &one);
      if (failed == 0) failed = become_realtime();
      if (failed != 0) {
        std::lock_guard lock(mutex);
        error = "stall watch on CPU " + std::to_string(cpu) + ": " + std::strerror(failed);
        return;
      }
      std::vector<Stall> seen;
      const auto seconds = [&](Clock::time_point t) { return std::chrono::duration<double>(t - start).count(); };
      for (Clock::time_point deadline = Clock::now() + kWatchPeriod; deadline < end; deadline += kWatchPeriod) {
        const timespec wake = to_timespec(deadline);
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &wake, nullptr) != 0) {
        }
        const Clock::time_point woke = Clock::now();
        if (std::chrono::duration<double, std::milli>(woke - deadline).count() > kStallMs) {
          seen.push_back({seconds(deadline), seconds(woke), static_cast<int>(cpu)});
        }
        // After a stall, the next deadline is a period after the wake-up,
        // not a burst of the deadlines missed.
        if (woke > deadline + kWatchPeriod) deadline = woke;
      }
      std::lock_guard lock(mutex);
      stalls.insert(stalls.end(), seen.begin(), seen.end());
    });
  }
  for (std::thread& watcher : watchers) watcher.join();
  if (!error.empty()) throw std::runtime_error(error);
  std::sort(stalls.begin(), stalls.end(), [](const Stall& a, const Stall& b) { return a.start_s < b.start_s; });
  return stalls;
}

bool overlaps_stall(const std::vector<Stall>& stalls, double from_s, double to_s) {
  // Those that start after to_s cannot overlap; of the others, any that
  // ends at or after from_s does. A few hundred stalls at most a run.
  auto first = std::lower_bound(stalls.begin(), stalls.end(), to_s,
                                [](const Stall& stall, double t) { return stall.start_s < t; });
  for (auto it = stalls.begin(); it != first; ++it) {
    if (it->end_s >= from_s) return true;
  }
  return false;
}

StallFigures stall_figures(const std::vector<Stall>& stalls) {
  StallFigures figures;
  figures.count = stalls.size();
  for (const Stall& stall : stalls) {
    const std::int64_t length_cms = std::llround(1e5 * (stall.end_s - stall.start_s));  // s -> 0.01 ms
    figures.longest_cms = std::max(figures.longest_cms, length_cms);
    figures.total_cms += length_cms;
  }
  return figures;
}

}  // namespace tumble::bench
