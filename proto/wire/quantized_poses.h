// The `packed` bytes of a QUANTIZED or DELTA PoseFrame: body ids and states
// on fixed grids, encoded and decoded by the same code on both ends.
//
// Grids:
//   position          whole multiples of 2^-k m (k = kPositionStepExponent,
//                     1/1024 m), stored relative to a per-frame origin: the
//                     smallest cell of the frame's bodies on each axis. No
//                     world bounds: each axis gets as many bits as the
//                     frame's extent on it needs. Error <= step / 2; cells
//                     are clamped only beyond +-2^52 (4.4e12 m at 1/1024).
//   orientation       smallest three in 32 bits (wire/smallest_three.h).
//   linear velocity   1/128 m/s steps in 16 bits: +-255.99 m/s, beyond which
//                     a component is clamped. Error <= 1/256 m/s inside it.
//   angular velocity  1/256 rad/s steps in 16 bits: +-127.99 rad/s, clamped
//                     beyond. Error <= 1/512 rad/s inside it.
//
// Layout, in order:
//   varint  n, the number of bodies
//   varint  flags: bit 0 set when velocities are present
//   varint  k: the position step is 2^-k m
//   n varints  ids, each as zigzag(id - previous id), the first against 0
//   if n > 0:
//     3 varints  origin cell on x, y, z, zigzag-coded
//     3 bytes    bit widths wx, wy, wz of the cell offsets (0-63)
//     bit stream (wire/bit_stream.h, LSB first), per body in id order:
//       wx, wy, wz bits   cell - origin on x, y, z
//       32 bits           orientation, smallest three
//       with velocities: 6 x 16 bits, linear x, y, z then angular x, y, z,
//                        two's complement
//     padded with zero bits to a whole byte
// A pose-only body costs 4 bytes of orientation, one of id while ids follow
// each other closely (a gap of 64 or more costs two) and (wx + wy + wz) / 8
// of position: within 10 bytes while wx + wy + wz <= 39, as when the bodies
// span less than 16 m x 16 m x 2 m, or 8 m on every axis.
//
// Thread: free functions, no shared state.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace tumble::wire {

inline constexpr unsigned kPositionStepExponent = 10;
inline constexpr double kPositionStep = 1.0 / (1u << kPositionStepExponent);  // m
inline constexpr double kLinearVelocityStep = 1.0 / 128;                      // m/s
inline constexpr double kAngularVelocityStep = 1.0 / 256;                     // rad/s

// One body's state on the grids. Two bodies whose quantized states are equal
// look the same to a client.
struct QuantizedBody {
  std::uint32_t id = 0;
  std::array<std::int64_t, 3> cell{};              // position / step
  std::uint32_t orientation = 0;                   // smallest three
  std::array<std::int16_t, 3> linear_velocity{};   // / kLinearVelocityStep
  std::array<std::int16_t, 3> angular_velocity{};  // / kAngularVelocityStep

  bool operator==(const QuantizedBody&) const = default;
};

// A decoded `packed` field.
struct QuantizedPoses {
  bool velocities = false;
  unsigned step_exponent = kPositionStepExponent;
  std::vector<QuantizedBody> bodies;
};

// Puts a body's state on the grids: position [3] m, orientation [4] w x y z,
// velocities [3] m/s and rad/s (null: zero).
QuantizedBody quantize_body(std::uint32_t id, const double* position, const double* orientation,
                            const double* linear_velocity, const double* angular_velocity,
                            unsigned step_exponent = kPositionStepExponent);

// The state a QuantizedBody stands for.
std::array<double, 3> position_of(const QuantizedBody& body, unsigned step_exponent = kPositionStepExponent);
std::array<double, 4> orientation_of(const QuantizedBody& body);
std::array<double, 3> linear_velocity_of(const QuantizedBody& body);
std::array<double, 3> angular_velocity_of(const QuantizedBody& body);

// The bytes of `bodies` in the layout above.
std::string encode_quantized_poses(std::span<const QuantizedBody> bodies, bool velocities,
                                   unsigned step_exponent = kPositionStepExponent);

// The bodies of `bytes`; nullopt when they do not follow the layout (cut
// short, a width over 63, bytes left over).
std::optional<QuantizedPoses> decode_quantized_poses(std::string_view bytes);

}  // namespace tumble::wire
