#include "sim/body_limits.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Eigenvalues>

namespace tumble::sim {
namespace {

std::string with_unit(double value, const char* unit) {
  return *unit == '\0' ? format_number(value) : format_number(value) + " " + unit;
}

}  // namespace

std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  std::string text = buffer;
  // "1e+09" -> "1e9", "1e-06" -> "1e-6".
  const std::size_t e = text.find('e');
  if (e == std::string::npos) return text;
  std::string exponent = text.substr(e + 1);
  const bool negative = !exponent.empty() && exponent[0] == '-';
  if (!exponent.empty() && (exponent[0] == '+' || exponent[0] == '-')) exponent.erase(0, 1);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return text.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}

Status check_range(double value, const Range& range, const std::string& path) {
  if (range.contains(value)) return {};
  return Status::error(path + ": " + with_unit(value, range.unit) + " is outside " + format_number(range.min) + " .. " +
                       with_unit(range.max, range.unit));
}

Status check_magnitude(const tumble::v1::Vec3& v, const char* unit, const std::string& path) {
  const Range range{-kMaxMagnitude, kMaxMagnitude, unit};
  if (Status status = check_range(v.x(), range, path + ".x"); !status.ok()) return status;
  if (Status status = check_range(v.y(), range, path + ".y"); !status.ok()) return status;
  return check_range(v.z(), range, path + ".z");
}

Status check_mass_properties(const physics::MassProperties& props, double volume, const std::string& where) {
  if (volume > 0) {
    const double density = props.mass / volume;
    if (!kDensityRange.contains(density)) {
      return Status::error(where + ".mass: " + with_unit(props.mass, "kg") + " in " + with_unit(volume, "m^3") +
                           " is a density of " + with_unit(density, kDensityRange.unit) + ", outside " +
                           format_number(kDensityRange.min) + " .. " +
                           with_unit(kDensityRange.max, kDensityRange.unit));
    }
  }
  // A tensor that is not finite has no principal moments to speak of.
  if (!props.inertia.allFinite()) {
    return Status::error(where + ": its moments of inertia are not finite numbers");
  }
  const Eigen::SelfAdjointEigenSolver<physics::Mat3> eigen(props.inertia, Eigen::EigenvaluesOnly);
  const double smallest = eigen.eigenvalues().minCoeff();
  const double largest = eigen.eigenvalues().maxCoeff();
  for (const double moment : {smallest, largest}) {
    if (!kMomentRange.contains(moment)) {
      return Status::error(where + ": its principal moment of inertia " + with_unit(moment, kMomentRange.unit) +
                           " is outside " + format_number(kMomentRange.min) + " .. " +
                           with_unit(kMomentRange.max, kMomentRange.unit));
    }
  }
  if (largest > kMaxMomentRatio * smallest) {
    return Status::error(where + ": its principal moments of inertia " + with_unit(smallest, kMomentRange.unit) +
                         " and " + with_unit(largest, kMomentRange.unit) + " differ by a factor of " +
                         format_number(largest / smallest) + ", more than " + format_number(kMaxMomentRatio) +
                         " (a shape too thin for its length, or point masses nearly in a line)");
  }
  return {};
}

Status check_hull_size(const physics::ConvexHull& hull, const std::string& path) {
  if (hull.bounding_radius > kSizeRange.max) {
    return Status::error(path + ": a vertex " + with_unit(hull.bounding_radius, "m") +
                         " from the centre of mass, more than " + with_unit(kSizeRange.max, "m"));
  }
  for (const physics::ConvexHull::Face& face : hull.faces) {
    double deepest = face.offset;
    for (const physics::Vec3& vertex : hull.vertices) deepest = std::min(deepest, face.normal.dot(vertex));
    const double thickness = face.offset - deepest;
    if (thickness < kSizeRange.min) {
      return Status::error(path + ": the hull is " + with_unit(thickness, "m") + " thick, less than " +
                           with_unit(kSizeRange.min, "m"));
    }
  }
  return {};
}

double hull_volume(const physics::ConvexHull& hull) {
  // Divergence theorem: V = 1/3 sum over faces of offset * area, the area of
  // a planar polygon being half the normal component of sum v_k x v_k+1.
  double volume = 0;
  for (const physics::ConvexHull::Face& face : hull.faces) {
    physics::Vec3 twice_area = physics::Vec3::Zero();
    for (std::uint32_t k = 0; k < face.count; ++k) {
      const physics::Vec3& a = hull.vertices[hull.face_vertices[face.first + k]];
      const physics::Vec3& b = hull.vertices[hull.face_vertices[face.first + (k + 1) % face.count]];
      twice_area += a.cross(b);
    }
    volume += face.offset * 0.5 * face.normal.dot(twice_area) / 3.0;
  }
  return volume;
}

}  // namespace tumble::sim
