#include "sim/state_saver.h"

#include <pthread.h>

#include <algorithm>
#include <chrono>

#include "sim/log.h"
#include "sim/state_file.h"

namespace tumble::sim {

StateSaver::StateSaver(std::string path)
    : StateSaver(path, [path](const tumble::v1::WorldState& state) { return write_state_file(path, state); }) {}

StateSaver::StateSaver(std::string destination, Writer write)
    : destination_(std::move(destination)), write_(std::move(write)), thread_([this] { run(); }) {}

StateSaver::~StateSaver() { stop(); }

void StateSaver::offer(std::shared_ptr<const tumble::v1::WorldState> state,
                       std::chrono::steady_clock::duration capture) {
  const double capture_ms = std::chrono::duration<double, std::milli>(capture).count();
  {
    std::lock_guard lock(mutex_);
    waiting_ = std::move(state);
    report_.last_capture_ms = capture_ms;
    report_.capture_ms_max = std::max(report_.capture_ms_max, capture_ms);
  }
  wakeup_.notify_one();
}

void StateSaver::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wakeup_.notify_one();
  if (thread_.joinable()) thread_.join();
}

std::uint64_t StateSaver::written() const {
  std::lock_guard lock(mutex_);
  return report_.written;
}

StateSaver::Report StateSaver::report() const {
  std::lock_guard lock(mutex_);
  return report_;
}

void StateSaver::run() {
  pthread_setname_np(pthread_self(), "tumbled-saver");
  std::unique_lock lock(mutex_);
  for (;;) {
    wakeup_.wait(lock, [this] { return stopping_ || waiting_ != nullptr; });
    if (waiting_ == nullptr) return;  // stopping, nothing left to write
    std::shared_ptr<const tumble::v1::WorldState> state = std::move(waiting_);
    waiting_ = nullptr;
    lock.unlock();
    const auto start = std::chrono::steady_clock::now();
    const Status status = write_(*state);
    const double write_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (status.ok()) {
      sim_log().debug("checkpoint of tick {} written to {}", state->tick(), destination_);
    } else {
      sim_log().error("checkpoint of tick {} not written: {}", state->tick(), status.message());
    }
    lock.lock();
    if (status.ok()) {
      ++report_.written;
      report_.last_tick = state->tick();
      report_.last_bytes = state->ByteSizeLong();
      report_.last_write_ms = write_ms;
      report_.write_ms_max = std::max(report_.write_ms_max, write_ms);
    } else {
      ++report_.failed;
    }
  }
}

}  // namespace tumble::sim
