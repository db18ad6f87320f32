// The protocol's Vec3 and Quat messages to and from the engine's vectors,
// component by component: nothing is checked or normalised here.
#pragma once

#include "tumble/physics/math.h"
#include "tumble/v1/types.pb.h"

namespace tumble::sim {

inline physics::Vec3 to_vec3(const tumble::v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

inline void set_vec3(const physics::Vec3& v, tumble::v1::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

inline physics::Quat to_quat(const tumble::v1::Quat& q) { return {q.w(), q.x(), q.y(), q.z()}; }

inline void set_quat(const physics::Quat& q, tumble::v1::Quat* out) {
  out->set_w(q.w());
  out->set_x(q.x());
  out->set_y(q.y());
  out->set_z(q.z());
}

}  // namespace tumble::sim
