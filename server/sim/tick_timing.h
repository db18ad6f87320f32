// The recent timing of the sim loop, for GetStats: how long the work of a
// tick took, on the wall clock and in the sim thread's CPU time, and how
// late the loop began its passes after their deadlines (percentiles over
// the last kStepWindow of each); and how fast sim time advanced against
// the wall clock over about the last second. A tick whose wall time is far
// above its CPU time, or a pass begun late, waited for a core: the machine,
// not the world, made it slow. Fixed-size rings: recording never allocates.
//
// Thread: owned by the sim thread.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>

namespace tumble::sim {

// A span of the steady clock in milliseconds, as TickTiming records them.
inline double milliseconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double, std::milli>(d).count();
}

class TickTiming {
 public:
  using Clock = std::chrono::steady_clock;

  static constexpr std::size_t kStepWindow = 1024;   // stepped ticks the percentiles look at
  static constexpr std::size_t kClockWindow = 4096;  // clock samples kept for the real-time factor

  // The work of one stepped tick, in milliseconds: wall-clock time, and
  // the sim thread's CPU time over the same span (at most the wall time).
  void record_step(double work_ms, double cpu_ms);

  // How late a pass of the loop began after its deadline, in milliseconds
  // (0 when on time).
  void record_start_late(double late_ms);

  // The calling thread's CPU time so far, in milliseconds (Linux:
  // CLOCK_THREAD_CPUTIME_ID).
  static double thread_cpu_ms();

  // Where sim time stood at a wall-clock instant; called once per pass of
  // the loop, paused or not.
  void record_clock(Clock::time_point wall, double sim_time);

  // The q-quantile (0 < q <= 1, nearest rank) of the recorded step times,
  // their CPU times, and the passes' late starts, in ms; 0 before any.
  double step_ms_quantile(double q) const;
  double step_cpu_ms_quantile(double q) const;
  double start_late_ms_quantile(double q) const;

  // Sim seconds per wall-clock second between the newest clock sample and
  // the oldest one at most a second older (or the oldest kept); 0 with
  // fewer than two samples or no wall time between them.
  double real_time_factor() const;

 private:
  struct ClockSample {
    Clock::time_point wall;
    double sim_time = 0;  // s
  };

  // A ring of the last kStepWindow samples of one figure, in ms.
  struct Window {
    std::array<float, kStepWindow> ms{};
    std::size_t count = 0;  // samples recorded, saturating at the window
    std::size_t next = 0;   // ring index of the next sample

    void record(double value_ms);
    double quantile(double q) const;
  };

  Window step_;
  Window step_cpu_;
  Window start_late_;

  std::array<ClockSample, kClockWindow> clock_{};
  std::size_t clock_count_ = 0;
  std::size_t clock_next_ = 0;
};

}  // namespace tumble::sim
