// The rows of each joint type (joint_solver.h): building a joint's row at
// the start of its group's solve, the warm start, one pass, and storing
// its impulses.
#include "joint_solver.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace tumble::physics {
namespace {

// [r]x: the matrix of v -> r x v.
Mat3 cross_matrix(const Vec3& r) {
  Mat3 m;
  m << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return m;
}

// The point block's K^-1 for the arms r_a, r_b (joint_solver.h, "Geometry").
Mat3 point_block_mass(const JointRow& row, const Vec3& r_a, const Vec3& r_b) {
  const Mat3 sa = cross_matrix(r_a), sb = cross_matrix(r_b);
  const Mat3 k = (row.inverse_mass_a + row.inverse_mass_b) * Mat3::Identity() - sa * row.inverse_inertia_a * sa -
                 sb * row.inverse_inertia_b * sb;
  return k.inverse();
}

// The anchors r_a, r_b turned by the bodies' rotation so far, and the gap
// d = anchor B minus anchor A after their moves (joint_solver.h, "Geometry").
Vec3 anchor_gap(const JointRow& row, const SolverBody* slots, const Quat* turns, Vec3& anchor_a, Vec3& anchor_b) {
  anchor_a = turns[row.slot_a] * row.anchor_a;
  anchor_b = turns[row.slot_b] * row.anchor_b;
  return row.delta_center + (load_vec3(slots[row.slot_b].displacement) - load_vec3(slots[row.slot_a].displacement)) +
         anchor_b - anchor_a;
}

// The two bodies' velocities during a pass, in double precision.
struct Velocities {
  Vec3 linear_a, angular_a, linear_b, angular_b;
};

Velocities load(const JointRow& row, const SolverBody* slots) {
  const SolverBody& a = slots[row.slot_a];
  const SolverBody& b = slots[row.slot_b];
  return {load_vec3(a.linear), load_vec3(a.angular), load_vec3(b.linear), load_vec3(b.angular)};
}

// Writes the velocities back; slot 0, the group's slot of zeros, is never
// written (a body of infinite mass takes no change anyway).
void save(const JointRow& row, const Velocities& v, SolverBody* slots) {
  if (row.slot_a != 0) {
    store_vec3(slots[row.slot_a].linear, v.linear_a);
    store_vec3(slots[row.slot_a].angular, v.angular_a);
  }
  if (row.slot_b != 0) {
    store_vec3(slots[row.slot_b].linear, v.linear_b);
    store_vec3(slots[row.slot_b].angular, v.angular_b);
  }
}

using Geometry = JointGeometry;

// One scalar row: Cdot = linear.(v_b - v_a) + angular_b.w_b - angular_a.w_a.
struct Jacobian {
  Vec3 linear = Vec3::Zero();
  Vec3 angular_a = Vec3::Zero();
  Vec3 angular_b = Vec3::Zero();

