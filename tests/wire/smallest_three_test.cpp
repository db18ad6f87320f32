// Smallest-three orientations: layout and the error bound of the header.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "wire/smallest_three.h"

namespace tumble::wire {
namespace {

using Quat = std::array<double, 4>;

Quat random_unit(std::mt19937_64& random) {
  std::normal_distribution<double> normal;
  Quat q{normal(random), normal(random), normal(random), normal(random)};
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q) c /= n;
  return q;
}

// |a - b| after giving b the sign of a (q and -q are one rotation).
double distance(const Quat& a, const Quat& b) {
  const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const double sign = dot < 0 ? -1.0 : 1.0;
  double sum = 0;
  for (std::size_t k = 0; k < 4; ++k) sum += (a[k] - sign * b[k]) * (a[k] - sign * b[k]);
  return std::sqrt(sum);
}

TEST(SmallestThree, IdentityIsTheLargestWWithThreeZeroLevels) {
  const std::uint32_t packed = pack_smallest_three({1, 0, 0, 0});
  EXPECT_EQ(packed & 3u, 0u);              // w is the largest
  EXPECT_EQ((packed >> 2) & 1023u, 511u);  // zero is level 511
  EXPECT_EQ((packed >> 12) & 1023u, 511u);
  EXPECT_EQ((packed >> 22) & 1023u, 511u);
  EXPECT_EQ(unpack_smallest_three(packed), (Quat{1, 0, 0, 0}));
  // A quarter turn about y comes back exact too.
  const double h = 1 / std::sqrt(2.0);
  const Quat turned = unpack_smallest_three(pack_smallest_three({h, 0, h, 0}));
  EXPECT_NEAR(distance(turned, {h, 0, h, 0}), 0, 1e-12);
}

TEST(SmallestThree, NegatedQuaternionPacksTheSame) {
  EXPECT_EQ(pack_smallest_three({0.1, -0.9, 0.3, 0.2}), pack_smallest_three({-0.1, 0.9, -0.3, -0.2}));
  const Quat q = unpack_smallest_three(pack_smallest_three({0.1, -0.9, 0.3, 0.2}));
  EXPECT_GT(q[1], 0);  // the largest comes back positive
}

TEST(SmallestThree, RoundTripErrorIsWithinTheBound) {
  std::mt19937_64 random(11);
  double worst = 0;
  double worst_angle = 0;
  for (int i = 0; i < 200000; ++i) {
    const Quat q = random_unit(random);
    const Quat back = unpack_smallest_three(pack_smallest_three(q));
    const double d = distance(q, back);
    worst = std::max(worst, d);
    worst_angle = std::max(worst_angle, 4 * std::asin(std::min(1.0, d / 2)));
    EXPECT_NEAR(back[0] * back[0] + back[1] * back[1] + back[2] * back[2] + back[3] * back[3], 1, 1e-12);
  }
  EXPECT_LE(worst, kSmallestThreeQuatError);
  EXPECT_LE(worst_angle, kSmallestThreeAngleError);
  // The bound is not loose by orders of magnitude: random draws come within 3x of it.
  EXPECT_GT(worst, kSmallestThreeQuatError / 3);
}

TEST(SmallestThree, ComponentsAtTheEdgesOfTheirRangeSurvive) {
  // Two equal largest components: the others lie at +-1/sqrt2 exactly.
  const double h = 1 / std::sqrt(2.0);
  for (const Quat& q : {Quat{h, h, 0, 0}, Quat{0, 0, -h, h}, Quat{0.5, -0.5, 0.5, -0.5}}) {
    EXPECT_LE(distance(q, unpack_smallest_three(pack_smallest_three(q))), kSmallestThreeQuatError);
  }
}

}  // namespace
}  // namespace tumble::wire
