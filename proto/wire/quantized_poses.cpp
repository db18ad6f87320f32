#include "wire/quantized_poses.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "wire/bit_stream.h"
#include "wire/smallest_three.h"

namespace tumble::wire {
namespace {

constexpr unsigned kVelocityBits = 16;
constexpr unsigned kMaxWidth = 63;
constexpr std::uint64_t kVelocitiesFlag = 1;
// Cells are kept within +-2^52 so that an offset (at most 2^53) fits its
// int64 and its width stays under 64 bits.
constexpr double kMaxCell = 4503599627370496.0;  // 2^52

std::int16_t velocity_level(double value, double step) {
  // Symmetric range: -32767..32767, so negation never overflows.
  return static_cast<std::int16_t>(std::clamp(std::round(value / step), -32767.0, 32767.0));
}

std::array<std::int16_t, 3> velocity_levels(const double* v, double step) {
  if (v == nullptr) return {};
  return {velocity_level(v[0], step), velocity_level(v[1], step), velocity_level(v[2], step)};
}

std::array<double, 3> velocity_values(const std::array<std::int16_t, 3>& levels, double step) {
  return {levels[0] * step, levels[1] * step, levels[2] * step};
}

}  // namespace

QuantizedBody quantize_body(std::uint32_t id, const double* position, const double* orientation,
                            const double* linear_velocity, const double* angular_velocity, unsigned step_exponent) {
  QuantizedBody body;
  body.id = id;
  const double cells_per_metre = std::ldexp(1.0, static_cast<int>(step_exponent));
  for (std::size_t a = 0; a < 3; ++a) {
    body.cell[a] = std::llround(std::clamp(position[a] * cells_per_metre, -kMaxCell, kMaxCell));
  }
  body.orientation = pack_smallest_three({orientation[0], orientation[1], orientation[2], orientation[3]});
  body.linear_velocity = velocity_levels(linear_velocity, kLinearVelocityStep);
  body.angular_velocity = velocity_levels(angular_velocity, kAngularVelocityStep);
  return body;
}

std::array<double, 3> position_of(const QuantizedBody& body, unsigned step_exponent) {
  const int e = -static_cast<int>(step_exponent);
  return {std::ldexp(static_cast<double>(body.cell[0]), e), std::ldexp(static_cast<double>(body.cell[1]), e),
          std::ldexp(static_cast<double>(body.cell[2]), e)};
}

std::array<double, 4> orientation_of(const QuantizedBody& body) { return unpack_smallest_three(body.orientation); }

std::array<double, 3> linear_velocity_of(const QuantizedBody& body) {
  return velocity_values(body.linear_velocity, kLinearVelocityStep);
}

std::array<double, 3> angular_velocity_of(const QuantizedBody& body) {
  return velocity_values(body.angular_velocity, kAngularVelocityStep);
}

std::string encode_quantized_poses(std::span<const QuantizedBody> bodies, bool velocities, unsigned step_exponent) {
  std::string out;
  append_varint(bodies.size(), out);
  append_varint(velocities ? kVelocitiesFlag : 0, out);
  append_varint(step_exponent, out);
  std::int64_t previous_id = 0;
  for (const QuantizedBody& body : bodies) {
    append_varint(zigzag(std::int64_t{body.id} - previous_id), out);
    previous_id = body.id;
  }
  if (bodies.empty()) return out;

  std::array<std::int64_t, 3> origin = bodies.front().cell;
  std::array<std::int64_t, 3> top = origin;
  for (const QuantizedBody& body : bodies) {
    for (std::size_t a = 0; a < 3; ++a) {
      origin[a] = std::min(origin[a], body.cell[a]);
      top[a] = std::max(top[a], body.cell[a]);
    }
  }
  std::array<unsigned, 3> width{};
  for (std::size_t a = 0; a < 3; ++a) {
    append_varint(zigzag(origin[a]), out);
    // Bits for offsets 0..top-origin; bit_width(0) = 0 when every body shares the cell.
    width[a] = static_cast<unsigned>(std::bit_width(static_cast<std::uint64_t>(top[a] - origin[a])));
  }
  for (unsigned w : width) out.push_back(static_cast<char>(w));

  BitWriter bits(out);
  for (const QuantizedBody& body : bodies) {
    for (std::size_t a = 0; a < 3; ++a) bits.write(static_cast<std::uint64_t>(body.cell[a] - origin[a]), width[a]);
    bits.write(body.orientation, 32);
    if (!velocities) continue;
    for (std::int16_t level : body.linear_velocity) bits.write(static_cast<std::uint16_t>(level), kVelocityBits);
    for (std::int16_t level : body.angular_velocity) bits.write(static_cast<std::uint16_t>(level), kVelocityBits);
  }
  return out;
}

std::optional<QuantizedPoses> decode_quantized_poses(std::string_view bytes) {
  const auto count = take_varint(bytes);
  const auto flags = take_varint(bytes);
  const auto exponent = take_varint(bytes);
  // Each body takes at least one byte of id, so a count beyond the bytes is a lie.
  if (!count || !flags || !exponent || *count > bytes.size() || *exponent > 64) return std::nullopt;
  QuantizedPoses poses;
  poses.velocities = (*flags & kVelocitiesFlag) != 0;
  poses.step_exponent = static_cast<unsigned>(*exponent);
  poses.bodies.resize(*count);
  std::int64_t id = 0;
  for (QuantizedBody& body : poses.bodies) {
    const auto delta = take_varint(bytes);
    if (!delta) return std::nullopt;
    id += unzigzag(*delta);
    if (id < 0 || id > std::int64_t{UINT32_MAX}) return std::nullopt;
    body.id = static_cast<std::uint32_t>(id);
  }
  if (poses.bodies.empty()) {
    if (!bytes.empty()) return std::nullopt;
    return poses;
  }

  std::array<std::int64_t, 3> origin{};
  for (std::int64_t& o : origin) {
    const auto coded = take_varint(bytes);
    if (!coded) return std::nullopt;
    o = unzigzag(*coded);
  }
  if (bytes.size() < 3) return std::nullopt;
  std::array<unsigned, 3> width{};
  for (std::size_t a = 0; a < 3; ++a) {
    width[a] = static_cast<unsigned char>(bytes[a]);
    if (width[a] > kMaxWidth) return std::nullopt;
  }
  bytes.remove_prefix(3);

  BitReader bits(bytes);
  const auto signed_level = [](std::uint64_t raw) {
    return static_cast<std::int16_t>(static_cast<std::uint16_t>(raw));
  };
  for (QuantizedBody& body : poses.bodies) {
    for (std::size_t a = 0; a < 3; ++a) {
      const auto offset = bits.read(width[a]);
      if (!offset) return std::nullopt;
      body.cell[a] = origin[a] + static_cast<std::int64_t>(*offset);
    }
    const auto orientation = bits.read(32);
    if (!orientation) return std::nullopt;
    body.orientation = static_cast<std::uint32_t>(*orientation);
    if (!poses.velocities) continue;
    for (auto* levels : {&body.linear_velocity, &body.angular_velocity}) {
      for (std::int16_t& level : *levels) {
        const auto raw = bits.read(kVelocityBits);
        if (!raw) return std::nullopt;
        level = signed_level(*raw);
      }
    }
  }
  // Only the padding of the last byte may remain.
  const std::size_t used_bits = [&] {
    std::size_t per_body = width[0] + width[1] + width[2] + 32 + (poses.velocities ? 6 * kVelocityBits : 0);
    return per_body * poses.bodies.size();
  }();
  if ((used_bits + 7) / 8 != bytes.size()) return std::nullopt;
  return poses;
}

}  // namespace tumble::wire
