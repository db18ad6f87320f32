#include "cpu_keep_awake.h"

#include <pthread.h>
#include <sched.h>

#include <cerrno>
#include <cstddef>
#include <cstring>
#include <future>
#include <string>
#include <utility>

#include "cpu_relax.h"

namespace tumble {
namespace {

// One spinner's life: pinned to `cpu`, then lowered to SCHED_IDLE, then
// spinning until `stopping`. Says through `ready` whether it got there
// (empty) or what stopped it; it spins only once both changes took.
void spin(std::size_t cpu, const std::atomic<bool>& stopping, std::promise<std::string> ready) {
  pthread_setname_np(pthread_self(), "tumbled-awake");
  cpu_set_t one_cpu;
  CPU_ZERO(&one_cpu);
  CPU_SET(cpu, &one_cpu);
  if (const int error = pthread_setaffinity_np(pthread_self(), sizeof one_cpu, &one_cpu); error != 0) {
    ready.set_value("pinning a thread to CPU " + std::to_string(cpu) + ": " + std::strerror(error));
    return;
  }
  const sched_param no_priority{};  // SCHED_IDLE takes priority 0
  if (const int error = pthread_setschedparam(pthread_self(), SCHED_IDLE, &no_priority); error != 0) {
    ready.set_value("SCHED_IDLE for the thread on CPU " + std::to_string(cpu) + ": " + std::strerror(error));
    return;
  }
  ready.set_value(std::string());
  while (!stopping.load(std::memory_order_relaxed)) physics::cpu_relax();
}

}  // namespace

sim::Status CpuKeepAwake::start() {
  if (!spinners_.empty()) return sim::Status();
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(0, sizeof mask, &mask) != 0) {
    return sim::Status::error(std::string("reading the CPU affinity: ") + std::strerror(errno));
  }
  stopping_.store(false);
  std::vector<std::future<std::string>> ready;
  for (std::size_t cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (!CPU_ISSET(cpu, &mask)) continue;
    std::promise<std::string> promise;
    ready.push_back(promise.get_future());
    spinners_.emplace_back(spin, cpu, std::cref(stopping_), std::move(promise));
  }
  std::string failure;
  for (std::future<std::string>& outcome : ready) {
    std::string message = outcome.get();
    if (failure.empty()) failure = std::move(message);
  }
  if (!failure.empty()) {
    stop();
    return sim::Status::error(failure);
  }
  return sim::Status();
}

void CpuKeepAwake::stop() {
  stopping_.store(true);
  for (std::thread& spinner : spinners_) spinner.join();
  spinners_.clear();
}

}  // namespace tumble
