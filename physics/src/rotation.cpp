#include "rotation.h"

#include <cmath>

namespace tumble::physics {

Quat quat_from_rotation_vector(const Vec3& theta) {
  const double angle2 = theta.squaredNorm();
  const double angle = std::sqrt(angle2);
  // s = sin(angle/2) / angle. Below 1e-4 rad use its Taylor series
  // 1/2 - angle^2/48 + angle^4/3840, whose truncation error (angle^6/645120)
  // is under a unit roundoff there; the division is exact enough above it.
  double s;
  if (angle < 1e-4) {
    s = 0.5 - angle2 / 48.0 + angle2 * angle2 / 3840.0;
  } else {
    s = std::sin(0.5 * angle) / angle;
  }
  return Quat(std::cos(0.5 * angle), s * theta.x(), s * theta.y(), s * theta.z());
}

bool is_isotropic(const Mat3& t) { return t == t(0, 0) * Mat3::Identity(); }

Mat3 body_to_world_tensor(const Quat& q, const Mat3& tensor_body) {
  if (is_isotropic(tensor_body)) return tensor_body;
  return body_to_world_tensor(q.toRotationMatrix(), tensor_body);
}

Mat3 body_to_world_tensor(const Mat3& r, const Mat3& tensor_body) {
  if (is_isotropic(tensor_body)) return tensor_body;
  return r * tensor_body * r.transpose();
}

Vec3 apply_body_to_world_tensor(const Mat3& r, const Mat3& tensor_body, const Vec3& v) {
  if (is_isotropic(tensor_body)) return tensor_body(0, 0) * v;
  return r * (tensor_body * (r.transpose() * v));
}

}  // namespace tumble::physics
