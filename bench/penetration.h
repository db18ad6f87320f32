// Overlap measured from body poses alone, with the scene's exact shapes, so
// it is computed the same way for every engine whatever the engine thinks
// its contacts are.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "engine.h"
#include "scenes.h"

namespace tumble::bench {

// Deepest overlaps at one moment (m), 0 when nothing overlaps.
struct Penetration {
  double ground = 0;  // of a dynamic body into the ground: box, -(lowest corner y); sphere, radius - y
  double bodies = 0;  // between two dynamic bodies: their exact penetration depth
};

// Measures Penetration for poses of one scene's bodies. Body pairs are found
// with a spatial hash of the bounding spheres; the probe keeps its scratch
// arrays between calls. The walls are not measured, nor pairs a joint
// connects (they do not collide, and may overlap where they are joined).
class PenetrationProbe {
 public:
  // Keeps a reference to scene.bodies: the scene must outlive the probe.
  explicit PenetrationProbe(const Scene& scene);
  // poses: of scene.bodies, in order. A non-finite pose makes ground infinite.
  Penetration measure(const std::vector<Pose>& poses);

 private:
  std::uint32_t bucket_of(const Eigen::Vector3i& cell) const;
  double pair_depth(std::size_t a, std::size_t b) const;

  const std::vector<DynamicBody>& bodies_;
  std::vector<double> bounding_radius_;  // per body
  double cell_size_ = 1;                 // m: at least the largest bounding diameter
  std::uint32_t bucket_mask_ = 0;        // bucket count - 1 (a power of two)
  // Pairs of bodies a joint connects, (lower index, higher), sorted.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> joined_;

  // Scratch of one measure() call.
  std::vector<Vec3> positions_;
  std::vector<Eigen::Matrix3d> rotations_;
  std::vector<Eigen::Vector3i> cells_;
  std::vector<char> finite_;                 // pose has no NaN or infinity
  std::vector<std::uint32_t> bucket_start_;  // bodies of bucket b: order_[start[b] .. start[b + 1])
  std::vector<std::uint32_t> cursor_;        // next free slot of each bucket while sorting
  std::vector<std::uint32_t> order_;         // body indices sorted by bucket
};

// Bodies whose centre is below y = 0: they fell through the ground.
std::size_t count_below_ground(const std::vector<Pose>& poses);

}  // namespace tumble::bench
