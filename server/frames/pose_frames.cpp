#include "frames/pose_frames.h"

#include <algorithm>

namespace tumble::frames {

void fill_full(const sim::Snapshot& snapshot, bool all_bodies, const std::vector<physics::BodyId>& filter,
               bool velocities, tumble::v1::PoseFrame* out) {
  tumble::v1::PoseFrame& frame = *out;
  const std::size_t n = all_bodies ? snapshot.body_count() : filter.size();
  frame.mutable_ids()->Reserve(static_cast<int>(n));
  frame.mutable_positions()->Reserve(static_cast<int>(3 * n));
  frame.mutable_orientations()->Reserve(static_cast<int>(4 * n));
  if (velocities) {
    frame.mutable_linear_velocities()->Reserve(static_cast<int>(3 * n));
    frame.mutable_angular_velocities()->Reserve(static_cast<int>(3 * n));
  }
  for (std::size_t i = 0; i < snapshot.body_count(); ++i) {
    const physics::BodyId id = snapshot.ids[i];
    if (!all_bodies && !std::binary_search(filter.begin(), filter.end(), id)) continue;
    frame.add_ids(id);
    for (std::size_t k = 0; k < 3; ++k) frame.add_positions(static_cast<float>(snapshot.positions[3 * i + k]));
    for (std::size_t k = 0; k < 4; ++k) frame.add_orientations(static_cast<float>(snapshot.orientations[4 * i + k]));
    if (!velocities) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      frame.add_linear_velocities(static_cast<float>(snapshot.linear_velocities[3 * i + k]));
      frame.add_angular_velocities(static_cast<float>(snapshot.angular_velocities[3 * i + k]));
    }
  }
}

void fill_joints(const sim::Snapshot& snapshot, tumble::v1::PoseFrame* out) {
  const int n = static_cast<int>(snapshot.joint_ids.size());
  out->mutable_joint_ids()->Reserve(n);
  out->mutable_joint_positions()->Reserve(n);
  out->mutable_joint_speeds()->Reserve(n);
  out->mutable_joint_motor_impulses()->Reserve(n);
  for (std::size_t i = 0; i < snapshot.joint_ids.size(); ++i) {
    out->add_joint_ids(snapshot.joint_ids[i]);
    out->add_joint_positions(static_cast<float>(snapshot.joint_positions[i]));
    out->add_joint_speeds(static_cast<float>(snapshot.joint_speeds[i]));
    out->add_joint_motor_impulses(static_cast<float>(snapshot.joint_motor_impulses[i]));
  }
}

void fill_quantized(const std::vector<wire::QuantizedBody>& bodies, bool velocities, tumble::v1::PoseFrame* out) {
  out->set_encoding(tumble::v1::POSE_ENCODING_QUANTIZED);
  out->set_packed(wire::encode_quantized_poses(bodies, velocities));
}

void fill_delta_key(const std::vector<wire::QuantizedBody>& bodies, bool velocities, tumble::v1::PoseFrame* out) {
  out->set_encoding(tumble::v1::POSE_ENCODING_DELTA);
  out->set_key_frame(true);
  out->set_packed(wire::encode_quantized_poses(bodies, velocities));
}

void fill_delta_change(const std::vector<wire::QuantizedBody>& before, const std::vector<wire::QuantizedBody>& after,
                       bool velocities, tumble::v1::PoseFrame* out, std::vector<wire::QuantizedBody>* changed) {
  out->set_encoding(tumble::v1::POSE_ENCODING_DELTA);
  // Both lists are sorted by id: one merge finds the changed, new and removed bodies.
  changed->clear();
  auto old = before.begin();
  for (const wire::QuantizedBody& body : after) {
    while (old != before.end() && old->id < body.id) out->add_removed_ids((old++)->id);
    const bool known = old != before.end() && old->id == body.id;
    if (!known || !(*old == body)) changed->push_back(body);
    if (known) ++old;
  }
  for (; old != before.end(); ++old) out->add_removed_ids(old->id);
  out->set_packed(wire::encode_quantized_poses(*changed, velocities));
}

}  // namespace tumble::frames
