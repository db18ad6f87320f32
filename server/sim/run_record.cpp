#include "sim/run_record.h"

#include <google/protobuf/arena.h>

#include <memory>
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
    case tumble::v1::ClientMessage::kListJoints:
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
  // On an arena: the capture takes its thousands of small messages from a
  // few large blocks instead of the heap one by one, and the whole state
  // goes at once, on whichever thread drops it last (the writer's).
  google::protobuf::ArenaOptions options;
  options.start_block_size = 64 << 10;
  options.max_block_size = 1 << 20;
  struct Owner {
    explicit Owner(const google::protobuf::ArenaOptions& options) : arena(options) {}
    std::shared_ptr<const void> kept;  // what the state points into: goes after the arena
    google::protobuf::Arena arena;
  };
  auto owner = std::make_shared<Owner>(options);
  auto* state = google::protobuf::Arena::CreateMessage<tumble::v1::WorldState>(&owner->arena);
  owner->kept = capture_(state);
  checkpoint_sink_(std::shared_ptr<const tumble::v1::WorldState>(owner, state), Clock::now() - start);
}

}  // namespace tumble::sim
