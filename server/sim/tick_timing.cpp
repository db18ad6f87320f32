#include "sim/tick_timing.h"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace tumble::sim {

void TickTiming::Window::record(double value_ms) {
  ms[next] = static_cast<float>(value_ms);
  next = (next + 1) % kStepWindow;
  count = std::min(count + 1, kStepWindow);
}

double TickTiming::Window::quantile(double q) const {
  if (count == 0) return 0;
  std::vector<float> samples(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(count));
  // Nearest rank: the smallest sample with at least a fraction q of the samples at or below it.
  const double rank = std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count));
  const std::size_t index = static_cast<std::size_t>(std::max(rank, 1.0)) - 1;
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(index), samples.end());
  return static_cast<double>(samples[index]);
}

void TickTiming::record_step(double work_ms, double cpu_ms) {
  step_.record(work_ms);
  step_cpu_.record(cpu_ms);
}

void TickTiming::record_start_late(double late_ms) { start_late_.record(late_ms); }

double TickTiming::thread_cpu_ms() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

void TickTiming::record_clock(Clock::time_point wall, double sim_time) {
  clock_[clock_next_] = ClockSample{wall, sim_time};
  clock_next_ = (clock_next_ + 1) % kClockWindow;
  clock_count_ = std::min(clock_count_ + 1, kClockWindow);
}

double TickTiming::step_ms_quantile(double q) const { return step_.quantile(q); }

double TickTiming::step_cpu_ms_quantile(double q) const { return step_cpu_.quantile(q); }

double TickTiming::start_late_ms_quantile(double q) const { return start_late_.quantile(q); }

double TickTiming::real_time_factor() const {
  if (clock_count_ < 2) return 0;
  const auto at = [this](std::size_t age) {  // age 0 is the newest sample
    return clock_[(clock_next_ + kClockWindow - 1 - age) % kClockWindow];
  };
  const ClockSample newest = at(0);
  ClockSample oldest = at(1);
  for (std::size_t age = 2; age < clock_count_; ++age) {
    const ClockSample sample = at(age);
    if (newest.wall - sample.wall > std::chrono::seconds(1)) break;
    oldest = sample;
  }
  const double wall_seconds = std::chrono::duration<double>(newest.wall - oldest.wall).count();
  if (wall_seconds <= 0) return 0;
  return (newest.sim_time - oldest.sim_time) / wall_seconds;
}

}  // namespace tumble::sim
