// The packed bytes of QUANTIZED and DELTA frames: layout, sizes, round-trip
// error and malformed input.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "wire/bit_stream.h"
#include "wire/quantized_poses.h"
#include "wire/smallest_three.h"

namespace tumble::wire {
namespace {

struct State {
  std::array<double, 3> x;
  std::array<double, 4> q;
  std::array<double, 3> v;
  std::array<double, 3> w;
};

State random_state(std::mt19937_64& random, double extent) {
  std::uniform_real_distribution<double> position(-extent, extent);
  std::uniform_real_distribution<double> speed(-20, 20);
  std::normal_distribution<double> normal;
  State s{};
  for (double& c : s.x) c = position(random);
  for (double& c : s.q) c = normal(random);
  const double n = std::sqrt(s.q[0] * s.q[0] + s.q[1] * s.q[1] + s.q[2] * s.q[2] + s.q[3] * s.q[3]);
  for (double& c : s.q) c /= n;
  for (double& c : s.v) c = speed(random);
  for (double& c : s.w) c = speed(random);
  return s;
}

TEST(QuantizedPoses, HeaderAndIdsFollowTheLayout) {
  const double x[3] = {0, 0, 0};
  const double q[4] = {1, 0, 0, 0};
  const std::vector<QuantizedBody> bodies = {quantize_body(5, x, q, nullptr, nullptr),
                                             quantize_body(6, x, q, nullptr, nullptr)};
  const std::string bytes = encode_quantized_poses(bodies, false);
  // n=2, flags=0, k=10, ids +5 +1 zigzagged, origin 0 0 0, widths 0 0 0, 2 x 32 bits.
  const std::string header("\x02\x00\x0a\x0a\x02\x00\x00\x00\x00\x00\x00", 11);
  ASSERT_EQ(bytes.size(), header.size() + 8);
  EXPECT_EQ(bytes.substr(0, header.size()), header);
}

TEST(QuantizedPoses, RoundTripIsWithinHalfAGridStep) {
  std::mt19937_64 random(3);
  std::vector<QuantizedBody> bodies;
  std::vector<State> states;
  for (std::uint32_t id = 1; id <= 500; ++id) {
    states.push_back(random_state(random, 100));
    const State& s = states.back();
    bodies.push_back(quantize_body(id * 3, s.x.data(), s.q.data(), s.v.data(), s.w.data()));
  }
  const auto decoded = decode_quantized_poses(encode_quantized_poses(bodies, true));
  ASSERT_TRUE(decoded.has_value());
  ASSERT_EQ(decoded->bodies.size(), bodies.size());
  EXPECT_TRUE(decoded->velocities);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const QuantizedBody& body = decoded->bodies[i];
    EXPECT_EQ(body, bodies[i]);
    const auto x = position_of(body, decoded->step_exponent);
    const auto v = linear_velocity_of(body);
    const auto w = angular_velocity_of(body);
    for (std::size_t a = 0; a < 3; ++a) {
      EXPECT_LE(std::abs(x[a] - states[i].x[a]), kPositionStep / 2);
      EXPECT_LE(std::abs(v[a] - states[i].v[a]), kLinearVelocityStep / 2);
      EXPECT_LE(std::abs(w[a] - states[i].w[a]), kAngularVelocityStep / 2);
    }
  }
}

TEST(QuantizedPoses, VelocitiesBeyondTheirRangeAreClamped) {
  const double x[3] = {0, 0, 0};
  const double q[4] = {1, 0, 0, 0};
  const double fast[3] = {1000, -1000, 0};
  const QuantizedBody body = quantize_body(1, x, q, fast, fast);
  EXPECT_NEAR(linear_velocity_of(body)[0], 32767 * kLinearVelocityStep, 1e-12);
  EXPECT_NEAR(angular_velocity_of(body)[1], -32767 * kAngularVelocityStep, 1e-12);
}

TEST(QuantizedPoses, APoseOnlyGridOf900BodiesTakesUnderTenBytesEach) {
  // 30 x 30 bodies 0.5 m apart, under 2 m up: 14.5 m x 14.5 m x 1.7 m, so
  // 14 + 14 + 11 bits of position, 32 of orientation and a byte of id.
  std::vector<QuantizedBody> bodies;
  std::mt19937_64 random(5);
  for (std::uint32_t id = 1; id <= 900; ++id) {
    State s = random_state(random, 1);
    s.x = {0.5 * ((id - 1) % 30), 0.5 * ((id - 1) / 30), 2.0 * (id % 7) / 7};
    bodies.push_back(quantize_body(id, s.x.data(), s.q.data(), nullptr, nullptr));
  }
  const std::string bytes = encode_quantized_poses(bodies, false);
  EXPECT_LE(static_cast<double>(bytes.size()) / static_cast<double>(bodies.size()), 10.0);
  EXPECT_EQ(decode_quantized_poses(bytes)->bodies, bodies);
}

TEST(QuantizedPoses, FarPositionsAreClampedAndStillRoundTrip) {
  const double far[3] = {1e13, -1e13, 0};
  const double near[3] = {0, 0, 0};
  const double q[4] = {1, 0, 0, 0};
  const std::vector<QuantizedBody> bodies = {quantize_body(1, far, q, nullptr, nullptr),
                                             quantize_body(2, near, q, nullptr, nullptr)};
  EXPECT_DOUBLE_EQ(position_of(bodies[0])[0], std::ldexp(1.0, 52 - 10));
  EXPECT_DOUBLE_EQ(position_of(bodies[0])[1], -std::ldexp(1.0, 52 - 10));
  const auto decoded = decode_quantized_poses(encode_quantized_poses(bodies, false));
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(decoded->bodies, bodies);
}

TEST(QuantizedPoses, AnEmptyListIsThreeBytes) {
  const std::string bytes = encode_quantized_poses({}, true);
  EXPECT_EQ(bytes, std::string("\x00\x01\x0a", 3));
  const auto decoded = decode_quantized_poses(bytes);
  ASSERT_TRUE(decoded.has_value());
  EXPECT_TRUE(decoded->bodies.empty());
}

TEST(QuantizedPoses, MalformedBytesAreRefused) {
  const double x[3] = {1, 2, 3};
  const double q[4] = {1, 0, 0, 0};
  const std::vector<QuantizedBody> bodies = {quantize_body(1, x, q, nullptr, nullptr),
                                             quantize_body(2, x, q, nullptr, nullptr)};
  const std::string bytes = encode_quantized_poses(bodies, false);
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    EXPECT_FALSE(decode_quantized_poses(bytes.substr(0, cut)).has_value()) << cut;
  }
  EXPECT_FALSE(decode_quantized_poses(bytes + '\0').has_value());
  EXPECT_FALSE(decode_quantized_poses(std::string("\x7f\x00\x0a", 3)).has_value());  // 127 bodies, no ids
}

}  // namespace
}  // namespace tumble::wire
