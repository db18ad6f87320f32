#include "sim/run_record.h"

#include <utility>

namespace tumble::sim {

void RunRecord::set_checkpoints(Clock::duration interval, CheckpointSink sink, Capture capture) {
  checkpoint_interval_ = interval;
  checkpoint_sink_ = std::move(sink);
  capture_ = std::move(capture);
  next_checkpoint_ = Clock::now() + interval;
}

void RunRecord::record(std::uint64_t tick, const tumble::v1::ClientMessage& message) {
  if (journal_ == nullptr) return;
  switch (message.kind_case()) {
    case tumble::v1::ClientMessage::kListBodies:
    case tumble::v1::ClientMessage::kGetStats:
      return;  // they read the world and change nothing
    default:
      break;
  }
  journal_->record(tick, message);
  journal_dirty_ = true;
}

void RunRecord::flush() {
  if (!journal_dirty_) return;
  journal_->flush();
  journal_dirty_ = false;
}

void RunRecord::finish(std::uint64_t tick) {
  if (journal_ != nullptr) journal_->finish(tick);
  journal_ = nullptr;  // finished: a second call (the destructor's stop()) writes nothing
}

void RunRecord::checkpoint_if_due() {
  if (!checkpoint_sink_) return;
  const Clock::time_point now = Clock::now();
  if (now < next_checkpoint_) return;
  next_checkpoint_ = now + checkpoint_interval_;
  // A paused, untouched world is already on disk.
  if (world_version_ == checkpointed_version_) return;
  checkpointed_version_ = world_version_;
  const Clock::time_point start = Clock::now();
  auto state = std::make_shared<tumble::v1::WorldState>();
  capture_(state.get());
  checkpoint_sink_(std::move(state), Clock::now() - start);
}

}  // namespace tumble::sim
