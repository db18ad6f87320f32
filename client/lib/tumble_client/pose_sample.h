// PoseSample: a PoseFrame's packed arrays unpacked into one record per body.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "tumble/v1/protocol.pb.h"
#include "tumble_client/result.h"
#include "wire/quantized_poses.h"

namespace tumble::client {

// One body's state as the server sent it, in float32 like the FULL
// encoding (QUANTIZED and DELTA values are converted from their grids). All
// vectors are in the world frame; the velocities are zero when the
// subscription asked for poses only.
struct BodyPose {
  std::uint32_t id = 0;
  std::array<float, 3> position{};          // m, centre of mass
  std::array<float, 4> orientation{};       // unit quaternion, body to world, [w, x, y, z]
  std::array<float, 3> linear_velocity{};   // m/s
  std::array<float, 3> angular_velocity{};  // rad/s
};

// One joint's state as a frame of a subscription with joints carries it
// (PoseFrame.joint_ids ...), in float32.
struct JointSample {
  std::uint32_t id = 0;
  float position = 0;       // rad (hinge, ball) or m (slider, distance)
  float speed = 0;          // rad/s or m/s
  float motor_impulse = 0;  // N m s or N s, over the last step
};

// The subscribed bodies after the step of `tick`, in the frame's order.
struct PoseSample {
  std::uint32_t subscription_id = 0;
  std::uint64_t tick = 0;
  double sim_time = 0;         // s
  bool has_velocities = true;  // false for a subscription to POSE_FIELDS_POSE
  std::vector<BodyPose> bodies;
  std::vector<JointSample> joints;  // every joint, by id, when the subscription asked for them
};

// Unpacks a FULL or QUANTIZED `frame`. Fails with kind protocol when an
// array's length is not the number of ids times its width (3 or 4) (both
// velocity arrays may instead be empty: a pose-only frame), when `packed`
// does not follow its layout, or for a DELTA frame, which only a PoseStream
// can complete.
Result<PoseSample> unpack_pose_frame(const tumble::v1::PoseFrame& frame);

// The sample of a decoded QUANTIZED or DELTA `packed` field, bodies in its
// order, and the frame's joints. Fails with kind protocol when the joint
// arrays are not all as long as joint_ids.
Result<PoseSample> sample_of(const tumble::v1::PoseFrame& frame, const wire::QuantizedPoses& poses);

}  // namespace tumble::client
