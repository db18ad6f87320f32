#include "tumble_client/pose_stream.h"

#include <algorithm>

namespace tumble::client {
namespace {

Failure malformed(const char* encoding) {
  return Failure{FailureKind::protocol,
                 std::string("the server sent a ") + encoding + " PoseFrame whose packed bytes are malformed"};
}

}  // namespace

Result<PoseSample> PoseStream::decode(const tumble::v1::PoseFrame& frame) {
  if (frame.encoding() != tumble::v1::POSE_ENCODING_DELTA) return unpack_pose_frame(frame);
  if (auto failure = merge(frame)) return *failure;
  return sample_of(frame, bodies_);
}

Result<std::size_t> PoseStream::apply(const tumble::v1::PoseFrame& frame) {
  if (frame.encoding() == tumble::v1::POSE_ENCODING_DELTA) {
    if (auto failure = merge(frame)) return *failure;
    return bodies_.bodies.size();
  }
  if (frame.encoding() == tumble::v1::POSE_ENCODING_QUANTIZED) {
    // Unpacked to the grids' integers only: the bytes are checked, nothing converted.
    const auto poses = wire::decode_quantized_poses(frame.packed());
    if (!poses) return malformed("QUANTIZED");
    return poses->bodies.size();
  }
  auto sample = unpack_pose_frame(frame);
  if (!sample) return sample.failure();
  return sample->bodies.size();
}

std::optional<Failure> PoseStream::merge(const tumble::v1::PoseFrame& frame) {
  auto poses = wire::decode_quantized_poses(frame.packed());
  if (!poses) return malformed("DELTA");
  if (!frame.key_frame() && !has_key_frame_) {
    return Failure{FailureKind::protocol, "the server sent a DELTA PoseFrame change before any key frame"};
  }
  const auto by_id = [](const wire::QuantizedBody& a, const wire::QuantizedBody& b) { return a.id < b.id; };
  if (frame.key_frame()) {
    has_key_frame_ = true;
    bodies_ = std::move(*poses);
    std::sort(bodies_.bodies.begin(), bodies_.bodies.end(), by_id);
    return std::nullopt;
  }
  std::vector<wire::QuantizedBody>& known = bodies_.bodies;
  for (const std::uint32_t id : frame.removed_ids()) {
    const auto it = std::lower_bound(known.begin(), known.end(), wire::QuantizedBody{.id = id}, by_id);
    if (it != known.end() && it->id == id) known.erase(it);
  }
  for (const wire::QuantizedBody& body : poses->bodies) {
    const auto it = std::lower_bound(known.begin(), known.end(), body, by_id);
    if (it != known.end() && it->id == body.id) {
      *it = body;
    } else {
      known.insert(it, body);
    }
  }
  bodies_.velocities = poses->velocities;
  bodies_.step_exponent = poses->step_exponent;
  return std::nullopt;
}

}  // namespace tumble::client
