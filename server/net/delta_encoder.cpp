#include "net/delta_encoder.h"

#include "frames/pose_frames.h"
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
  out.MergeFrom(frame.joints);  // the joints' states go whole in every frame
  return message;
}

std::string encode_key(const QuantizedFrame& frame) {
  tumble::v1::ServerMessage message = delta_message(frame);
  frames::fill_delta_key(frame.bodies, frame.velocities, message.mutable_pose_frame());
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
  frames::fill_delta_change(baseline_->bodies, frame.bodies, frame.velocities, message.mutable_pose_frame(), &changed_);
  return wire::encode_frame(message);
}

}  // namespace tumble::net
