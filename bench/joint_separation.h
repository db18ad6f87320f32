// Joint separation measured from body poses alone: how far apart the two
// anchor points of a joint are, computed the same way for every engine
// whatever its solver thinks of its joints.
#pragma once

#include <vector>

#include "engine.h"
#include "scenes.h"

namespace tumble::bench {

// Measures the largest joint separation for poses of one scene's bodies.
class JointSeparationProbe {
 public:
  // Fixes each joint's anchor to its bodies at their starting poses.
  explicit JointSeparationProbe(const Scene& scene);
  // poses: of scene.bodies, in order. The largest distance (m) between a
  // joint's anchor on body_a (or in the world) and its anchor on body_b,
  // over every joint; 0 without joints, infinite when a pose is not finite.
  double measure(const std::vector<Pose>& poses) const;

 private:
  // One joint's anchor in each body's frame (relative to its centre of
  // mass); anchor_a is a world point when body_a is kWorld.
  struct Anchors {
    int body_a;
    int body_b;
    Vec3 anchor_a;
    Vec3 anchor_b;
  };
  std::vector<Anchors> anchors_;
};

}  // namespace tumble::bench
