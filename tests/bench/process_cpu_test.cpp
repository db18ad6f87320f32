// net_load's reading of a process's CPU time (bench/net/process_cpu.h).
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "process_cpu.h"

namespace tumble::bench {
namespace {

// Spins until the calling thread has used `seconds` of CPU time.
void burn(double seconds) {
  timespec now{};
  do {
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  } while (static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) * 1e-9 < seconds);
}

// A thread that burns 0.3 s of CPU, then (when asked) moves itself under
// SCHED_IDLE, and waits to be released, so its time is on the books while
// it is read.
class Burner {
 public:
  explicit Burner(bool then_idle)
      : thread_([this, then_idle] {
          burn(0.3);
          if (then_idle) {
            const sched_param none{};
            lowered_ = pthread_setschedparam(pthread_self(), SCHED_IDLE, &none) == 0;
          }
          std::unique_lock<std::mutex> lock(mutex_);
          burned_ = true;
          changed_.notify_all();
          changed_.wait(lock, [this] { return released_; });
        }) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return burned_; });
  }
  ~Burner() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      released_ = true;
    }
    changed_.notify_all();
    thread_.join();
  }
  bool lowered() const { return lowered_; }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  bool burned_ = false;
  bool released_ = false;
  bool lowered_ = false;
  std::thread thread_;  // last: starts once the rest is built
};

// The time of a thread under SCHED_IDLE is left out of the process's; an
// ordinary thread's is counted. Each thread burns 0.3 s; /proc counts in
// ticks of 10 ms.
TEST(ProcessCpu, LeavesOutTheThreadsUnderSchedIdle) {
  const std::optional<double> before = process_cpu_seconds(getpid());
  ASSERT_TRUE(before.has_value());
  Burner idle(true);
  ASSERT_TRUE(idle.lowered());
  const std::optional<double> after_idle = process_cpu_seconds(getpid());
  Burner ordinary(false);
  const std::optional<double> after_ordinary = process_cpu_seconds(getpid());
  ASSERT_TRUE(after_idle.has_value() && after_ordinary.has_value());
  EXPECT_LT(*after_idle - *before, 0.15);
  EXPECT_GE(*after_ordinary - *after_idle, 0.25);
}

TEST(ProcessCpu, AProcessThatIsGoneHasNoTime) {
  pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) _exit(0);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_FALSE(process_cpu_seconds(child).has_value());
}

}  // namespace
}  // namespace tumble::bench
