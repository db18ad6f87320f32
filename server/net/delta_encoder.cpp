#include "net/delta_encoder.h"

#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::net {

std::string DeltaEncoder::encode(const QuantizedFrame& frame) {
  tumble::v1::ServerMessage message;
  tumble::v1::PoseFrame& out = *message.mutable_pose_frame();
  out.set_subscription_id(frame.subscription_id);
  out.set_tick(frame.tick);
  out.set_sim_time(frame.sim_time);
  out.set_encoding(tumble::v1::POSE_ENCODING_DELTA);
  if (!has_baseline_) {
    out.set_key_frame(true);
    out.set_packed(wire::encode_quantized_poses(frame.bodies, frame.velocities));
  } else {
    // Both lists are sorted by id: one merge finds the changed, new and removed bodies.
    changed_.clear();
    auto old = baseline_.begin();
    for (const wire::QuantizedBody& body : frame.bodies) {
      while (old != baseline_.end() && old->id < body.id) out.add_removed_ids((old++)->id);
      const bool known = old != baseline_.end() && old->id == body.id;
      if (!known || !(*old == body)) changed_.push_back(body);
      if (known) ++old;
    }
    for (; old != baseline_.end(); ++old) out.add_removed_ids(old->id);
    out.set_packed(wire::encode_quantized_poses(changed_, frame.velocities));
  }
  baseline_ = frame.bodies;
  has_baseline_ = true;
  return wire::encode_frame(message);
}

}  // namespace tumble::net