  Jacobian operator-() const { return {-linear, -angular_a, -angular_b}; }
};

Jacobian angular_row(const Vec3& axis) { return {Vec3::Zero(), axis, axis}; }

// A row along n through the anchors; arm_a is A's lever arm (the anchor,
// or anchor plus d when n turns with A).
Jacobian linear_row(const Vec3& n, const Vec3& arm_a, const Vec3& arm_b) { return {n, arm_a.cross(n), arm_b.cross(n)}; }

double velocity(const Jacobian& j, const Velocities& v) {
  return j.linear.dot(v.linear_b - v.linear_a) + j.angular_b.dot(v.angular_b) - j.angular_a.dot(v.angular_a);
}

// J_1 M^-1 J_2^T: how an impulse along row 2 changes row 1's velocity.
double coupling(const JointRow& row, const Jacobian& j1, const Jacobian& j2) {
  return (row.inverse_mass_a + row.inverse_mass_b) * j1.linear.dot(j2.linear) +
         j1.angular_a.dot(row.inverse_inertia_a * j2.angular_a) +
         j1.angular_b.dot(row.inverse_inertia_b * j2.angular_b);
}

// 1 / (J M^-1 J^T), or 0 when nothing can move along the row.
double effective_mass(const JointRow& row, const Jacobian& j) {
  const double k = coupling(row, j, j);
  return k > 0 ? 1.0 / k : 0.0;
}

// K^-1 of two rows solved as one block, K = [J_i M^-1 J_j^T].
Eigen::Matrix2d block_mass(const JointRow& row, const Jacobian& j1, const Jacobian& j2) {
  Eigen::Matrix2d k;
  k(0, 0) = coupling(row, j1, j1);
  k(0, 1) = k(1, 0) = coupling(row, j1, j2);
  k(1, 1) = coupling(row, j2, j2);
  return k.inverse();
}

void apply(const JointRow& row, const Jacobian& j, double lambda, Velocities& v) {
  v.linear_a -= (row.inverse_mass_a * lambda) * j.linear;
  v.angular_a -= row.inverse_inertia_a * (lambda * j.angular_a);
  v.linear_b += (row.inverse_mass_b * lambda) * j.linear;
  v.angular_b += row.inverse_inertia_b * (lambda * j.angular_b);
}

// A linear impulse p on B (and -p on A) at the lever arms, plus an angular
// impulse l on B (and -l on A).
void apply(const JointRow& row, const Vec3& p, const Vec3& arm_a, const Vec3& arm_b, const Vec3& l, Velocities& v) {
  v.linear_a -= row.inverse_mass_a * p;
  v.angular_a -= row.inverse_inertia_a * (arm_a.cross(p) + l);
  v.linear_b += row.inverse_mass_b * p;
  v.angular_b += row.inverse_inertia_b * (arm_b.cross(p) + l);
}

// The position terms of a rigid row: a soft pass corrects C through the
// joint spring, a relax pass not at all.
struct Correction {
  double bias_rate = 0;
  double mass_scale = 1;
  double impulse_scale = 0;
};

Correction correction(const JointStepSettings& settings, bool soft) {
  if (!soft) return {};
  return {settings.joint_soft.bias_rate, settings.joint_soft.mass_scale, settings.joint_soft.impulse_scale};
}

// A one-sided row C >= 0 (a limit), as Box2D v3 solves its limits: while
// C > 0 the bodies may close the gap within the substep (speculative);
// while violated it is pushed back softly in a soft pass and held rigidly
// in a relax pass. The accumulated impulse stays >= 0.
void solve_one_sided(const JointRow& row, const Jacobian& j, double mass, double c, double& accumulated,
                     const JointStepSettings& settings, bool soft, Velocities& v) {
  double bias = 0, mass_scale = 1, impulse_scale = 0;
  if (c > 0) {
    bias = c * settings.inverse_h;
  } else if (soft) {
    bias = settings.joint_soft.bias_rate * c;
    mass_scale = settings.joint_soft.mass_scale;
    impulse_scale = settings.joint_soft.impulse_scale;
  }
  const double target = velocity(j, v) + bias;
  // With nothing accumulated the impulse has the sign of -target, and
  // clamped at zero it is zero: a limit not reached this substep (most
  // of them, most of the time) costs no more than its velocity.
  if (accumulated == 0 && target >= 0) return;
  double lambda = -mass * mass_scale * target - impulse_scale * accumulated;
  const double next = std::max(accumulated + lambda, 0.0);
  lambda = next - accumulated;
  accumulated = next;
  apply(row, j, lambda, v);
}

// An equality row C = 0 with the joint spring.
void solve_rigid(const JointRow& row, const Jacobian& j, double mass, double c, double& accumulated,
                 const JointStepSettings& settings, bool soft, Velocities& v) {
  const Correction k = correction(settings, soft);
  const double lambda = -mass * k.mass_scale * (velocity(j, v) + k.bias_rate * c) - k.impulse_scale * accumulated;
  accumulated += lambda;
  apply(row, j, lambda, v);
}

// A spring row towards C = 0 with its own softness, in every pass.
void solve_spring(const JointRow& row, const Jacobian& j, double mass, double c, const Softness& spring,
                  double& accumulated, Velocities& v) {
  const double lambda =
      -mass * spring.mass_scale * (velocity(j, v) + spring.bias_rate * c) - spring.impulse_scale * accumulated;
  accumulated += lambda;
  apply(row, j, lambda, v);
}

// The motor of a hinge or slider along j, at `position` (rad or m).
void solve_motor(const JointRow& row, const JointMotor& motor, const Jacobian& j, double mass, double position,
                 bool angular, const JointStepSettings& settings, double& accumulated, Velocities& v) {
  const double cdot = velocity(j, v);
  double lambda;
  if (motor.mode == JointMotor::Mode::speed) {
    lambda = -mass * (cdot - motor.target);
  } else {
    double c = position - motor.target;
    // The shorter way round for a hinge.
    if (angular) c = std::remainder(c, 2.0 * std::numbers::pi);
    const Softness& s = row.motor_soft;
    lambda = -mass * s.mass_scale * (cdot + s.bias_rate * c) - s.impulse_scale * accumulated;
  }
  // The motor's force within max_force: an impulse within max_force h a substep.
  const double max_impulse = motor.max_force * settings.h;
  const double next = std::clamp(accumulated + lambda, -max_impulse, max_impulse);
  lambda = next - accumulated;
  accumulated = next;
  apply(row, j, lambda, v);
}

// A ball joint's friction: the relative angular velocity w_b - w_a driven
// to zero as one block, the impulse within friction h in magnitude (the
// torque resists turning about any axis alike).
void solve_ball_friction(const JointRow& row, double friction, const JointStepSettings& settings, Vec3& accumulated,
                         Velocities& v) {
  const Vec3 cdot = v.angular_b - v.angular_a;
  Vec3 next = accumulated - row.lock_mass * cdot;
  const double max_impulse = friction * settings.h;
  if (next.squaredNorm() > max_impulse * max_impulse) next *= max_impulse / next.norm();
  const Vec3 lambda = next - accumulated;
  accumulated = next;
  v.angular_a -= row.inverse_inertia_a * lambda;
  v.angular_b += row.inverse_inertia_b * lambda;
}

// The point constraint C = d, three rows as one block (joint_solver.h).
void solve_point(const JointRow& row, const Geometry& g, const JointStepSettings& settings, bool soft,
                 Vec3& accumulated, Velocities& v) {
  const Vec3 cdot = v.linear_b + v.angular_b.cross(g.anchor_b) - v.linear_a - v.angular_a.cross(g.anchor_a);
  const Correction c = correction(settings, soft);
  const Vec3 lambda = -c.mass_scale * (row.point_mass * (cdot + c.bias_rate * g.d)) - c.impulse_scale * accumulated;
  accumulated += lambda;
  apply(row, lambda, g.anchor_a, g.anchor_b, Vec3::Zero(), v);
}

// The rotation lock: frame B turns with frame A (fixed, slider).
void solve_rotation_lock(const JointRow& row, const Geometry& g, const JointStepSettings& settings, bool soft,
                         Vec3& accumulated, Velocities& v) {
  const Vec3 cdot = v.angular_b - v.angular_a;
  // The small-angle rotation from frame A to frame B: 2 vec(q_B q_A^-1),
  // on the short way round.
  const Quat error = Quat(g.frame_b) * Quat(g.frame_a).conjugate();
  const Vec3 c = (error.w() < 0 ? -2.0 : 2.0) * error.vec();
  const Correction s = correction(settings, soft);
  const Vec3 lambda = -s.mass_scale * (row.lock_mass * (cdot + s.bias_rate * c)) - s.impulse_scale * accumulated;
  accumulated += lambda;
  v.angular_a -= row.inverse_inertia_a * lambda;
  v.angular_b += row.inverse_inertia_b * lambda;
}

// The hinge's two alignment rows, C_i = a_A.b_B and a_A.c_B, as one 2x2
// block; their accumulated impulses are accumulated.x() and .y().
void solve_hinge_alignment(const JointRow& row, const Geometry& g, const JointStepSettings& settings, bool soft,
                           Vec3& accumulated, Velocities& v) {
  const Vec3 axis = g.frame_a.col(0);
  const Vec3 j1 = g.frame_b.col(1).cross(axis), j2 = g.frame_b.col(2).cross(axis);
  const Vec3 dw = v.angular_b - v.angular_a;
  const Eigen::Vector2d c(axis.dot(g.frame_b.col(1)), axis.dot(g.frame_b.col(2)));
  const Eigen::Vector2d cdot(j1.dot(dw), j2.dot(dw));
  const Correction s = correction(settings, soft);
  const Eigen::Vector2d previous(accumulated.x(), accumulated.y());
  const Eigen::Vector2d lambda = -s.mass_scale * (g.block_mass * (cdot + s.bias_rate * c)) - s.impulse_scale * previous;
  accumulated.x() += lambda.x();
  accumulated.y() += lambda.y();
  const Vec3 l = lambda.x() * j1 + lambda.y() * j2;
  v.angular_a -= row.inverse_inertia_a * l;
  v.angular_b += row.inverse_inertia_b * l;
}

// The slider's two rows across the axis, C_i = d.n_i for frame A's y and z
// axes, as one 2x2 block; accumulated.x() and .y().
void solve_slider_line(const JointRow& row, const Geometry& g, const JointStepSettings& settings, bool soft,
                       Vec3& accumulated, Velocities& v) {
  const Vec3 arm_a = g.anchor_a + g.d;
  const Jacobian j1 = linear_row(g.frame_a.col(1), arm_a, g.anchor_b);
  const Jacobian j2 = linear_row(g.frame_a.col(2), arm_a, g.anchor_b);
  const Eigen::Vector2d c(g.d.dot(g.frame_a.col(1)), g.d.dot(g.frame_a.col(2)));
  const Eigen::Vector2d cdot(velocity(j1, v), velocity(j2, v));
  const Correction s = correction(settings, soft);
  const Eigen::Vector2d previous(accumulated.x(), accumulated.y());
  const Eigen::Vector2d lambda = -s.mass_scale * (g.block_mass * (cdot + s.bias_rate * c)) - s.impulse_scale * previous;
  accumulated.x() += lambda.x();
  accumulated.y() += lambda.y();
  apply(row, j1, lambda.x(), v);
  apply(row, j2, lambda.y(), v);
}

// The rows along the joint's free direction (hinge: about a_A; slider:
// along it): friction, motor, then the limits.
void solve_axial(JointRow& row, const JointDesc& desc, const Jacobian& j, double position, bool angular,
                 const JointStepSettings& settings, bool soft, Velocities& v) {
  JointImpulses& impulses = row.impulses;
  const double mass = row.geometry.axial_mass;
  if (desc.friction > 0) {
    // Coulomb friction on the free direction: a motor of target speed 0
    // whose force is the friction, with its own accumulated impulse.
    const JointMotor still{JointMotor::Mode::speed, 0, desc.friction};
    solve_motor(row, still, j, mass, position, angular, settings, impulses.friction.x(), v);
  }
  if (desc.motor.mode != JointMotor::Mode::off) {
    solve_motor(row, desc.motor, j, mass, position, angular, settings, impulses.motor, v);
  }
  if (desc.limits_enabled) {
    solve_one_sided(row, j, mass, position - desc.lower, impulses.lower, settings, soft, v);
    solve_one_sided(row, -j, mass, desc.upper - position, impulses.upper, settings, soft, v);
  }
}

// The net impulse of the axial rows along their direction.
double axial_impulse(const JointImpulses& impulses) {
  return impulses.friction.x() + impulses.motor + impulses.lower - impulses.upper;
}

}  // namespace

