#include "joint_separation.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace tumble::bench {
namespace {

// A point fixed to a body, in the world frame at the body's pose.
Vec3 world_point(const Pose& pose, const Vec3& body_point) {
  return pose.position + pose.orientation.normalized() * body_point;
}

}  // namespace

JointSeparationProbe::JointSeparationProbe(const Scene& scene) {
  anchors_.reserve(scene.joints.size());
  for (const SceneJoint& joint : scene.joints) {
    const Vec3 anchor_a = joint.body_a == kWorld
                              ? joint.anchor
                              : body_point(scene.bodies[static_cast<std::size_t>(joint.body_a)], joint.anchor);
    anchors_.push_back({joint.body_a, joint.body_b, anchor_a,
                        body_point(scene.bodies[static_cast<std::size_t>(joint.body_b)], joint.anchor)});
  }
}

double JointSeparationProbe::measure(const std::vector<Pose>& poses) const {
  double largest = 0;
  for (const Anchors& joint : anchors_) {
    const Vec3 a = joint.body_a == kWorld ? joint.anchor_a
                                          : world_point(poses[static_cast<std::size_t>(joint.body_a)], joint.anchor_a);
    const Vec3 b = world_point(poses[static_cast<std::size_t>(joint.body_b)], joint.anchor_b);
    const double separation = (b - a).norm();
    if (!std::isfinite(separation)) return std::numeric_limits<double>::infinity();
    largest = std::max(largest, separation);
  }
  return largest;
}

}  // namespace tumble::bench
