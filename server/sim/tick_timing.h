// The recent timing of the sim loop, for GetStats: how long the work of a
// tick took (percentiles over the last kStepWindow stepped ticks), and how
// fast sim time advanced against the wall clock over about the last second.
// Fixed-size rings: recording never allocates.
//
// Thread: owned by the sim thread.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>

namespace tumble::sim {

class TickTiming {
 public:
  using Clock = std::chrono::steady_clock;

  static constexpr std::size_t kStepWindow = 1024;   // stepped ticks the percentiles look at
  static constexpr std::size_t kClockWindow = 4096;  // clock samples kept for the real-time factor

  // The work of one stepped tick, in milliseconds.
  void record_step(double work_ms);

  // Where sim time stood at a wall-clock instant; called once per pass of
  // the loop, paused or not.
  void record_clock(Clock::time_point wall, double sim_time);

  // The q-quantile (0 < q <= 1, nearest rank) of the recorded step times,
  // in ms; 0 before any step.
  double step_ms_quantile(double q) const;

  // Sim seconds per wall-clock second between the newest clock sample and
  // the oldest one at most a second older (or the oldest kept); 0 with
  // fewer than two samples or no wall time between them.
  double real_time_factor() const;

 private:
  struct ClockSample {
    Clock::time_point wall;
    double sim_time = 0;  // s
  };

  std::array<float, kStepWindow> step_ms_{};
  std::size_t step_count_ = 0;  // samples recorded, saturating at the window
  std::size_t step_next_ = 0;   // ring index of the next sample

  std::array<ClockSample, kClockWindow> clock_{};
  std::size_t clock_count_ = 0;
  std::size_t clock_next_ = 0;
};

}  // namespace tumble::sim