void measure_joint(JointRow& row, const SolverBody* slots, const Quat* turns) {
  const Quat& turn_a = turns[row.slot_a];
  const Quat& turn_b = turns[row.slot_b];
  Geometry& g = row.geometry;
  g.d = anchor_gap(row, slots, turns, g.anchor_a, g.anchor_b);
  g.cone_axis_valid = false;
  if (row.type == JointType::distance) {
    const double length = g.d.norm();
    if (length >= 1e-12) g.axial_mass = effective_mass(row, linear_row(g.d / length, g.anchor_a, g.anchor_b));
  }
  if (!row.frames) return;
  g.frame_a = (turn_a * row.frame_a).toRotationMatrix();
  g.frame_b = (turn_b * row.frame_b).toRotationMatrix();
  const Vec3 axis = g.frame_a.col(0);
  if (row.type == JointType::hinge) {
    // Frame B's y axis against frame A's, about A's x axis.
    const Vec3 ya = g.frame_a.col(1), yb = g.frame_b.col(1);
    g.angle = std::atan2(ya.cross(yb).dot(axis), ya.dot(yb));
    g.axial_mass = effective_mass(row, angular_row(axis));
    // The alignment rows j_1 = b_B x a_A, j_2 = c_B x a_A (angular only).
    g.block_mass =
        block_mass(row, angular_row(g.frame_b.col(1).cross(axis)), angular_row(g.frame_b.col(2).cross(axis)));
  } else if (row.type == JointType::ball) {
    // The cone: the angle between the frames' x axes, about their normal.
    const Vec3 n = axis.cross(g.frame_b.col(0));
    const double s = n.norm();
    g.angle = std::atan2(s, axis.dot(g.frame_b.col(0)));
    g.cone_axis_valid = s >= 1e-9;
    if (g.cone_axis_valid) {
      g.cone_axis = n / s;
      g.axial_mass = effective_mass(row, angular_row(g.cone_axis));
    }
  } else if (row.type == JointType::slider) {
    const Vec3 arm_a = g.anchor_a + g.d;
    g.axial_mass = effective_mass(row, linear_row(axis, arm_a, g.anchor_b));
    // The line rows, along n_1, n_2 = frame A's y and z axes.
    g.block_mass = block_mass(row, linear_row(g.frame_a.col(1), arm_a, g.anchor_b),
                              linear_row(g.frame_a.col(2), arm_a, g.anchor_b));
  }
}

