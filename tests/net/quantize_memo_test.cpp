// QuantizeMemo against quantizing every body afresh, frame after frame,
// as bodies move, rest, leave, arrive and are filtered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "frames/quantize_memo.h"
#include "sim/snapshot.h"
#include "wire/quantized_poses.h"

namespace tumble::net {
namespace {

// A body's values in a test snapshot.
struct Pose {
  physics::BodyId id;
  double x, y, z;
  double angle;  // rad about the axis (1, 2, 2) / 3
  double speed;  // m/s along x, and as much rad/s about y
};

sim::Snapshot snapshot_of(const std::vector<Pose>& poses) {
  sim::Snapshot s;
  for (const Pose& p : poses) {
    s.ids.push_back(p.id);
    s.positions.insert(s.positions.end(), {p.x, p.y, p.z});
    const double c = std::cos(p.angle / 2);
    const double k = std::sin(p.angle / 2) / 3;
    s.orientations.insert(s.orientations.end(), {c, k, 2 * k, 2 * k});
    s.linear_velocities.insert(s.linear_velocities.end(), {p.speed, 0, 0});
    s.angular_velocities.insert(s.angular_velocities.end(), {0, p.speed, 0});
  }
  return s;
}

// What the memo must return: every body read quantized afresh, by id.
std::vector<wire::QuantizedBody> fresh(const sim::Snapshot& s, bool all, const std::vector<physics::BodyId>& filter,
                                       bool velocities) {
  std::vector<wire::QuantizedBody> bodies;
  for (std::size_t i = 0; i < s.body_count(); ++i) {
    if (!all && !std::binary_search(filter.begin(), filter.end(), s.ids[i])) continue;
    bodies.push_back(wire::quantize_body(s.ids[i], &s.positions[3 * i], &s.orientations[4 * i],
                                         velocities ? &s.linear_velocities[3 * i] : nullptr,
                                         velocities ? &s.angular_velocities[3 * i] : nullptr));
  }
  std::sort(bodies.begin(), bodies.end(),
            [](const wire::QuantizedBody& a, const wire::QuantizedBody& b) { return a.id < b.id; });
  return bodies;
}

std::vector<Pose> forty_bodies() {
  std::vector<Pose> poses;
  for (physics::BodyId id = 1; id <= 40; ++id) {
    poses.push_back({id, 0.37 * id, 0.2, -0.11 * id, 0.05 * id, 0.0});
  }
  return poses;
}

class QuantizeMemoTest : public ::testing::TestWithParam<bool> {};

TEST_P(QuantizeMemoTest, ReusesTheRecordsOfUnchangedBodiesOnly) {
  const bool velocities = GetParam();
  frames::QuantizeMemo memo;
  std::vector<Pose> poses = forty_bodies();
  const auto check = [&](std::size_t expected_fresh, const char* step) {
    const sim::Snapshot s = snapshot_of(poses);
    EXPECT_EQ(memo.quantize(s, true, {}, velocities), fresh(s, true, {}, velocities)) << step;
    EXPECT_EQ(memo.quantized_last(), expected_fresh) << step;
  };
  check(40, "the first frame quantizes every body");
  check(0, "a world at rest quantizes none");

  // Three bodies move: one by far less than a grid step (a new record all
  // the same, equal to a fresh one), one turns, one speeds up (a change
  // only to a stream with velocities).
  poses[4].x += 1e-9;
  poses[17].angle += 0.3;
  poses[30].speed = 2.5;
  check(velocities ? 3 : 2, "three bodies changed");
  check(0, "and rest again");

  // Body 11 leaves the way the world removes one: its last body takes its place.
  poses[10] = poses.back();
  poses.pop_back();
  check(1, "after a removal only the body that moved into the hole");
  check(0, "then none");

  // Two arrive at the end, and one of the old ones changes.
  poses.push_back({41, 1, 2, 3, 0.5, 1});
  poses.push_back({42, -1, 2, -3, 0.7, 1});
  poses[2].y = 0.25;
  check(3, "two new bodies and a changed one");

  // The order changes wholesale: nothing wrong, only fresh work.
  std::reverse(poses.begin(), poses.end());
  const sim::Snapshot reversed = snapshot_of(poses);
  EXPECT_EQ(memo.quantize(reversed, true, {}, velocities), fresh(reversed, true, {}, velocities));
  check(0, "in the new order at rest");
}

TEST_P(QuantizeMemoTest, ReadsOnlyTheFilteredBodies) {
  const bool velocities = GetParam();
  frames::QuantizeMemo memo;
  std::vector<Pose> poses = forty_bodies();
  const std::vector<physics::BodyId> filter{3, 9, 10, 27, 99};  // 99 is not in the world
  sim::Snapshot s = snapshot_of(poses);
  EXPECT_EQ(memo.quantize(s, false, filter, velocities), fresh(s, false, filter, velocities));
  EXPECT_EQ(memo.quantized_last(), 4u);
  poses[8].x = 5;   // body 9, in the filter
  poses[20].x = 5;  // body 21, not in it
  s = snapshot_of(poses);
  const std::vector<wire::QuantizedBody> bodies = memo.quantize(s, false, filter, velocities);
  EXPECT_EQ(bodies, fresh(s, false, filter, velocities));
  EXPECT_EQ(memo.quantized_last(), 1u);
  ASSERT_EQ(bodies.size(), 4u);
  EXPECT_EQ(bodies[1].id, 9u);
  // Ids out of order (the world lists its bodies in its own order).
  std::swap(poses[2], poses[30]);
  std::swap(poses[9], poses[26]);
  s = snapshot_of(poses);
  EXPECT_EQ(memo.quantize(s, false, filter, velocities), fresh(s, false, filter, velocities));
  poses[9].x = 7;  // body 27
  s = snapshot_of(poses);
  EXPECT_EQ(memo.quantize(s, false, filter, velocities), fresh(s, false, filter, velocities));
  EXPECT_EQ(memo.quantized_last(), 1u);
}

INSTANTIATE_TEST_SUITE_P(PoseAndVelocities, QuantizeMemoTest, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& param_info) {
                           return param_info.param ? "WithVelocities" : "PoseOnly";
                         });

}  // namespace
}  // namespace tumble::net
