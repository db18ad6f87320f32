// Unit quaternions in 32 bits, "smallest three": the index of the largest
// component by magnitude, and the other three on a 10-bit grid. Since
// w^2 + x^2 + y^2 + z^2 = 1, the largest is recovered as the square root of
// one minus the others' squares; q and -q are the same rotation, so the
// quaternion is negated first if need be to make the largest positive.
//
// Layout (bit 0 = least significant):
//   bits 0-1    index of the largest component in w, x, y, z order (0-3)
//   bits 2-11   the first of the other three, in w, x, y, z order
//   bits 12-21  the second
//   bits 22-31  the third
// Each of the three lies in [-1/sqrt2, 1/sqrt2] (none can exceed the largest
// in magnitude) and is stored as round(c * sqrt2 * 511) + 511, a level from 0
// to 1022 with zero exactly at 511 (so the identity and the quarter turns
// come back exact); the grid step is 1 / (511 sqrt2) and the rounding error
// at most half of it, 6.92e-4, per component.
//
// Error bound: with d = 6.92e-4 on each of the three, their error vector is at
// most sqrt3 d long; the recovered largest component L = sqrt(1 - |s|^2)
// moves by |s . ds| / L <= sqrt3 |ds| (|s| <= sqrt3 L and |s|^2 <= 3/4 give
// |s| / L <= sqrt3), so |q' - q| <= 2 sqrt3 d = 2.397e-3 to first order, and
// the rotation angle between them, 4 asin(|q' - q| / 2), is at most 4.8e-3
// rad (0.27 degrees).
#pragma once

#include <array>
#include <cstdint>

namespace tumble::wire {

// The largest |q' - q| between a unit quaternion and its decoding (with q
// sign-normalised as the encoding does), and the largest rotation angle
// between them, rad, each rounded up from the bound above.
inline constexpr double kSmallestThreeQuatError = 2.4e-3;
inline constexpr double kSmallestThreeAngleError = 4.8e-3;

// Packs a unit quaternion [w, x, y, z]; it need not be normalised exactly.
std::uint32_t pack_smallest_three(const std::array<double, 4>& q);

// The unit quaternion [w, x, y, z] of a packed value, its largest component
// positive.
std::array<double, 4> unpack_smallest_three(std::uint32_t packed);

}  // namespace tumble::wire
