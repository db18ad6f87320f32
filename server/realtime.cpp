#include "realtime.h"

#include <linux/capability.h>
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

namespace tumble {
namespace {

// Whether CAP_SYS_NICE is in this process's effective set (the CapEff mask
// of /proc/self/status).
bool holds_cap_sys_nice() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("CapEff:", 0) != 0) continue;
    const std::uint64_t mask = std::stoull(line.substr(7), nullptr, 16);
    return ((mask >> CAP_SYS_NICE) & 1) != 0;
  }
  return false;
}

// Whether the soft RLIMIT_RTPRIO lets an unprivileged thread use `priority`.
bool rlimit_allows(int priority) {
  rlimit limit{};
  if (getrlimit(RLIMIT_RTPRIO, &limit) != 0) return false;
  return limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur >= static_cast<rlim_t>(priority);
}

// sched_setattr's argument (linux/sched/types.h, whose sched_param clashes
// with glibc's), up to the fields it reads for SCHED_OTHER.
struct SchedAttr {
  std::uint32_t size;
  std::uint32_t sched_policy;
  std::uint64_t sched_flags;
  std::int32_t sched_nice;
  std::uint32_t sched_priority;
  std::uint64_t sched_runtime;  // ns: the slice, for a fair policy
  std::uint64_t sched_deadline;
  std::uint64_t sched_period;
};

}  // namespace

sim::Status request_short_slice() {
  SchedAttr attr{};
  attr.size = sizeof attr;
  attr.sched_policy = SCHED_OTHER;
  attr.sched_nice = getpriority(PRIO_PROCESS, 0);  // keep this thread's nice value
  attr.sched_runtime = kShortSliceNanoseconds;
  if (syscall(SYS_sched_setattr, 0, &attr, 0U) == 0) return {};
  return sim::Status::error(std::string("the kernel refused a time slice of ") +
                            std::to_string(kShortSliceNanoseconds / 1000) + " us (" + std::strerror(errno) + ")");
}

sim::Status enter_realtime(int priority) {
  if (priority < kMinRealtimePriority || priority > kMaxRealtimePriority) {
    return sim::Status::error("real-time priority " + std::to_string(priority) + " is outside " +
                              std::to_string(kMinRealtimePriority) + " to " + std::to_string(kMaxRealtimePriority));
  }
  sched_param param{};
  param.sched_priority = priority;
  // pthread_setschedparam returns the error rather than setting errno.
  const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (error == 0) return {};
  std::string message =
      "the kernel refused SCHED_FIFO at priority " + std::to_string(priority) + " (" + std::strerror(error) + ")";
  if (error == EPERM) {
    const std::string p = std::to_string(priority);
    if (holds_cap_sys_nice() || rlimit_allows(priority)) {
      // Permitted to the process, refused all the same: under cgroup v1
      // real-time group scheduling, a group gets no real-time time unless
      // given some (cpu.rt_runtime_us is 0 in a new group).
      message +=
          ": the process may use it (CAP_SYS_NICE or RLIMIT_RTPRIO), but its control group has no real-time "
          "time; give the group some in cpu.rt_runtime_us (cgroup v1; in a container, docker run "
          "--cpu-rt-runtime=400000, with dockerd --cpu-rt-runtime set)";
    } else {
      message += ": it needs CAP_SYS_NICE, or an RLIMIT_RTPRIO of at least " + p + " (ulimit -r " + p +
                 "; in a container, docker run --ulimit rtprio=" + p + ")";
    }
  }
  return sim::Status::error(message);
}

}  // namespace tumble
