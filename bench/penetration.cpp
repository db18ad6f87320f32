#include "penetration.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace tumble::bench {
namespace {

using Mat3 = Eigen::Matrix3d;

// Penetration depth of two boxes (0 when apart) by the separating axis test
// over their 15 candidate axes (Ericson, "Real-Time Collision Detection",
// 4.4.1): the overlap of the projections along any direction is at least the
// depth, and the smallest one over the face normals of both boxes and the
// cross products of their edges is the depth itself.
double box_box_depth(const Vec3& half_a, const Mat3& rot_a, const Vec3& pos_a, const Vec3& half_b, const Mat3& rot_b,
                     const Vec3& pos_b) {
  const Vec3 d = pos_b - pos_a;
  double depth = std::numeric_limits<double>::infinity();
  // Narrows depth to the overlap along axis; false when the axis separates.
  auto overlaps_along = [&](const Vec3& axis) {
    const double length = axis.norm();
    if (length < 1e-9) return true;  // parallel edges: their face normals are tested already
    const Vec3 n = axis / length;
    const double reach_a = (rot_a.transpose() * n).cwiseAbs().dot(half_a);
    const double reach_b = (rot_b.transpose() * n).cwiseAbs().dot(half_b);
    const double overlap = reach_a + reach_b - std::abs(d.dot(n));
    depth = std::min(depth, overlap);
    return overlap > 0;
  };
  for (int i = 0; i < 3; ++i) {
    if (!overlaps_along(rot_a.col(i)) || !overlaps_along(rot_b.col(i))) return 0;
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!overlaps_along(rot_a.col(i).cross(rot_b.col(j)))) return 0;
    }
  }
  return depth;
}

// Penetration depth of a box and a sphere (0 when apart): from the closest
// point of the box to the centre, or, with the centre inside the box, from
// the nearest face.
double box_sphere_depth(const Vec3& half, const Mat3& rot, const Vec3& box_pos, double radius, const Vec3& centre) {
  const Vec3 local = rot.transpose() * (centre - box_pos);
  const Vec3 inside_by = half - local.cwiseAbs();  // > 0 along every axis: centre inside
  if ((inside_by.array() > 0).all()) return radius + inside_by.minCoeff();
  const Vec3 closest = local.cwiseMax(-half).cwiseMin(half);
  return std::max(0.0, radius - (local - closest).norm());
}

double bounding_radius_of(const DynamicBody& body) {
  return body.shape == BodyShape::box ? body.half_extents.norm() : body.radius;
}

}  // namespace

