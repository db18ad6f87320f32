#include "rotation.h"

#include <cmath>

namespace tumble::physics {

Quat quat_from_rotation_vector(const Vec3& theta) {
  const double angle2 = theta.squaredNorm();
  // Below half a radian (the turn of a substep, and of most steps) cos(x)
  // and sin(x)/x at the half angle x come from their Taylor series in
  // x^2, which needs neither the square root nor the library's sin and cos:
  // at x <= 1/4 the first term left out (x^14/14! for cos, x^12/13! for
  // sin(x)/x) is under 1e-17, below a unit roundoff.
  if (angle2 < 0.25) {
    const double x2 = 0.25 * angle2;
    const double c =
        1 + x2 * (-1.0 / 2 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 + x2 * (-1.0 / 3628800 +
                                                                                           x2 * (1.0 / 479001600))))));
    const double sinc =
        1 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800)))));
    const double s = 0.5 * sinc;  // sin(x) / angle = sin(x) / (2 x)
    return Quat(c, s * theta.x(), s * theta.y(), s * theta.z());
  }
  const double angle = std::sqrt(angle2);
  const double s = std::sin(0.5 * angle) / angle;
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
