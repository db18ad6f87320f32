#include "sim/body_spec.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Eigenvalues>

#include "sim/body_limits.h"
#include "sim/proto_math.h"
#include "sim/string_limits.h"
#include "tumble/physics/convex_hull.h"
#include "tumble/physics/mass_properties.h"
#include "tumble/physics/shape.h"

namespace tumble::sim {
namespace {

// A point mass's offset from the body's origin: each component within the largest size.
constexpr Range kPointOffsetRange{-kSizeRange.max, kSizeRange.max, "m"};

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
    if (!(status = check_range(spec.mass(), kMassRange, where + ".mass")).ok()) return status;
  }
  const double mass = dynamic ? spec.mass() : 1.0;
  double volume = 0;  // m^3 of a solid shape, for its density; 0 for point masses

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
      if (!(status = check_range(h.x(), kSizeRange, path + ".x")).ok()) return status;
      if (!(status = check_range(h.y(), kSizeRange, path + ".y")).ok()) return status;
      if (!(status = check_range(h.z(), kSizeRange, path + ".z")).ok()) return status;
      volume = 8 * h.x() * h.y() * h.z();
      desc->shape.type = physics::ShapeType::box;
      desc->shape.half_extents = to_vec3(h);
      desc->mass_properties = physics::box_mass_properties(mass, desc->shape.half_extents);
      break;
    }
    case tumble::v1::Shape::kSphere: {
      const double radius = shape.sphere().radius();
      if (!(status = check_range(radius, kSizeRange, shape_path + ".sphere.radius")).ok()) return status;
      volume = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
      desc->shape.type = physics::ShapeType::sphere;
      desc->shape.radius = radius;
      desc->mass_properties = physics::sphere_mass_properties(mass, radius);
      break;
    }
    case tumble::v1::Shape::kCapsule: {
      const auto& capsule = shape.capsule();
      const double r = capsule.radius();
      if (!(status = check_range(r, kSizeRange, shape_path + ".capsule.radius")).ok()) return status;
      const std::string half_height = shape_path + ".capsule.half_height";
      if (!(status = check_range(capsule.half_height(), kHalfHeightRange, half_height)).ok()) return status;
      volume = std::numbers::pi * r * r * (2 * capsule.half_height() + 4.0 / 3.0 * r);
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
        if (!(status = check_range(points.masses(i), kMassRange, path + ".masses" + index)).ok()) return status;
        const tumble::v1::Vec3& p = points.positions(i);
        const std::string position = path + ".positions" + index;
        if (!(status = check_range(p.x(), kPointOffsetRange, position + ".x")).ok()) return status;
        if (!(status = check_range(p.y(), kPointOffsetRange, position + ".y")).ok()) return status;
        if (!(status = check_range(p.z(), kPointOffsetRange, position + ".z")).ok()) return status;
        masses.push_back(points.masses(i));
        positions.push_back(to_vec3(points.positions(i)));
        total += points.masses(i);
      }
      // The mass field is optional for points; when given it must agree.
      if (spec.mass() != 0 && std::abs(spec.mass() - total) > 1e-9 * total) {
        return Status::error(where + ".mass: " + std::to_string(spec.mass()) +
                             " differs from the sum of the point masses " + std::to_string(total));
      }
      if (!(status = check_range(total, kMassRange, path + ".masses (their sum)")).ok()) return status;
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
        if (!(status = check_magnitude(shape.plane().normal(), "", path + ".normal")).ok()) return status;
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
        if (!(status = check_magnitude(points[i], "m", path + "[" + std::to_string(i) + "]")).ok()) return status;
        cloud.push_back(to_vec3(points[i]));
      }
      const auto hull = physics::build_convex_hull(cloud);
      if (!hull) return Status::error(path + ": the points span no volume (all coplanar)");
      // Re-centre the hull on its centre of mass: a body's position is its
      // centre of mass, so the shape must be centred on it.
      const physics::MassProperties uncentred = physics::convex_hull_mass_properties(*hull, mass);
      const auto centred = physics::translate_convex_hull(*hull, -uncentred.center);
      if (!(status = check_hull_size(*centred, path)).ok()) return status;
      volume = hull_volume(*centred);
      desc->shape = physics::convex_hull_shape(centred);
      desc->mass_properties = physics::convex_hull_mass_properties(*centred, mass);
      break;
    }
    case tumble::v1::Shape::KIND_NOT_SET:
      break;
  }
  if (dynamic) {
    // Mass and sizes within their ranges can still make a body too dense,
    // too lopsided or (point masses) too light to turn.
    if (!(status = check_mass_properties(desc->mass_properties, volume, where)).ok()) return status;
  }

  if (!(status = check_magnitude(spec.position(), "m", where + ".position")).ok()) return status;
  if (!(status = check_magnitude(spec.linear_velocity(), "m/s", where + ".linear_velocity")).ok()) return status;
  if (!(status = check_magnitude(spec.angular_velocity(), "rad/s", where + ".angular_velocity")).ok()) return status;
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
