// Torque-free rotation: conservation of L and kinetic energy, agreement with
// an independent solution of Euler's equations, the intermediate axis
// theorem, and the unit length of the orientation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "integrator.h"
#include "rotation.h"
#include "tumble/physics/mass_properties.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

// The asymmetric box of these tests: half extents (0.1, 0.3, 0.6), mass 1.
// Principal moments I_x = 0.15 (largest), I_y = 0.37/3 (intermediate),
// I_z = 0.1/3 (smallest).
const Vec3 kHalfExtents(0.1, 0.3, 0.6);
constexpr double kMass = 1.0;
constexpr double kDt = 1.0 / 240.0;

BodyDesc spinning_box(const Quat& orientation, const Vec3& angular_velocity_body) {
  BodyDesc desc;
  desc.shape.type = ShapeType::box;
  desc.shape.half_extents = kHalfExtents;
  desc.mass_properties = box_mass_properties(kMass, kHalfExtents);
  desc.orientation = orientation;
  desc.angular_velocity = orientation * angular_velocity_body;
  return desc;
}

Quat generic_orientation() { return quat_from_rotation_vector(Vec3(0.3, -0.7, 1.1)); }

// Reference solution, independent of the integrator: Euler's equations in
// principal body axes, I_1 dw_1/dt = (I_2 - I_3) w_2 w_3 (cyclic), and
// dq/dt = 1/2 q [0, w_body], by classical Runge-Kutta with a small step.
struct EulerReference {
  Vec3 moments;  // principal moments of inertia
  Quat q;        // body -> world
  Vec3 w;        // angular velocity, body axes

  struct Rate {
    Vec3 dw;
    Eigen::Vector4d dq;  // derivative of (w, x, y, z)
  };

  Rate rate(const Eigen::Vector4d& qv, const Vec3& wb) const {
    Rate r;
    r.dw = Vec3((moments.y() - moments.z()) * wb.y() * wb.z() / moments.x(),
                (moments.z() - moments.x()) * wb.z() * wb.x() / moments.y(),
                (moments.x() - moments.y()) * wb.x() * wb.y() / moments.z());
    const Quat qq(qv(0), qv(1), qv(2), qv(3));
    const Quat dq = qq * Quat(0.0, wb.x(), wb.y(), wb.z());
    r.dq = 0.5 * Eigen::Vector4d(dq.w(), dq.x(), dq.y(), dq.z());
    return r;
  }

  void step(double h) {
    const Eigen::Vector4d q0(q.w(), q.x(), q.y(), q.z());
    const Rate k1 = rate(q0, w);
    const Rate k2 = rate(q0 + 0.5 * h * k1.dq, w + 0.5 * h * k1.dw);
    const Rate k3 = rate(q0 + 0.5 * h * k2.dq, w + 0.5 * h * k2.dw);
    const Rate k4 = rate(q0 + h * k3.dq, w + h * k3.dw);
    const Eigen::Vector4d q1 = q0 + h / 6.0 * (k1.dq + 2.0 * k2.dq + 2.0 * k3.dq + k4.dq);
    w += h / 6.0 * (k1.dw + 2.0 * k2.dw + 2.0 * k3.dw + k4.dw);
    q = Quat(q1(0), q1(1), q1(2), q1(3)).normalized();
  }
};

// Angle (rad) between two orientations.
double angle_between(const Quat& a, const Quat& b) { return a.angularDistance(b); }

TEST(AngularMotionTest, TorqueFreeConservesMomentumAndEnergy) {
  World world;
  world.set_gravity(Vec3::Zero());
  const BodyId id = world.add_body(spinning_box(generic_orientation(), Vec3(2.0, 3.0, -1.5)));

  const Vec3 l0 = world.angular_momentum(id);
  const double e0 = world.kinetic_energy(id);
  double max_l_drift = 0;
  double max_e_drift = 0;
  const int steps = 2400;  // 10 s at 240 Hz
  for (int i = 0; i < steps; ++i) {
    world.step(kDt);
    const Vec3& l = world.angular_momentum(id);
    EXPECT_EQ(l, l0) << "step " << i;  // L is the state: untouched without torque
    max_l_drift = std::max(max_l_drift, std::abs(l.norm() - l0.norm()) / l0.norm());
    max_e_drift = std::max(max_e_drift, std::abs(world.kinetic_energy(id) - e0) / e0);
  }
  EXPECT_LE(max_l_drift, 1e-6);
  EXPECT_LE(max_e_drift, 1e-3);
  RecordProperty("max_relative_angular_momentum_drift", std::to_string(max_l_drift));
  RecordProperty("max_relative_kinetic_energy_drift", std::to_string(max_e_drift));
  std::printf("[ measured ] torque-free box, 10 s at 240 Hz: max |L| drift %.3e, max energy drift %.3e (relative)\n",
              max_l_drift, max_e_drift);
}

