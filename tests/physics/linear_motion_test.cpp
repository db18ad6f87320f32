// Forces, torques and impulses: momenta and positions against the closed
// forms of the semi-implicit Euler scheme (integrator.h).
#include <gtest/gtest.h>

#include <cmath>

#include "tumble/physics/mass_properties.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

// Expects |a - b| <= tolerance componentwise.
void expect_near(const Vec3& a, const Vec3& b, double tolerance) {
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(a(i), b(i), tolerance) << "component " << i << ": " << a.transpose() << " vs " << b.transpose();
  }
}

// Principal moments of a solid box, written out: m/3 (hy^2 + hz^2), ...
Vec3 box_moments(double mass, const Vec3& h) {
  return (mass / 3.0) *
         Vec3(h.y() * h.y() + h.z() * h.z(), h.x() * h.x() + h.z() * h.z(), h.x() * h.x() + h.y() * h.y());
}

BodyDesc box_desc(double mass, const Vec3& half_extents, const Vec3& position) {
  BodyDesc desc;
  desc.shape.type = ShapeType::box;
  desc.shape.half_extents = half_extents;
  desc.mass_properties = box_mass_properties(mass, half_extents);
  desc.position = position;
  return desc;
}

// Under constant acceleration a from rest, semi-implicit Euler gives
// v_n = a n dt and x_n = x_0 + a dt^2 (1 + 2 + ... + n) = x_0 + a dt^2 n(n+1)/2,
// which exceeds the exact 1/2 a t^2 by a t dt / 2.
void expect_constant_acceleration(const World& world, BodyId id, const Vec3& x0, const Vec3& a, double dt, int n) {
  const double t = n * dt;
  expect_near(world.linear_velocity(id), a * t, 1e-12);
  const Vec3 x_discrete = x0 + a * (dt * dt * n * (n + 1) / 2.0);
  expect_near(world.position(id), x_discrete, 1e-12);
  const Vec3 x_exact = x0 + 0.5 * a * t * t;
  const double bound = 0.5 * a.norm() * t * dt;
  EXPECT_LE((world.position(id) - x_exact).norm(), bound * (1.0 + 1e-9));
  // The bound is tight (the scheme is first order in position), not slack.
  EXPECT_GE((world.position(id) - x_exact).norm(), bound * (1.0 - 1e-9));
}

TEST(LinearMotionTest, ConstantForceFromRest) {
  World world;
  world.set_gravity(Vec3::Zero());
  const Vec3 x0(1.0, 2.0, 3.0);
  const double mass = 2.5;
  const BodyId id = world.add_body(box_desc(mass, Vec3(0.5, 0.5, 0.5), x0));

  const Vec3 force(3.0, -1.5, 2.0);
  const double dt = 1.0 / 60.0;
  const int n = 120;
  for (int i = 0; i < n; ++i) {
    world.add_force(id, force);
    world.step(dt);
  }
  expect_constant_acceleration(world, id, x0, force / mass, dt, n);
  expect_near(world.linear_momentum(id), force * (n * dt), 1e-12);
  // A force through the centre of mass does not turn the body.
  EXPECT_EQ(world.angular_momentum(id), Vec3::Zero());
  EXPECT_EQ(world.orientation(id).coeffs(), Quat::Identity().coeffs());
}

TEST(LinearMotionTest, AccumulatorsClearedByStep) {
  World world;
  world.set_gravity(Vec3::Zero());
  const BodyId id = world.add_body(box_desc(2.0, Vec3(0.5, 0.5, 0.5), Vec3::Zero()));
  world.add_force(id, Vec3(2.0, 0.0, 0.0));
  world.add_torque(id, Vec3(0.0, 1.0, 0.0));
  world.step(0.5);
  EXPECT_EQ(world.accumulated_force(id), Vec3::Zero());
  EXPECT_EQ(world.accumulated_torque(id), Vec3::Zero());
  const Vec3 p = world.linear_momentum(id);
  const Vec3 l = world.angular_momentum(id);
  world.step(0.5);  // no new force: momenta unchanged
  EXPECT_EQ(world.linear_momentum(id), p);
  EXPECT_EQ(world.angular_momentum(id), l);
  expect_near(p, Vec3(1.0, 0.0, 0.0), 1e-15);
  expect_near(l, Vec3(0.0, 0.5, 0.0), 1e-15);
}

TEST(LinearMotionTest, GravityFreeFall) {
  World world;
  EXPECT_EQ(world.gravity(), Vec3(0.0, -9.81, 0.0));
  const Vec3 x0(0.0, 100.0, 0.0);
  const BodyId id = world.add_body(box_desc(7.0, Vec3(0.2, 0.3, 0.4), x0));
  const double dt = 1.0 / 240.0;
  const int n = 480;
  for (int i = 0; i < n; ++i) world.step(dt);
  expect_constant_acceleration(world, id, x0, world.gravity(), dt, n);
  // Gravity acts at the centre of mass: no rotation.
  EXPECT_EQ(world.angular_momentum(id), Vec3::Zero());
}