PenetrationProbe::PenetrationProbe(const Scene& scene) : bodies_(scene.bodies) {
  double largest = 0;
  for (const DynamicBody& body : bodies_) {
    bounding_radius_.push_back(bounding_radius_of(body));
    largest = std::max(largest, bounding_radius_.back());
  }
  // Bodies that can touch are then in the same or adjacent cells.
  cell_size_ = std::max(2.0 * largest, 1e-3);
  std::uint32_t buckets = 64;
  while (buckets < 2 * bodies_.size()) buckets *= 2;
  bucket_mask_ = buckets - 1;
  for (const SceneJoint& joint : scene.joints) {
    if (joint.body_a == kWorld) continue;
    const auto a = static_cast<std::uint32_t>(joint.body_a);
    const auto b = static_cast<std::uint32_t>(joint.body_b);
    joined_.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(joined_.begin(), joined_.end());
  bucket_start_.resize(buckets + 1);
  cursor_.resize(buckets);
  order_.resize(bodies_.size());
}

std::uint32_t PenetrationProbe::bucket_of(const Eigen::Vector3i& cell) const {
  // Spatial hash of Teschner et al., "Optimized Spatial Hashing for Collision
  // Detection of Deformable Objects" (2003); unsigned so it wraps.
  const auto x = static_cast<std::uint32_t>(cell.x()) * 73856093u;
  const auto y = static_cast<std::uint32_t>(cell.y()) * 19349663u;
  const auto z = static_cast<std::uint32_t>(cell.z()) * 83492791u;
  return (x ^ y ^ z) & bucket_mask_;
}

double PenetrationProbe::pair_depth(std::size_t a, std::size_t b) const {
  const DynamicBody& body_a = bodies_[a];
  const DynamicBody& body_b = bodies_[b];
  if (body_a.shape == BodyShape::sphere && body_b.shape == BodyShape::sphere) {
    return std::max(0.0, body_a.radius + body_b.radius - (positions_[b] - positions_[a]).norm());
  }
  if (body_a.shape == BodyShape::box && body_b.shape == BodyShape::box) {
    return box_box_depth(body_a.half_extents, rotations_[a], positions_[a], body_b.half_extents, rotations_[b],
                         positions_[b]);
  }
  const std::size_t box = body_a.shape == BodyShape::box ? a : b;
  const std::size_t sphere = box == a ? b : a;
  return box_sphere_depth(bodies_[box].half_extents, rotations_[box], positions_[box], bodies_[sphere].radius,
                          positions_[sphere]);
}

Penetration PenetrationProbe::measure(const std::vector<Pose>& poses) {
  const std::size_t n = bodies_.size();
  positions_.resize(n);
  rotations_.resize(n);
  cells_.resize(n);
  finite_.resize(n);
  Penetration result;

  for (std::size_t i = 0; i < n; ++i) {
    positions_[i] = poses[i].position;
    rotations_[i] = poses[i].orientation.normalized().toRotationMatrix();
    finite_[i] = positions_[i].allFinite() && rotations_[i].allFinite();
    if (!finite_[i]) {
      // A body that blew up: infinitely deep, and parked at the origin out of
      // the pair tests (its cell would be meaningless).
      result.ground = std::numeric_limits<double>::infinity();
      positions_[i].setZero();
      rotations_[i].setIdentity();
      cells_[i].setZero();
      continue;
    }
    const DynamicBody& body = bodies_[i];
    // Lowest point: for a box, the centre minus the half extents projected
    // on y (row 1 of R holds the y components of the body axes).
    const double lowest = body.shape == BodyShape::box
                              ? positions_[i].y() - rotations_[i].row(1).cwiseAbs().dot(body.half_extents.transpose())
                              : positions_[i].y() - body.radius;
    result.ground = std::max(result.ground, -lowest);
    // Clamped so a body flung far away still has a representable cell.
    cells_[i] = (positions_[i] / cell_size_).array().floor().cwiseMax(-1e9).cwiseMin(1e9).cast<int>();
  }

  // Counting sort of the bodies by bucket.
  std::fill(bucket_start_.begin(), bucket_start_.end(), 0u);
  for (std::size_t i = 0; i < n; ++i) ++bucket_start_[bucket_of(cells_[i]) + 1];
  for (std::size_t b = 1; b < bucket_start_.size(); ++b) bucket_start_[b] += bucket_start_[b - 1];
  std::copy(bucket_start_.begin(), bucket_start_.end() - 1, cursor_.begin());
  for (std::size_t i = 0; i < n; ++i) order_[cursor_[bucket_of(cells_[i])]++] = static_cast<std::uint32_t>(i);

  // Each body against the bodies of the 27 cells around it, each pair once
  // (a < b) and each bucket once even when two cells share it.
  for (std::size_t a = 0; a < n; ++a) {
    if (!finite_[a]) continue;
    std::array<std::uint32_t, 27> buckets{};
    std::size_t count = 0;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) buckets[count++] = bucket_of(cells_[a] + Eigen::Vector3i(dx, dy, dz));
      }
    }
    std::sort(buckets.begin(), buckets.end());
    const auto unique_end = std::unique(buckets.begin(), buckets.end());
    for (auto bucket = buckets.begin(); bucket != unique_end; ++bucket) {
      for (std::uint32_t k = bucket_start_[*bucket]; k < bucket_start_[*bucket + 1]; ++k) {
        const std::size_t b = order_[k];
        if (b <= a || !finite_[b]) continue;
        const double reach = bounding_radius_[a] + bounding_radius_[b];
        if ((positions_[b] - positions_[a]).squaredNorm() >= reach * reach) continue;
        if (!joined_.empty() &&
            std::binary_search(joined_.begin(), joined_.end(),
                               std::pair(static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)))) {
          continue;
        }
        result.bodies = std::max(result.bodies, pair_depth(a, b));
      }
    }
  }
  return result;
}

std::size_t count_below_ground(const std::vector<Pose>& poses) {
  return static_cast<std::size_t>(
      std::count_if(poses.begin(), poses.end(), [](const Pose& pose) { return pose.position.y() < 0; }));
}

}  // namespace tumble::bench
