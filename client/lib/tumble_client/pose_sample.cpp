#include "tumble_client/pose_sample.h"

#include <optional>
#include <string>

namespace tumble::client {
namespace {

using FloatArray = google::protobuf::RepeatedField<float>;

// A failure unless `values` holds `width` floats for each of `count` bodies.
bool has_width(const FloatArray& values, std::size_t count, std::size_t width) {
  return static_cast<std::size_t>(values.size()) == count * width;
}

template <std::size_t N>
std::array<float, N> slice(const FloatArray& values, std::size_t body) {
  std::array<float, N> out{};
  for (std::size_t k = 0; k < N; ++k) out[k] = values.Get(static_cast<int>(body * N + k));
  return out;
}

template <std::size_t N>
std::array<float, N> to_float(const std::array<double, N>& values) {
  std::array<float, N> out{};
  for (std::size_t k = 0; k < N; ++k) out[k] = static_cast<float>(values[k]);
  return out;
}

// The frame's joints into sample.joints; a failure unless each of its joint
// arrays has a value for every joint id.
std::optional<Failure> read_joints(const tumble::v1::PoseFrame& frame, PoseSample* sample) {
  const int count = frame.joint_ids_size();
  if (frame.joint_positions_size() != count || frame.joint_speeds_size() != count ||
      frame.joint_motor_impulses_size() != count) {
    return Failure{FailureKind::protocol, "the server sent a PoseFrame with " + std::to_string(count) +
                                              " joint ids but joint arrays of other lengths"};
  }
  sample->joints.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    sample->joints.push_back(
        {frame.joint_ids(i), frame.joint_positions(i), frame.joint_speeds(i), frame.joint_motor_impulses(i)});
  }
  return std::nullopt;
}

}  // namespace

Result<PoseSample> sample_of(const tumble::v1::PoseFrame& frame, const wire::QuantizedPoses& poses) {
  PoseSample sample;
  sample.subscription_id = frame.subscription_id();
  sample.tick = frame.tick();
  sample.sim_time = frame.sim_time();
  sample.has_velocities = poses.velocities;
  sample.bodies.reserve(poses.bodies.size());
  for (const wire::QuantizedBody& body : poses.bodies) {
    BodyPose pose;
    pose.id = body.id;
    pose.position = to_float(wire::position_of(body, poses.step_exponent));
    pose.orientation = to_float(wire::orientation_of(body));
    if (poses.velocities) {
      pose.linear_velocity = to_float(wire::linear_velocity_of(body));
      pose.angular_velocity = to_float(wire::angular_velocity_of(body));
    }
    sample.bodies.push_back(pose);
  }
  if (auto failure = read_joints(frame, &sample)) return *failure;
  return sample;
}

Result<PoseSample> unpack_pose_frame(const tumble::v1::PoseFrame& frame) {
  if (frame.encoding() == tumble::v1::POSE_ENCODING_DELTA) {
    return Failure{FailureKind::protocol, "a DELTA PoseFrame cannot be read without the frames before it"};
  }
  if (frame.encoding() == tumble::v1::POSE_ENCODING_QUANTIZED) {
    const auto poses = wire::decode_quantized_poses(frame.packed());
    if (!poses) {
      return Failure{FailureKind::protocol, "the server sent a QUANTIZED PoseFrame whose packed bytes are malformed"};
    }
    return sample_of(frame, *poses);
  }
  const auto count = static_cast<std::size_t>(frame.ids_size());
  // A pose-only frame has neither velocity array; checked as width 0.
  const bool has_velocities = count == 0 || frame.linear_velocities_size() > 0 || frame.angular_velocities_size() > 0;
  const std::size_t velocity_width = has_velocities ? 3 : 0;
  struct Field {
    const FloatArray& values;
    std::size_t width;
    const char* name;
  };
  const Field fields[] = {
      {frame.positions(), 3, "positions"},
      {frame.orientations(), 4, "orientations"},
      {frame.linear_velocities(), velocity_width, "linear_velocities"},
      {frame.angular_velocities(), velocity_width, "angular_velocities"},
  };
  for (const Field& field : fields) {
    if (!has_width(field.values, count, field.width)) {
      return Failure{FailureKind::protocol, "the server sent a PoseFrame with " + std::to_string(count) + " ids but " +
                                                std::to_string(field.values.size()) + " " + field.name + " (expected " +
                                                std::to_string(count * field.width) + ")"};
    }
  }

  PoseSample sample;
  sample.subscription_id = frame.subscription_id();
  sample.tick = frame.tick();
  sample.sim_time = frame.sim_time();
  sample.has_velocities = has_velocities;
  sample.bodies.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    BodyPose pose;
    pose.id = frame.ids(static_cast<int>(i));
    pose.position = slice<3>(frame.positions(), i);
    pose.orientation = slice<4>(frame.orientations(), i);
    if (has_velocities) {
      pose.linear_velocity = slice<3>(frame.linear_velocities(), i);
      pose.angular_velocity = slice<3>(frame.angular_velocities(), i);
    }
    sample.bodies.push_back(pose);
  }
  if (auto failure = read_joints(frame, &sample)) return *failure;
  return sample;
}

}  // namespace tumble::client