void prepare_joint_row(const Joint& joint, std::uint32_t body_a, std::uint32_t body_b, std::uint32_t slot_a,
                       std::uint32_t slot_b, const ContactSolverBodies& bodies, const JointStepSettings& settings,
                       JointRow& row) {
  const JointDesc& desc = joint.desc;
  row.type = desc.type;
  row.slot_a = slot_a;
  row.slot_b = slot_b;
  // A side on the world has its frame in world coordinates and no motion.
  auto side = [&](std::uint32_t body, const Vec3& local_anchor, const Quat& local_basis, double& inverse_mass,
                  Mat3& inverse_inertia, Vec3& anchor, Quat& frame) -> Vec3 {
    if (body == kNoJointBody) {
      inverse_mass = 0;
      inverse_inertia.setZero();
      anchor = local_anchor;
      frame = local_basis;
      return Vec3::Zero();
    }
    const Transform& t = bodies.transforms[body];
    inverse_mass = bodies.inverse_mass[body];
    inverse_inertia = bodies.inverse_inertia[body];
    anchor = t.rotation * local_anchor;
    frame = (Quat(t.rotation) * local_basis).normalized();
    return t.position;
  };
  const Vec3 center_a = side(body_a, desc.local_anchor_a, desc.local_basis_a, row.inverse_mass_a, row.inverse_inertia_a,
                             row.anchor_a, row.frame_a);
  const Vec3 center_b = side(body_b, desc.local_anchor_b, desc.local_basis_b, row.inverse_mass_b, row.inverse_inertia_b,
                             row.anchor_b, row.frame_b);
  row.delta_center = center_b - center_a;
  const bool point = desc.type == JointType::ball || desc.type == JointType::hinge || desc.type == JointType::fixed;
  if (point) {
    row.point_mass = point_block_mass(row, row.anchor_a, row.anchor_b);
  }
  if (desc.type == JointType::fixed || desc.type == JointType::slider ||
      (desc.type == JointType::ball && desc.friction > 0)) {
    row.lock_mass = (row.inverse_inertia_a + row.inverse_inertia_b).inverse();
  }
  row.frames = !(desc.type == JointType::distance || (desc.type == JointType::ball && std::isinf(desc.cone_limit)));
  row.motor_soft = make_softness(desc.motor.hertz, desc.motor.damping_ratio, settings.h);
  row.spring_soft = make_softness(desc.spring_hertz, desc.spring_damping_ratio, settings.h);
  row.impulses = joint.impulses;
  row.motor_sum = 0;
}