TEST(AngularMotionTest, EnergyErrorDoesNotGrow) {
  // The symmetric update bounds the energy error: it oscillates rather than
  // accumulating, so the worst error over the last 10 s of a 40 s run is no
  // larger than over the first 10 s (a drifting scheme would grow fourfold).
  World world;
  world.set_gravity(Vec3::Zero());
  const BodyId id = world.add_body(spinning_box(generic_orientation(), Vec3(2.0, 3.0, -1.5)));
  const double e0 = world.kinetic_energy(id);
  const int quarter = 2400;
  double first = 0;
  double last = 0;
  for (int i = 0; i < 4 * quarter; ++i) {
    world.step(kDt);
    const double drift = std::abs(world.kinetic_energy(id) - e0) / e0;
    if (i < quarter) first = std::max(first, drift);
    if (i >= 3 * quarter) last = std::max(last, drift);
  }
  EXPECT_LT(last, 1.5 * first) << "first 10 s " << first << ", last 10 s " << last;
}

TEST(AngularMotionTest, MatchesEulerEquationsSecondOrder) {
  const Quat q0 = generic_orientation();
  const Vec3 w0(2.0, 3.0, -1.5);
  const double duration = 2.0;

  EulerReference reference{box_mass_properties(kMass, kHalfExtents).inertia.diagonal(), q0, w0};
  const int substeps = 16;
  for (int i = 0; i < static_cast<int>(std::lround(duration / kDt)) * substeps; ++i) reference.step(kDt / substeps);

  // Orientation error of the World after `duration` with step dt.
  auto error_with_step = [&](double dt) {
    World world;
    world.set_gravity(Vec3::Zero());
    const BodyId id = world.add_body(spinning_box(q0, w0));
    const int steps = static_cast<int>(std::lround(duration / dt));
    for (int i = 0; i < steps; ++i) world.step(dt);
    return angle_between(world.orientation(id), reference.q);
  };
  const double error_fine = error_with_step(kDt);
  const double error_coarse = error_with_step(2.0 * kDt);
  std::printf("[ measured ] orientation error after %.0f s vs RK4 reference: %.3e rad at 240 Hz, %.3e rad at 120 Hz\n",
              duration, error_fine, error_coarse);
  EXPECT_LT(error_fine, 1e-2);
  // Second order: halving dt divides the error by about four.
  const double ratio = error_coarse / error_fine;
  EXPECT_GT(ratio, 3.5);
  EXPECT_LT(ratio, 4.5);
}

// Spins the box about the principal body axis `axis` at 5 rad/s with a
// 1e-3 rad/s perturbation on the other two axes for 10 s, and returns the
// minimum over all steps of the dot product between that body axis in the
// world and its initial world direction.
double min_axis_alignment(int axis, double* first_flip_time) {
  const Quat q0 = generic_orientation();
  Vec3 w_body = Vec3::Constant(1e-3);
  w_body(axis) = 5.0;
  World world;
  world.set_gravity(Vec3::Zero());
  const BodyId id = world.add_body(spinning_box(q0, w_body));
  const Vec3 initial = q0 * Vec3::Unit(axis);
  double min_dot = 1.0;
  *first_flip_time = -1.0;
  for (int i = 0; i < 2400; ++i) {
    world.step(kDt);
    const double dot = (world.orientation(id) * Vec3::Unit(axis)).dot(initial);
    if (dot < -0.9 && *first_flip_time < 0) *first_flip_time = (i + 1) * kDt;
    min_dot = std::min(min_dot, dot);
  }
  return min_dot;
}

TEST(AngularMotionTest, IntermediateAxisFlips) {
  double flip_time = 0;
  const double min_dot = min_axis_alignment(1, &flip_time);  // y: intermediate
  EXPECT_LT(min_dot, -0.9);
  RecordProperty("intermediate_axis_min_dot", std::to_string(min_dot));
  RecordProperty("intermediate_axis_first_flip_s", std::to_string(flip_time));
  std::printf("[ measured ] intermediate axis (y): min dot %.6f, first below -0.9 at t = %.4f s\n", min_dot, flip_time);

  // The same flip in the reference solution of Euler's equations.
  const Quat q0 = generic_orientation();
  EulerReference reference{box_mass_properties(kMass, kHalfExtents).inertia.diagonal(), q0, Vec3(1e-3, 5.0, 1e-3)};
  const Vec3 initial = q0 * Vec3::UnitY();
  double reference_flip_time = -1.0;
  const int substeps = 4;
  for (int i = 0; i < 2400 * substeps && reference_flip_time < 0; ++i) {
    reference.step(kDt / substeps);
    if ((reference.q * Vec3::UnitY()).dot(initial) < -0.9) reference_flip_time = (i + 1) * kDt / substeps;
  }
  std::printf("[ measured ] reference flip at t = %.4f s\n", reference_flip_time);
  ASSERT_GT(reference_flip_time, 0.0);
  EXPECT_NEAR(flip_time, reference_flip_time, 0.02 * reference_flip_time);
}

