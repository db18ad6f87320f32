#include "wire/smallest_three.h"

#include <algorithm>
#include <cmath>

namespace tumble::wire {
namespace {

constexpr double kSqrt2 = 1.4142135623730951;
constexpr unsigned kComponentBits = 10;
constexpr std::uint32_t kComponentMask = (1u << kComponentBits) - 1;
constexpr long kZeroLevel = 511;  // levels 0..1022, symmetric about zero

}  // namespace

std::uint32_t pack_smallest_three(const std::array<double, 4>& q) {
  std::size_t largest = 0;
  for (std::size_t k = 1; k < 4; ++k) {
    if (std::abs(q[k]) > std::abs(q[largest])) largest = k;
  }
  const double sign = q[largest] < 0 ? -1.0 : 1.0;
  std::uint32_t packed = static_cast<std::uint32_t>(largest);
  unsigned shift = 2;
  for (std::size_t k = 0; k < 4; ++k) {
    if (k == largest) continue;
    // [-1/sqrt2, 1/sqrt2] onto [0, 1022]; clamped against rounding outside it.
    const long offset = std::clamp(std::lround(sign * q[k] * kSqrt2 * kZeroLevel), -kZeroLevel, kZeroLevel);
    const auto level = static_cast<std::uint32_t>(offset + kZeroLevel);
    packed |= level << shift;
    shift += kComponentBits;
  }
  return packed;
}

std::array<double, 4> unpack_smallest_three(std::uint32_t packed) {
  const std::size_t largest = packed & 3u;
  std::array<double, 4> q{};
  double small_squares = 0;
  unsigned shift = 2;
  for (std::size_t k = 0; k < 4; ++k) {
    if (k == largest) continue;
    const auto level = static_cast<long>((packed >> shift) & kComponentMask);
    q[k] = static_cast<double>(level - kZeroLevel) / (kZeroLevel * kSqrt2);
    small_squares += q[k] * q[k];
    shift += kComponentBits;
  }
  q[largest] = std::sqrt(std::max(0.0, 1.0 - small_squares));
  // Rounding can leave the four a hair off unit length (or the three over it).
  const double norm = std::sqrt(small_squares + q[largest] * q[largest]);
  for (double& c : q) c /= norm;
  return q;
}

}  // namespace tumble::wire
