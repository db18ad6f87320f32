#include "net/delta_encoder.h"

#include "tumble/v1/protocol.pb.h"
#include "wire/frame.h"

namespace tumble::net {
namespace {

// A DELTA PoseFrame of `frame` with its header filled in.
tumble::v1::ServerMessage delta_message(const QuantizedFrame& frame) {
  tumble::v1::ServerMessage message;
  tumble::v1::PoseFrame& out = *message.mutable_pose_frame();
  out.set_subscription_id(frame.subscription_id);
  out.set_tick(frame.tick);
  out.set_sim_time(frame.sim_time);
  out.set_encoding(tumble::v1::POSE_ENCODING_DELTA);
  return message;
}

std::string encode_key(const QuantizedFrame& frame) {
  tumble::v1::ServerMessage message = delta_message(frame);
  message.mutable_pose_frame()->set_key_frame(true);
  message.mutable_pose_frame()->set_packed(wire::encode_quantized_poses(frame.bodies, frame.velocities));
  return wire::encode_frame(message);
}

}  // namespace

std::shared_ptr<const std::string> DeltaEncoder::encode(std::shared_ptr<const QuantizedFrame> frame) {
  std::shared_ptr<const std::string> bytes;
  if (!baseline_) {
    if (!frame->key_bytes) frame->key_bytes = std::make_shared<const std::string>(encode_key(*frame));
    bytes = frame->key_bytes;
  } else if (baseline_->sequence + 1 == frame->sequence) {
    // The baseline is the stream's previous frame, as for every client that keeps up.
    if (!frame->change_bytes) frame->change_bytes = std::make_shared<const std::string>(encode_change(*frame));
    bytes = frame->change_bytes;
  } else {
    bytes = std::make_shared<const std::string>(encode_change(*frame));
  }
  baseline_ = std::move(frame);
  return bytes;
}

std::string DeltaEncoder::encode_change(const QuantizedFrame& frame) {
  tumble::v1::ServerMessage message = delta_message(frame);
  tumble::v1::PoseFrame& out = *message.mutable_pose_frame();
  // Both lists are sorted by id: one merge finds the changed, new and removed bodies.
  changed_.clear();
  const std::vector<wire::QuantizedBody>& before = baseline_->bodies;
  auto old = before.begin();
  for (const wire::QuantizedBody& body : frame.bodies) {
    while (old != before.end() && old->id < body.id) out.add_removed_ids((old++)->id);
    const bool known = old != before.end() && old->id == body.id;
    if (!known || !(*old == body)) changed_.push_back(body);
    if (known) ++old;
  }
  for (; old != before.end(); ++old) out.add_removed_ids(old->id);
  out.set_packed(wire::encode_quantized_poses(changed_, frame.velocities));
  return wire::encode_frame(message);
}

}  // namespace tumble::net
