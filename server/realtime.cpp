#include "realtime.h"

#include <pthread.h>
#include <sched.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace tumble {

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
  std::string message = "the kernel refused SCHED_FIFO at priority " + std::to_string(priority) + " (" +
                        std::strerror(error) + ")";
  if (error == EPERM) {
    const std::string p = std::to_string(priority);
    message += ": it needs CAP_SYS_NICE, or an RLIMIT_RTPRIO of at least " + p + " (ulimit -r " + p +
               "; in a container, docker run --ulimit rtprio=" + p + ")";
  }
  return sim::Status::error(message);
}

}  // namespace tumble
