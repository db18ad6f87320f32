#include "sim/body_spec.h"

#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

#include "physics/mass_properties.h"

namespace tumble::sim {
namespace {

bool within_limits(double value) { return std::isfinite(value) && std::abs(value) <= kMaxMagnitude; }

Status check_vec3(const tumble::v1::Vec3& v, const std::string& path) {
  if (within_limits(v.x()) && within_limits(v.y()) && within_limits(v.z())) return {};
  return Status::error(path + ": components must be finite and at most 1e9 in magnitude");
}

Status check_positive(double value, const std::string& path) {
  if (within_limits(value) && value > 0) return {};
  return Status::error(path + ": must be a positive finite number");
}

physics::Vec3 to_vec3(const tumble::v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

Status body_desc_from_spec(const tumble::v1::BodySpec& spec, const std::string& where,
                           physics::BodyDesc* desc) {
  *desc = physics::BodyDesc{};
  const tumble::v1::Shape& shape = spec.shape();
  const std::string shape_path = where + ".shape";
  Status status;

  if (shape.kind_case() == tumble::v1::Shape::KIND_NOT_SET) {
    return Status::error(shape_path + ": expected one of box, sphere, capsule, points");
  }
  if (shape.kind_case() != tumble::v1::Shape::kPoints) {
    if (!(status = check_positive(spec.mass(), where + ".mass")).ok()) return status;
  }

  switch (shape.kind_case()) {
    case tumble::v1::Shape::kBox: {
      const auto& h = shape.box().half_extents();
      const std::string path = shape_path + ".box.half_extents";
      for (double component : {h.x(), h.y(), h.z()}) {
        if (!(status = check_positive(component, path)).ok()) return status;
      }
      desc->shape.type = physics::ShapeType::box;
      desc->shape.half_extents = to_vec3(h);
      desc->mass_properties = physics::box_mass_properties(spec.mass(), desc->shape.half_extents);
      break;
    }
    case tumble::v1::Shape::kSphere: {
      const double radius = shape.sphere().radius();
      if (!(status = check_positive(radius, shape_path + ".sphere.radius")).ok()) return status;
      desc->shape.type = physics::ShapeType::sphere;
      desc->shape.radius = radius;
      desc->mass_properties = physics::sphere_mass_properties(spec.mass(), radius);
      break;
    }
    case tumble::v1::Shape::kCapsule: {
      const auto& capsule = shape.capsule();
      if (!(status = check_positive(capsule.radius(), shape_path + ".capsule.radius")).ok()) return status;
      if (!within_limits(capsule.half_height()) || capsule.half_height() < 0) {
        return Status::error(shape_path + ".capsule.half_height: must be a finite number >= 0");
      }
      desc->shape.type = physics::ShapeType::capsule;
      desc->shape.radius = capsule.radius();
      desc->shape.half_height = capsule.half_height();
      desc->mass_properties =
          physics::capsule_mass_properties(spec.mass(), capsule.radius(), capsule.half_height());
      break;
    }
    case tumble::v1::Shape::kPoints: {
      const auto& points = shape.points();
      const std::string path = shape_path + ".points";
      if (points.masses_size() == 0) return Status::error(path + ": needs at least one point");
      if (points.masses_size() != points.positions_size()) {
        return Status::error(path + ": masses and positions differ in length");
      }
      std::vector<double> masses;
      std::vector<physics::Vec3> positions;
      double total = 0;
      for (int i = 0; i < points.masses_size(); ++i) {
        const std::string index = "[" + std::to_string(i) + "]";
        if (!(status = check_positive(points.masses(i), path + ".masses" + index)).ok()) return status;
        if (!(status = check_vec3(points.positions(i), path + ".positions" + index)).ok()) return status;
        masses.push_back(points.masses(i));
        positions.push_back(to_vec3(points.positions(i)));
        total += points.masses(i);
      }
      // The mass field is optional for points; when given it must agree.
      if (spec.mass() != 0 && std::abs(spec.mass() - total) > 1e-9 * total) {
        return Status::error(where + ".mass: " + std::to_string(spec.mass()) +
                             " differs from the sum of the point masses " + std::to_string(total));
      }
      desc->shape.type = physics::ShapeType::none;
      desc->mass_properties = physics::point_mass_properties(masses, positions);
      // A rigid set of points needs three non-collinear points for a
      // positive-definite inertia tensor (Baraff (2-33)).
      const Eigen::SelfAdjointEigenSolver<physics::Mat3> eigen(desc->mass_properties.inertia);
      if (eigen.eigenvalues().minCoeff() <= 1e-12 * eigen.eigenvalues().maxCoeff()) {
        return Status::error(path + ": the points are collinear, so the body has no rotational inertia about one axis");
      }
      break;
    }
    case tumble::v1::Shape::KIND_NOT_SET:
      break;
  }

  if (!(status = check_vec3(spec.position(), where + ".position")).ok()) return status;
  if (!(status = check_vec3(spec.linear_velocity(), where + ".linear_velocity")).ok()) return status;
  if (!(status = check_vec3(spec.angular_velocity(), where + ".angular_velocity")).ok()) return status;
  desc->position = to_vec3(spec.position());
  desc->linear_velocity = to_vec3(spec.linear_velocity());
  desc->angular_velocity = to_vec3(spec.angular_velocity());

  if (spec.has_orientation()) {
    const auto& q = spec.orientation();
    const double norm = std::sqrt(q.w() * q.w() + q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
    // Accept rounding in hand-written files, then normalise exactly.
    if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3) {
      return Status::error(where + ".orientation: must be a unit quaternion [w, x, y, z]");
    }
    desc->orientation = physics::Quat(q.w() / norm, q.x() / norm, q.y() / norm, q.z() / norm);
  }
  return {};
}

const char* shape_kind_name(const tumble::v1::Shape& shape) {
  switch (shape.kind_case()) {
    case tumble::v1::Shape::kBox: return "box";
    case tumble::v1::Shape::kSphere: return "sphere";
    case tumble::v1::Shape::kCapsule: return "capsule";
    case tumble::v1::Shape::kPoints: return "points";
    case tumble::v1::Shape::KIND_NOT_SET: break;
  }
  return "none";
}

}  // namespace tumble::sim