TEST(AngularMotionTest, ExtremeAxesAreStable) {
  double unused = 0;
  const double min_dot_largest = min_axis_alignment(0, &unused);   // x: largest moment
  const double min_dot_smallest = min_axis_alignment(2, &unused);  // z: smallest moment
  EXPECT_GT(min_dot_largest, 0.99);
  EXPECT_GT(min_dot_smallest, 0.99);
  RecordProperty("largest_axis_min_dot", std::to_string(min_dot_largest));
  RecordProperty("smallest_axis_min_dot", std::to_string(min_dot_smallest));
  std::printf("[ measured ] largest axis (x): min dot %.9f; smallest axis (z): min dot %.9f\n", min_dot_largest,
              min_dot_smallest);
}

TEST(AngularMotionTest, OrientationStaysUnitInFastSpin) {
  World world;
  world.set_gravity(Vec3::Zero());
  const BodyId id = world.add_body(spinning_box(generic_orientation(), Vec3(20.0, 35.0, -15.0)));
  const double e0 = world.kinetic_energy(id);
  double max_norm_error = 0;
  double max_e_drift = 0;
  for (int i = 0; i < 14400; ++i) {  // 60 s at 240 Hz
    world.step(kDt);
    max_norm_error = std::max(max_norm_error, std::abs(world.orientation(id).norm() - 1.0));
    max_e_drift = std::max(max_e_drift, std::abs(world.kinetic_energy(id) - e0) / e0);
  }
  EXPECT_LT(max_norm_error, 1e-12);
  EXPECT_LT(max_e_drift, 0.05);
  std::printf("[ measured ] fast spin, 60 s at 240 Hz: max | |q| - 1 | %.3e, max energy drift %.3e\n", max_norm_error,
              max_e_drift);
}

TEST(AngularMotionTest, SphereSpinsAtConstantRate) {
  // Isotropic inertia: w = L / I is constant, so the orientation after n
  // steps is exactly exp(w n dt) q0.
  World world;
  world.set_gravity(Vec3::Zero());
  BodyDesc desc;
  desc.shape.type = ShapeType::sphere;
  desc.shape.radius = 0.5;
  desc.mass_properties = sphere_mass_properties(2.0, 0.5);
  desc.angular_velocity = Vec3(0.0, 0.0, 3.0);
  const BodyId id = world.add_body(desc);
  const int steps = 240;
  for (int i = 0; i < steps; ++i) world.step(kDt);
  const Quat expected = quat_from_rotation_vector(desc.angular_velocity * (steps * kDt));
  EXPECT_LT(angle_between(world.orientation(id), expected), 1e-12);
}

TEST(AngularMotionTest, ConstantTorqueAboutPrincipalAxis) {
  // tau about a principal axis: L = tau t exactly and the body turns through
  // the angle of the discrete sum dt^2 tau/I n(n+1)/2, as in the linear case.
  World world;
  world.set_gravity(Vec3::Zero());
  const BodyId id = world.add_body(spinning_box(Quat::Identity(), Vec3::Zero()));
  const double i_z = box_mass_properties(kMass, kHalfExtents).inertia(2, 2);
  const Vec3 torque(0.0, 0.0, 0.2);
  const int n = 120;
  for (int i = 0; i < n; ++i) {
    world.add_torque(id, torque);
    world.step(kDt);
  }
  EXPECT_LT((world.angular_momentum(id) - torque * (n * kDt)).norm(), 1e-14);
  const double angle = torque.z() / i_z * kDt * kDt * n * (n + 1) / 2.0;
  const Quat expected = quat_from_rotation_vector(Vec3(0.0, 0.0, angle));
  EXPECT_LT(angle_between(world.orientation(id), expected), 1e-12);
}

TEST(AngularMotionTest, AdvanceOrientationIsTimeSymmetric) {
  // Stepping forward then backward with the same L returns to the start.
  const Mat3 inverse_inertia = box_mass_properties(kMass, kHalfExtents).inertia.inverse();
  const Quat q0 = generic_orientation();
  const Vec3 l(0.3, -0.5, 0.2);
  const double dt = 0.02;
  const Quat q1 = advance_orientation(q0, l, inverse_inertia, dt);
  const Quat back = advance_orientation(q1, l, inverse_inertia, -dt);
  EXPECT_GT(angle_between(q0, q1), 1e-3);
  EXPECT_LT(angle_between(q0, back), 1e-13);
}

}  // namespace
}  // namespace tumble::physics
