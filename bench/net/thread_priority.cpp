#include "thread_priority.h"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace tumble::bench {

void set_thread_priority(int nice, bool idle, const char* program) {
  if (nice != 0 && setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), nice) != 0) {
    std::perror((std::string(program) + ": setpriority").c_str());
  }
  if (!idle) return;
  sched_param param{};
  param.sched_priority = 0;
  if (const int failed = pthread_setschedparam(pthread_self(), SCHED_IDLE, &param); failed != 0) {
    std::fprintf(stderr, "%s: SCHED_IDLE: error %d\n", program, failed);
  }
}

}  // namespace tumble::bench