TEST(LinearMotionTest, CustomGravityIsIndependentOfMass) {
  World world;
  const Vec3 g(1.0, -3.0, 0.5);
  world.set_gravity(g);
  // Side by side, far enough apart not to touch.
  const Vec3 light_start(-5.0, 0.0, 0.0), heavy_start(5.0, 0.0, 0.0);
  const BodyId light = world.add_body(box_desc(0.1, Vec3(0.1, 0.1, 0.1), light_start));
  const BodyId heavy = world.add_body(box_desc(1000.0, Vec3(1.0, 1.0, 1.0), heavy_start));
  const double dt = 0.01;
  const int n = 100;
  for (int i = 0; i < n; ++i) world.step(dt);
  expect_constant_acceleration(world, light, light_start, g, dt, n);
  expect_constant_acceleration(world, heavy, heavy_start, g, dt, n);
}

TEST(LinearMotionTest, OffCentreForceSpinUp) {
  // A constant force applied at a point a fixed world offset d from the
  // centre of mass (the point travels with the centre): the torque d x F is
  // constant, so P = F T and L = (d x F) T however the body turns.
  World world;
  world.set_gravity(Vec3::Zero());
  const double mass = 2.0;
  const Vec3 x0(0.5, -1.0, 2.0);
  const BodyId id = world.add_body(box_desc(mass, Vec3(0.5, 0.25, 0.1), x0));

  const Vec3 force(1.0, 2.0, -0.5);
  const Vec3 offset(0.3, -0.2, 0.1);
  const double dt = 1.0 / 120.0;
  const int n = 120;
  for (int i = 0; i < n; ++i) {
    world.add_force_at_point(id, force, world.position(id) + offset);
    world.step(dt);
  }
  const double t = n * dt;
  expect_near(world.linear_momentum(id), force * t, 1e-9);
  expect_near(world.angular_momentum(id), offset.cross(force) * t, 1e-9);
  expect_constant_acceleration(world, id, x0, force / mass, dt, n);
}

TEST(LinearMotionTest, OffCentreForceOneStep) {
  // A force at a body-fixed point (a corner of the box) for one step:
  // L = (r - x) x F dt, and w = I^-1 L with I the box's inertia.
  World world;
  world.set_gravity(Vec3::Zero());
  const double mass = 2.0;
  const Vec3 h(0.5, 0.25, 0.1);
  const Vec3 x0(0.5, -1.0, 2.0);
  const BodyId id = world.add_body(box_desc(mass, h, x0));

  const Vec3 corner = x0 + h;
  const Vec3 force(1.0, 2.0, -0.5);
  const double dt = 1.0 / 60.0;
  world.add_force_at_point(id, force, corner);
  expect_near(world.accumulated_torque(id), h.cross(force), 1e-15);
  world.step(dt);

  const Vec3 l = h.cross(force) * dt;
  expect_near(world.linear_momentum(id), force * dt, 1e-15);
  expect_near(world.angular_momentum(id), l, 1e-15);

  // The body has turned during the step, so express L in body axes, divide
  // by the principal moments, and turn back.
  const Vec3 moments = box_moments(mass, h);
  const Quat& q = world.orientation(id);
  const Vec3 w_expected = q * (q.conjugate() * l).cwiseQuotient(moments);
  expect_near(world.angular_velocity(id), w_expected, 1e-14);
  EXPECT_FALSE(q.isApprox(Quat::Identity(), 1e-6));  // it did turn
}

TEST(LinearMotionTest, ImpulseAtPoint) {
  World world;
  const double mass = 3.0;
  const Vec3 h(0.4, 0.3, 0.2);
  const Vec3 x0(1.0, 1.0, 1.0);
  BodyDesc desc = box_desc(mass, h, x0);
  desc.linear_velocity = Vec3(0.1, 0.2, 0.3);
  desc.angular_velocity = Vec3(-0.5, 0.25, 1.0);
  const BodyId id = world.add_body(desc);

  const Vec3 p0 = world.linear_momentum(id);
  const Vec3 l0 = world.angular_momentum(id);
  const Vec3 impulse(0.7, -0.2, 1.3);
  const Vec3 point = x0 + Vec3(0.4, -0.3, 0.2);
  world.apply_impulse_at_point(id, impulse, point);
  expect_near(world.linear_momentum(id) - p0, impulse, 1e-15);
  expect_near(world.angular_momentum(id) - l0, (point - x0).cross(impulse), 1e-15);

  // Orientation is the identity here, so w = L / moments componentwise.
  const Vec3 moments = box_moments(mass, h);
  expect_near(world.angular_velocity(id), world.angular_momentum(id).cwiseQuotient(moments), 1e-14);
  expect_near(world.linear_velocity(id), world.linear_momentum(id) / mass, 1e-15);

  // A central impulse changes P only.
  const Vec3 l1 = world.angular_momentum(id);
  world.apply_impulse(id, impulse);
  expect_near(world.linear_momentum(id) - p0, 2.0 * impulse, 1e-15);
  EXPECT_EQ(world.angular_momentum(id), l1);
}

}  // namespace
}  // namespace tumble::physics
