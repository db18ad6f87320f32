#include "sim/body_spec.h"

#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

#include "sim/string_limits.h"
#include "tumble/physics/convex_hull.h"
#include "tumble/physics/mass_properties.h"
#include "tumble/physics/shape.h"

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

Status body_desc_from_spec(const tumble::v1::BodySpec& spec, const std::string& where, physics::BodyDesc* desc) {
  *desc = physics::BodyDesc{};
  const tumble::v1::Shape& shape = spec.shape();
  const std::string shape_path = where + ".shape";
  Status status = check_body_name(spec.name(), where + ".name");
  if (!status.ok()) return status;

  if (shape.kind_case() == tumble::v1::Shape::KIND_NOT_SET) {
    return Status::error(shape_path + ": expected one of box, sphere, capsule, points, plane, convex");
  }
  switch (spec.motion()) {
    case tumble::v1::MOTION_DYNAMIC:
      desc->motion_type = physics::MotionType::dynamic_body;
      break;
    case tumble::v1::MOTION_STATIC:
      desc->motion_type = physics::MotionType::static_body;
      break;
    case tumble::v1::MOTION_KINEMATIC:
      desc->motion_type = physics::MotionType::kinematic_body;
      break;
    default:
      return Status::error(where + ".motion: unknown motion type " + std::to_string(spec.motion()));
  }
  const bool dynamic = desc->motion_type == physics::MotionType::dynamic_body;
  if (shape.kind_case() == tumble::v1::Shape::kPlane && dynamic) {
    return Status::error(shape_path + ".plane: a plane must be static (\"static\": true)");
  }
  if (shape.kind_case() == tumble::v1::Shape::kPoints && !dynamic) {
    return Status::error(shape_path + ".points: point masses have no collision shape, so they must be dynamic");
  }
  // Static and kinematic bodies have infinite mass; a mass given for them is
  // ignored.
  if (dynamic && shape.kind_case() != tumble::v1::Shape::kPoints) {
    if (!(status = check_positive(spec.mass(), where + ".mass")).ok()) return status;
  }
  const double mass = dynamic ? spec.mass() : 1.0;

  if (spec.has_friction()) {
    if (!within_limits(spec.friction()) || spec.friction() < 0) {
      return Status::error(where + ".friction: must be a finite number >= 0");
    }
    desc->friction = spec.friction();
  }
  if (spec.has_restitution()) {
    if (!std::isfinite(spec.restitution()) || spec.restitution() < 0 || spec.restitution() > 1) {
      return Status::error(where + ".restitution: must be between 0 and 1");
    }
    desc->restitution = spec.restitution();
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
      desc->mass_properties = physics::box_mass_properties(mass, desc->shape.half_extents);
      break;
    }
    case tumble::v1::Shape::kSphere: {
      const double radius = shape.sphere().radius();
      if (!(status = check_positive(radius, shape_path + ".sphere.radius")).ok()) return status;
      desc->shape.type = physics::ShapeType::sphere;
      desc->shape.radius = radius;
      desc->mass_properties = physics::sphere_mass_properties(mass, radius);
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
      desc->mass_properties = physics::capsule_mass_properties(mass, capsule.radius(), capsule.half_height());
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
    case tumble::v1::Shape::kPlane: {
      const std::string path = shape_path + ".plane";
      physics::Vec3 normal = physics::Vec3::UnitY();
      if (shape.plane().has_normal()) {
        if (!(status = check_vec3(shape.plane().normal(), path + ".normal")).ok()) return status;
        normal = to_vec3(shape.plane().normal());
        if (normal.norm() < 1e-9) return Status::error(path + ".normal: must not be zero");
        normal.normalize();
      }
      if (!within_limits(shape.plane().offset())) {
        return Status::error(path + ".offset: must be finite and at most 1e9 in magnitude");
      }
      // The plane is given in world coordinates: the body stays at the
      // origin, unrotated, and its pose fields are ignored.
      desc->shape = physics::plane_shape(normal, shape.plane().offset());
      return {};
    }
    case tumble::v1::Shape::kConvex: {
      const std::string path = shape_path + ".convex.points";
      const auto& points = shape.convex().points();
      if (points.size() < 4) return Status::error(path + ": needs at least four points");
      if (points.size() > kMaxConvexPoints) {
        return Status::error(path + ": at most " + std::to_string(kMaxConvexPoints) + " points");
      }
      std::vector<physics::Vec3> cloud;
      cloud.reserve(static_cast<std::size_t>(points.size()));
      for (int i = 0; i < points.size(); ++i) {
        if (!(status = check_vec3(points[i], path + "[" + std::to_string(i) + "]")).ok()) return status;
        cloud.push_back(to_vec3(points[i]));
      }
      const auto hull = physics::build_convex_hull(cloud);
      if (!hull) return Status::error(path + ": the points span no volume (all coplanar)");
      // Re-centre the hull on its centre of mass: a body's position is its
      // centre of mass, so the shape must be centred on it.
      const physics::MassProperties uncentred = physics::convex_hull_mass_properties(*hull, mass);
      const auto centred = physics::translate_convex_hull(*hull, -uncentred.center);
      desc->shape = physics::convex_hull_shape(centred);
      desc->mass_properties = physics::convex_hull_mass_properties(*centred, mass);
      break;
    }
    case tumble::v1::Shape::KIND_NOT_SET:
      break;
  }
  if (dynamic) {
    // Sizes and masses that pass the checks above can still be so small
    // that the inertia tensor underflows to a singular one (a capsule of
    // radius 1e-200 has moments of about 1e-400, that is 0), or that its
    // inverse or the inverse mass overflows; the engine steps with both.
    const physics::MassProperties& props = desc->mass_properties;
    const Eigen::SelfAdjointEigenSolver<physics::Mat3> moments(props.inertia, Eigen::EigenvaluesOnly);
    const double smallest = props.inertia.allFinite() ? moments.eigenvalues().minCoeff() : 0.0;
    if (!(smallest > 0 && std::isfinite(1.0 / smallest) && std::isfinite(1.0 / props.mass))) {
      return Status::error(where + ": too small or too light: its inertia cannot be inverted");
    }
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

tumble::v1::Motion wire_motion(physics::MotionType type) {
  switch (type) {
    case physics::MotionType::static_body:
      return tumble::v1::MOTION_STATIC;
    case physics::MotionType::kinematic_body:
      return tumble::v1::MOTION_KINEMATIC;
    case physics::MotionType::dynamic_body:
      break;
  }
  return tumble::v1::MOTION_DYNAMIC;
}

}  // namespace tumble::sim