void warm_start_joint(const JointRow& row, SolverBody* slots) {
  const Geometry& g = row.geometry;
  Velocities v = load(row, slots);
  const JointImpulses& impulses = row.impulses;
  switch (row.type) {
    case JointType::ball: {
      const Vec3 cone = g.cone_axis_valid ? Vec3(-impulses.lower * g.cone_axis) : Vec3::Zero();
      apply(row, impulses.linear, g.anchor_a, g.anchor_b, cone + impulses.friction, v);
      break;
    }
    case JointType::hinge: {
      const Vec3 axis = g.frame_a.col(0);
      const Vec3 l = impulses.angular.x() * g.frame_b.col(1).cross(axis) +
                     impulses.angular.y() * g.frame_b.col(2).cross(axis) + axial_impulse(impulses) * axis;
      apply(row, impulses.linear, g.anchor_a, g.anchor_b, l, v);
      break;
    }
    case JointType::fixed:
      apply(row, impulses.linear, g.anchor_a, g.anchor_b, impulses.angular, v);
      break;
    case JointType::slider: {
      const Vec3 p = impulses.linear.x() * g.frame_a.col(1) + impulses.linear.y() * g.frame_a.col(2) +
                     axial_impulse(impulses) * g.frame_a.col(0);
      apply(row, p, g.anchor_a + g.d, g.anchor_b, impulses.angular, v);
      break;
    }
    case JointType::distance: {
      const double length = g.d.norm();
      if (length < 1e-12) break;
      const Vec3 p = (impulses.linear.x() + impulses.spring + impulses.lower - impulses.upper) / length * g.d;
      apply(row, p, g.anchor_a, g.anchor_b, Vec3::Zero(), v);
      break;
    }
  }
  save(row, v, slots);
}

