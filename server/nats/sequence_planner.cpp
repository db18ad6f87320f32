#include "nats/sequence_planner.h"

namespace tumble::nats {

SequencePlanner::Frame SequencePlanner::next(double sim_time_s) {
  Frame frame;
  frame.sequence = ++sequence_;
  const double interval = changed_since_key_ ? key_interval_s_ : rest_key_interval_s_;
  // A Reset does not turn the clock back, but a restarted world may start
  // below the last key frame's time: that, too, is time for a key frame.
  frame.key = key_due_ || sim_time_s - last_key_time_ >= interval || sim_time_s < last_key_time_;
  if (frame.key) {
    last_key_time_ = sim_time_s;
    key_due_ = false;
    changed_since_key_ = false;
  }
  return frame;
}

}  // namespace tumble::nats
