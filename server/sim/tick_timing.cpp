#include "sim/tick_timing.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace tumble::sim {

void TickTiming::record_step(double work_ms) {
  step_ms_[step_next_] = static_cast<float>(work_ms);
  step_next_ = (step_next_ + 1) % kStepWindow;
  step_count_ = std::min(step_count_ + 1, kStepWindow);
}

void TickTiming::record_clock(Clock::time_point wall, double sim_time) {
  clock_[clock_next_] = ClockSample{wall, sim_time};
  clock_next_ = (clock_next_ + 1) % kClockWindow;
  clock_count_ = std::min(clock_count_ + 1, kClockWindow);
}

double TickTiming::step_ms_quantile(double q) const {
  if (step_count_ == 0) return 0;
  std::vector<float> samples(step_ms_.begin(), step_ms_.begin() + static_cast<std::ptrdiff_t>(step_count_));
  // Nearest rank: the smallest sample with at least a fraction q of the samples at or below it.
  const double rank = std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(step_count_));
  const std::size_t index = static_cast<std::size_t>(std::max(rank, 1.0)) - 1;
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(index), samples.end());
  return static_cast<double>(samples[index]);
}

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