void solve_joint(JointRow& row, const Joint& joint, SolverBody* slots, const JointStepSettings& settings, bool soft) {
  const JointDesc& desc = joint.desc;
  const Geometry& g = row.geometry;
  Velocities v = load(row, slots);
  JointImpulses& impulses = row.impulses;
  switch (row.type) {
    case JointType::ball: {
      if (desc.friction > 0) solve_ball_friction(row, desc.friction, settings, impulses.friction, v);
      if (g.cone_axis_valid) {
        // C = cone - phi >= 0 with dphi/dt = axis.(w_b - w_a).
        solve_one_sided(row, angular_row(-g.cone_axis), g.axial_mass, desc.cone_limit - g.angle, impulses.lower,
                        settings, soft, v);
      }
      solve_point(row, g, settings, soft, impulses.linear, v);
      break;
    }
    case JointType::hinge:
      solve_axial(row, desc, angular_row(g.frame_a.col(0)), g.angle, true, settings, soft, v);
      solve_hinge_alignment(row, g, settings, soft, impulses.angular, v);
      solve_point(row, g, settings, soft, impulses.linear, v);
      break;
    case JointType::fixed:
      solve_rotation_lock(row, g, settings, soft, impulses.angular, v);
      solve_point(row, g, settings, soft, impulses.linear, v);
      break;
    case JointType::slider: {
      const Vec3 axis = g.frame_a.col(0);
      solve_axial(row, desc, linear_row(axis, g.anchor_a + g.d, g.anchor_b), g.d.dot(axis), false, settings, soft, v);
      solve_rotation_lock(row, g, settings, soft, impulses.angular, v);
      solve_slider_line(row, g, settings, soft, impulses.linear, v);
      break;
    }
    case JointType::distance: {
      const double length = g.d.norm();
      if (length < 1e-12) break;  // no direction to act along
      const Jacobian j = linear_row(g.d / length, g.anchor_a, g.anchor_b);
      const double mass = g.axial_mass;
      if (desc.min_length == desc.max_length) {
        solve_rigid(row, j, mass, length - desc.length, impulses.linear.x(), settings, soft, v);
        break;
      }
      if (desc.spring_hertz > 0) solve_spring(row, j, mass, length - desc.length, row.spring_soft, impulses.spring, v);
      solve_one_sided(row, j, mass, length - desc.min_length, impulses.lower, settings, soft, v);
      solve_one_sided(row, -j, mass, desc.max_length - length, impulses.upper, settings, soft, v);
      break;
    }
  }
  save(row, v, slots);
}

void correct_joint_position(JointRow& row, SolverBody* slots, Quat* turns, double fraction) {
  if (row.type != JointType::ball && row.type != JointType::hinge && row.type != JointType::fixed) return;
  SolverBody& a = slots[row.slot_a];
  SolverBody& b = slots[row.slot_b];
  Vec3 anchor_a, anchor_b;
  const Vec3 d = anchor_gap(row, slots, turns, anchor_a, anchor_b);
  if (d.squaredNorm() <= kJointSlop * kJointSlop) return;
  // K from the arms as they are now: the step's own (row.point_mass) can be
  // far off for a link that has turned a tenth of a radian, and a chain
  // with a heavy weight then overshoots.
  const Vec3 p = -fraction * (point_block_mass(row, anchor_a, anchor_b) * d);
  // The body's move by the impulse p: dx = p / M, dtheta = I^-1 (r x p),
  // with the world-frame I^-1 of the step's start.
  if (row.inverse_mass_a > 0) {
    store_vec3(a.displacement, load_vec3(a.displacement) - row.inverse_mass_a * p);
    store_vec3(a.rotation, load_vec3(a.rotation) - row.inverse_inertia_a * anchor_a.cross(p));
    turns[row.slot_a] = quat_from_rotation_vector(load_vec3(a.rotation));
  }
  if (row.inverse_mass_b > 0) {
    store_vec3(b.displacement, load_vec3(b.displacement) + row.inverse_mass_b * p);
    store_vec3(b.rotation, load_vec3(b.rotation) + row.inverse_inertia_b * anchor_b.cross(p));
    turns[row.slot_b] = quat_from_rotation_vector(load_vec3(b.rotation));
  }
}

void store_joint(const JointRow& row, const JointStepSettings& settings, Joint& joint) {
  const Geometry& g = row.geometry;
  const JointImpulses& impulses = row.impulses;
  Vec3 linear = Vec3::Zero(), angular = Vec3::Zero();
  switch (row.type) {
    case JointType::ball:
      linear = impulses.linear;
      angular = impulses.friction;
      if (g.cone_axis_valid) angular -= impulses.lower * g.cone_axis;
      break;
    case JointType::hinge: {
      const Vec3 axis = g.frame_a.col(0);
      linear = impulses.linear;
      angular = impulses.angular.x() * g.frame_b.col(1).cross(axis) +
                impulses.angular.y() * g.frame_b.col(2).cross(axis) + axial_impulse(impulses) * axis;
      break;
    }
    case JointType::fixed:
      linear = impulses.linear;
      angular = impulses.angular;
      break;
    case JointType::slider:
      linear = impulses.linear.x() * g.frame_a.col(1) + impulses.linear.y() * g.frame_a.col(2) +
               axial_impulse(impulses) * g.frame_a.col(0);
      angular = impulses.angular;
      break;
    case JointType::distance: {
      const double length = g.d.norm();
      if (length >= 1e-12) {
        linear = (impulses.linear.x() + impulses.spring + impulses.lower - impulses.upper) / length * g.d;
      }
      break;
    }
  }
  // The accumulated impulses act in every substep: force = impulse / h.
  joint.force = linear * settings.inverse_h;
  joint.torque = angular * settings.inverse_h;
  joint.motor_impulse = row.motor_sum;
  joint.impulses = impulses;
}

}  // namespace tumble::physics
