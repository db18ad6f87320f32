// Joints against analytic answers: pendulum periods, energy, a loaded
// chain, limits, motors, friction, a slider, a weld, breaking, and the bookkeeping
// (collision between jointed bodies, sleeping together, removal).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "scene_helpers.h"
#include "tumble/physics/joint.h"
#include "tumble/physics/world.h"

namespace tumble::physics {
namespace {

using testing::box_body;
using testing::kGravity;
using testing::kTick;
using testing::settings_without_sleep;
using testing::sphere_body;

// A joint of `type` between a and b at a world anchor (the same for both)
// with a world axis.
JointDesc joint_at(const World& world, JointType type, BodyId a, BodyId b, const Vec3& anchor,
                   const Vec3& axis = Vec3::UnitZ()) {
  JointDesc desc;
  desc.type = type;
  desc.body_a = a;
  desc.body_b = b;
  world.set_joint_frames(desc, anchor, anchor, axis);
  return desc;
}

// A rigid distance joint between anchor points on a and b, as long as they
// are apart now.
JointDesc rod(const World& world, BodyId a, BodyId b, const Vec3& anchor_a, const Vec3& anchor_b) {
  JointDesc desc;
  desc.type = JointType::distance;
  desc.body_a = a;
  desc.body_b = b;
  world.set_joint_frames(desc, anchor_a, anchor_b, Vec3::UnitX());
  desc.length = desc.min_length = desc.max_length = (anchor_b - anchor_a).norm();
  return desc;
}

// Distance between a joint's two anchors now (m): how far it has opened.
double separation(const World& world, JointId id) {
  const JointDesc& desc = world.joint_desc(id);
  auto anchor = [&](BodyId body, const Vec3& local) -> Vec3 {
    if (body == kWorldBodyId) return local;
    return world.position(body) + world.orientation(body) * local;
  };
  return (anchor(desc.body_b, desc.local_anchor_b) - anchor(desc.body_a, desc.local_anchor_a)).norm();
}

// The period of x(t) from its upward zero crossings (linear interpolation
// between ticks), averaged over every full period in `seconds`.
template <typename Sample>
double measured_period(World& world, double seconds, Sample sample) {
  std::vector<double> crossings;
  double previous = sample();
  const int steps = static_cast<int>(std::lround(seconds / kTick));
  for (int i = 1; i <= steps; ++i) {
    world.step(kTick);
    const double now = sample();
    if (previous < 0 && now >= 0) crossings.push_back((i - 1 + previous / (previous - now)) * kTick);
    previous = now;
  }
  if (crossings.size() < 2) return 0;
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

TEST(JointTest, APointMassOnADistanceJointSwingsWithTheSmallAnglePeriod) {
  World world;
  world.set_settings(settings_without_sleep());
  const double length = 1.0, angle = 0.05;
  const Vec3 pivot(0, 2, 0);
  // A small sphere whose centre hangs on the rod: its spin is free, so it
  // swings as a point mass.
  const BodyId bob =
      world.add_body(sphere_body(pivot + length * Vec3(std::sin(angle), -std::cos(angle), 0), 0.01, 1.0));
  world.add_joint(rod(world, kWorldBodyId, bob, pivot, world.position(bob)));
  const double period = measured_period(world, 12.0, [&] { return world.position(bob).x(); });
  const double expected = 2 * std::numbers::pi * std::sqrt(length / kGravity);
  EXPECT_NEAR(period, expected, 0.005 * expected);
}

TEST(JointTest, ARodOnAHingeSwingsWithTheCompoundPendulumPeriod) {
  World world;
  world.set_settings(settings_without_sleep());
  const double mass = 2.0, half_length = 0.5, half_width = 0.05, angle = 0.05;
  const Vec3 pivot(0, 2, 0);
  BodyDesc desc;
  desc.shape = box_shape(Vec3(half_width, half_length, half_width));
  desc.mass_properties = box_mass_properties(mass, desc.shape.half_extents);
  desc.orientation = Quat(Eigen::AngleAxisd(angle, Vec3::UnitZ()));
  desc.position = pivot + desc.orientation * Vec3(0, -half_length, 0);
  const BodyId rod_body = world.add_body(desc);
  world.add_joint(joint_at(world, JointType::hinge, kWorldBodyId, rod_body, pivot, Vec3::UnitZ()));
  const double period = measured_period(world, 12.0, [&] { return world.position(rod_body).x(); });
  // I about the pivot = I_cm + m d^2, with I_cm = m (h^2 + w^2) / 12 for
  // the full height h and width w.
  const double d = half_length;
  const double inertia = mass * (4 * half_length * half_length + 4 * half_width * half_width) / 12 + mass * d * d;
  const double expected = 2 * std::numbers::pi * std::sqrt(inertia / (mass * kGravity * d));
  EXPECT_NEAR(period, expected, 0.005 * expected);
}

TEST(JointTest, AFrictionlessPendulumKeepsItsEnergyForAMinute) {
  World world;
  world.set_settings(settings_without_sleep());
  const double length = 1.0, angle = std::numbers::pi / 3;
  const Vec3 pivot(0, 2, 0);
  const BodyId bob =
      world.add_body(sphere_body(pivot + length * Vec3(std::sin(angle), -std::cos(angle), 0), 0.05, 1.0));
  world.add_joint(rod(world, kWorldBodyId, bob, pivot, world.position(bob)));
  auto energy = [&] { return world.kinetic_energy(bob) + world.mass(bob) * kGravity * world.position(bob).y(); };
  const double start = energy();
  // Measured against the energy the swing trades: m g L (1 - cos 60).
  const double swing = world.mass(bob) * kGravity * length * (1 - std::cos(angle));
  double worst = 0;
  for (int i = 0; i < 60 * 240; ++i) {
    world.step(kTick);
    worst = std::max(worst, std::abs(energy() - start));
  }
  EXPECT_LT(worst, 0.01 * swing);
}

// The joints are soft (joint_solver.h): a joint opens by about load / (m
// omega^2) for the effective mass m of its row and the joint spring's
// omega, which the substep rate bounds. A chain carrying a hundred times
// its links' mass opens by 9 mm at the default 2 substeps of a 240 Hz step
// and 2.2 mm at 4; it holds within 1 mm at 8.
WorldSettings stiff_settings() {
  WorldSettings settings = settings_without_sleep();
  settings.substeps = 8;
  return settings;
}

TEST(JointTest, AChainHoldsAWeightOfAHundredLinksWithoutOpening) {
  World world;
  world.set_settings(stiff_settings());
  const int links = 40;
  const double link_half = 0.05, link_mass = 0.1;
  const Vec3 top(0, 5, 0);
  std::vector<JointId> joints;
  BodyId previous = kWorldBodyId;
  for (int i = 0; i < links; ++i) {
    const Vec3 center = top - Vec3(0, (2 * i + 1) * link_half, 0);
    BodyDesc desc;
    desc.shape = capsule_shape(link_half * 0.6, link_half * 0.4);
    desc.mass_properties = capsule_mass_properties(link_mass, desc.shape.radius, desc.shape.half_height);
    desc.position = center;
    const BodyId link = world.add_body(desc);
    joints.push_back(world.add_joint(joint_at(world, JointType::ball, previous, link, center + Vec3(0, link_half, 0))));
    previous = link;
  }
  const Vec3 end = top - Vec3(0, 2 * links * link_half, 0);
  const BodyId weight = world.add_body(sphere_body(end - Vec3(0, 0.2, 0), 0.2, 100 * link_mass));
  joints.push_back(world.add_joint(joint_at(world, JointType::ball, previous, weight, end)));
  // A push to the side so that it swings as well as hangs.
  world.apply_impulse(weight, Vec3(2, 0, 1));
  // Over the tenth second, once the joints' impulses have built up from
  // zero (the first steps of the weight's fall reach the top of the chain
  // only after several steps of a pass a substep).
  double worst = 0;
  for (int i = 0; i < 10 * 240; ++i) {
    world.step(kTick);
    if (i < 9 * 240) continue;
    for (JointId id : joints) worst = std::max(worst, separation(world, id));
  }
  EXPECT_LT(worst, 1e-3);
}

// A plank hinged at one end about z, pulled down by gravity against a
// limit.
struct Flap {
  World world;
  BodyId plank = kInvalidBodyId;
  JointId hinge = kInvalidJointId;

  Flap(bool limits, double lower, double upper, const JointMotor& motor = {}) {
    world.set_settings(settings_without_sleep());
    BodyDesc desc = box_body(Vec3(1, 2, 0), 0.5, 4.0);
    desc.shape = box_shape(Vec3(1, 0.05, 0.3));
    desc.mass_properties = box_mass_properties(4.0, desc.shape.half_extents);
    plank = world.add_body(desc);
    JointDesc joint = joint_at(world, JointType::hinge, kWorldBodyId, plank, Vec3(0, 2, 0), Vec3::UnitZ());
    joint.limits_enabled = limits;
    joint.lower = lower;
    joint.upper = upper;
    joint.motor = motor;
    hinge = world.add_joint(joint);
  }
};

// A ragdoll of 11 boxes standing at `base` (feet on it), facing +z: ball
// joints with cones at the spine, neck, shoulders and hips, hinges with
// limits at the elbows and knees, each with 1 N m of friction. Returns its
// joints.
std::vector<JointId> add_ragdoll(World& world, const Vec3& base) {
  std::vector<JointId> joints;
  auto part = [&](const Vec3& center, const Vec3& half, double mass) {
    BodyDesc desc;
    desc.shape = box_shape(half);
    desc.mass_properties = box_mass_properties(mass, half);
    desc.position = base + center;
    return world.add_body(desc);
  };
  auto join = [&](JointType type, BodyId a, BodyId b, const Vec3& anchor, const Vec3& axis) {
    JointDesc desc = joint_at(world, type, a, b, base + anchor, axis);
    if (type == JointType::ball) desc.cone_limit = 0.8;
    desc.friction = 1.0;  // N m, the limbs' muscles
    if (type == JointType::hinge) {
      desc.limits_enabled = true;
      desc.lower = 0;
      desc.upper = 2.4;
    }
    joints.push_back(world.add_joint(desc));
  };
  const BodyId pelvis = part(Vec3(0, 1.0, 0), Vec3(0.15, 0.1, 0.1), 10);
  const BodyId torso = part(Vec3(0, 1.35, 0), Vec3(0.18, 0.22, 0.1), 20);
  const BodyId head = part(Vec3(0, 1.72, 0), Vec3(0.1, 0.1, 0.1), 5);
  join(JointType::ball, pelvis, torso, Vec3(0, 1.11, 0), Vec3::UnitY());
  join(JointType::ball, torso, head, Vec3(0, 1.6, 0), Vec3::UnitY());
  for (double side : {-1.0, 1.0}) {
    const BodyId upper_arm = part(Vec3(side * 0.35, 1.5, 0), Vec3(0.13, 0.04, 0.04), 2);
    const BodyId forearm = part(Vec3(side * 0.63, 1.5, 0), Vec3(0.13, 0.035, 0.035), 1.5);
    join(JointType::ball, torso, upper_arm, Vec3(side * 0.2, 1.5, 0), Vec3(side, 0, 0));
    join(JointType::hinge, upper_arm, forearm, Vec3(side * 0.49, 1.5, 0), Vec3::UnitY());
    const BodyId thigh = part(Vec3(side * 0.09, 0.7, 0), Vec3(0.06, 0.18, 0.06), 7);
    const BodyId shin = part(Vec3(side * 0.09, 0.27, 0), Vec3(0.05, 0.22, 0.05), 4);
    join(JointType::ball, pelvis, thigh, Vec3(side * 0.09, 0.89, 0), -Vec3::UnitY());
    join(JointType::hinge, thigh, shin, Vec3(side * 0.09, 0.505, 0), Vec3::UnitX());
  }
  return joints;
}

// Six ragdolls dropped across a pile of boxes and each other, lying down,
// turned about y by `turn` radians more each. Returns the farthest any joint
// opened (m) and the steps until every body slept (or `max_steps`).
struct RagdollDrop {
  double worst_separation = 0;
  int steps = 0;
  std::size_t awake = 0;
};

RagdollDrop drop_ragdolls(double turn_step, int max_steps) {
  World world;
  world.add_body(testing::ground_plane());
  for (int i = 0; i < 9; ++i) world.add_body(box_body(Vec3(0.6 * (i % 3) - 0.6, 0.25, 0.6 * (i / 3) - 0.6), 0.25));
  std::vector<JointId> joints;
  for (int i = 0; i < 6; ++i) {
    // Lying down, across the pile and each other, a little apart.
    const Vec3 base(0.2 * (i % 2), 0.7 + 0.45 * i, -0.9);
    const std::size_t first_body = world.body_count();
    const std::vector<JointId> ragdoll = add_ragdoll(world, base);
    joints.insert(joints.end(), ragdoll.begin(), ragdoll.end());
    // Turned onto its back about the x axis through its feet, by a quarter
    // turn, and about y by a varying angle.
    const Quat turn = Quat(Eigen::AngleAxisd(turn_step * i, Vec3::UnitY())) *
                      Quat(Eigen::AngleAxisd(-std::numbers::pi / 2, Vec3::UnitX()));
    for (std::size_t k = first_body; k < world.body_count(); ++k) {
      const BodyId id = world.body_id_at(k);
      world.set_state(id, base + turn * (world.position(id) - base), turn * world.orientation(id), Vec3::Zero(),
                      Vec3::Zero());
    }
  }
  RagdollDrop drop;
  for (; drop.steps < max_steps && world.sleeping_body_count() < world.body_count() - 1; ++drop.steps) {
    world.step(kTick);
    for (JointId id : joints) drop.worst_separation = std::max(drop.worst_separation, separation(world, id));
  }
  drop.awake = world.body_count() - 1 - world.sleeping_body_count();  // the plane never sleeps
  return drop;
}

// A heap of limbs is chaotic: which arm ends up hanging off the pile turns
// on the last bit of a rounding. So the drop is made six times, turned by
// a nanoradian more each time, and every one must hold. Without the
// joints' friction a hanging arm swings as a pendulum and most of these
// drops are still awake after 20 s (tried: 19 of 30). Without the joints'
// position correction (WorldSettings::joint_position_correction) an elbow
// struck by a falling torso opens by up to 1.25 cm.
TEST(JointTest, RagdollsDroppedOnAPileStayWholeAndFallAsleep) {
  for (int trial = 0; trial < 6; ++trial) {
    const RagdollDrop drop = drop_ragdolls(0.7 + 1e-9 * trial, 10 * 240);
    EXPECT_LT(drop.worst_separation, 0.01) << "trial " << trial;
    EXPECT_EQ(drop.awake, 0u) << "trial " << trial << ", after " << drop.steps << " steps";
  }
}

TEST(JointTest, AHingeLimitHoldsALoadedDoor) {
  Flap flap(true, -0.5, 0.5);
  // Gravity's torque about the hinge, m g 1 m, and a push of as much again.
  double lowest = 0;
  for (int i = 0; i < 5 * 240; ++i) {
    flap.world.add_force_at_point(flap.plank, Vec3(0, -40, 0), flap.world.position(flap.plank));
    flap.world.step(kTick);
    lowest = std::min(lowest, flap.world.joint_state(flap.hinge).position);
  }
  EXPECT_GT(lowest, -0.5 - 0.5 * std::numbers::pi / 180);
  EXPECT_NEAR(flap.world.joint_state(flap.hinge).position, -0.5, 0.5 * std::numbers::pi / 180);
}

TEST(JointTest, AHingeMotorHoldsItsSpeedUnderLoadWithinItsTorque) {
  JointMotor motor;
  motor.mode = JointMotor::Mode::speed;
  motor.target = 1.0;
  motor.max_force = 200;  // N m; gravity's torque peaks at m g 1 m = 39 N m
  Flap flap(false, 0, 0, motor);
  for (int i = 0; i < 2 * 240; ++i) {
    flap.world.step(kTick);
    const JointState state = flap.world.joint_state(flap.hinge);
    EXPECT_LE(std::abs(state.motor_impulse), motor.max_force * kTick * (1 + 1e-9));
    if (i >= 60) {
      EXPECT_NEAR(state.speed, 1.0, 0.02) << "step " << i;
    }
  }
}

TEST(JointTest, AHingeMotorTooWeakForItsLoadGivesItsMaximumTorque) {
  JointMotor motor;
  motor.mode = JointMotor::Mode::speed;
  motor.target = 1.0;
  motor.max_force = 10;  // N m, against gravity's 39 N m at the horizontal
  Flap flap(false, 0, 0, motor);
  flap.world.step(kTick);
  const JointState state = flap.world.joint_state(flap.hinge);
  EXPECT_NEAR(state.motor_impulse, motor.max_force * kTick, 1e-9);
  // Gravity wins: the plank falls.
  for (int i = 0; i < 120; ++i) flap.world.step(kTick);
  EXPECT_LT(flap.world.joint_state(flap.hinge).speed, 0);
}

TEST(JointTest, AHingePositionMotorTurnsToItsTarget) {
  JointMotor motor;
  motor.mode = JointMotor::Mode::position;
  motor.target = 0.7;
  motor.max_force = 500;
  motor.hertz = 4;
  motor.damping_ratio = 1;
  Flap flap(false, 0, 0, motor);
  for (int i = 0; i < 3 * 240; ++i) flap.world.step(kTick);
  // A spring against gravity settles a little below its target: m g L cos(a)
  // / k with k = I omega^2, I the plank's inertia about its centre, m (4 +
  // 0.01) / 12 (the hinge's point rows carry the rest).
  const double inertia = 4.0 * (4 + 0.01) / 12;
  const double stiffness = inertia * std::pow(2 * std::numbers::pi * motor.hertz, 2);
  const double sag = 4.0 * kGravity * 1.0 * std::cos(0.7) / stiffness;
  EXPECT_NEAR(flap.world.joint_state(flap.hinge).position, 0.7 - sag, 0.01);
}

// A 1 m cube of 6 kg (I = m (2a)^2 / 6 = 1 kg m^2 about any axis through
// its centre) joined to the world at its centre, its axis (hinge, slider)
// along z, in zero gravity, with `friction` on the joint.
struct FrictionRig {
  World world;
  BodyId cube = kInvalidBodyId;
  JointId joint = kInvalidJointId;

  FrictionRig(JointType type, double friction) {
    world.set_settings(settings_without_sleep());
    world.set_gravity(Vec3::Zero());
    cube = world.add_body(box_body(Vec3(0, 2, 0), 0.5, 6.0));
    JointDesc desc = joint_at(world, type, kWorldBodyId, cube, Vec3(0, 2, 0), Vec3::UnitZ());
    desc.friction = friction;
    joint = world.add_joint(desc);
  }

  // Pushes with `torque` (N m) and `force` (N) at the centre for `seconds`.
  void push(const Vec3& torque, const Vec3& force, double seconds) {
    for (int i = 0; i < static_cast<int>(std::lround(seconds / kTick)); ++i) {
      world.add_torque(cube, torque);
      world.add_force(cube, force);
      world.step(kTick);
    }
  }
};

// Coulomb friction on the free direction: a load below the friction leaves
// the joint still, a larger one accelerates it at (load - friction) / I.
TEST(JointTest, AHingesFrictionHoldsASmallerTorqueAndSlowsALargerOne) {
  FrictionRig held(JointType::hinge, 2.0);
  held.push(Vec3(0, 0, 1.5), Vec3::Zero(), 1.0);
  EXPECT_LT(std::abs(held.world.joint_state(held.joint).speed), 1e-9);
  EXPECT_LT(std::abs(held.world.joint_state(held.joint).position), 1e-9);

  FrictionRig turned(JointType::hinge, 2.0);
  turned.push(Vec3(0, 0, 3.0), Vec3::Zero(), 2.0);
  // alpha = (3 - 2) N m / 1 kg m^2: 2 rad/s after 2 s, 2 rad turned.
  EXPECT_NEAR(turned.world.joint_state(turned.joint).speed, 2.0, 0.01);
  EXPECT_NEAR(turned.world.joint_state(turned.joint).position, 2.0, 0.02);
}

TEST(JointTest, ABallJointsFrictionResistsTurningAboutAnyAxisAlike) {
  const Vec3 axis = Vec3(1, 2, 2) / 3;
  FrictionRig held(JointType::ball, 2.0);
  held.push(1.5 * axis, Vec3::Zero(), 1.0);
  EXPECT_LT(held.world.angular_velocity(held.cube).norm(), 1e-9);

  FrictionRig turned(JointType::ball, 2.0);
  turned.push(3.0 * axis, Vec3::Zero(), 2.0);
  // The friction torque opposes the motion whatever its axis: (3 - 2) N m.
  const Vec3 w = turned.world.angular_velocity(turned.cube);
  EXPECT_TRUE(w.isApprox(2.0 * axis, 0.005)) << w.transpose();
}

TEST(JointTest, ASlidersFrictionHoldsASmallerForceAndSlowsALargerOne) {
  FrictionRig held(JointType::slider, 4.0);
  held.push(Vec3::Zero(), Vec3(0, 0, 3), 1.0);
  EXPECT_LT(held.world.linear_velocity(held.cube).norm(), 1e-9);

  FrictionRig pushed(JointType::slider, 4.0);
  pushed.push(Vec3::Zero(), Vec3(0, 0, 10), 1.0);
  // a = (10 - 4) N / 6 kg: 1 m/s after 1 s.
  EXPECT_NEAR(pushed.world.joint_state(pushed.joint).speed, 1.0, 0.005);
  EXPECT_NEAR(pushed.world.linear_velocity(pushed.cube).z(), 1.0, 0.005);
}

TEST(JointTest, ASliderMovesAlongItsAxisOnlyAndStopsAtItsLimit) {
  World world;
  world.set_settings(settings_without_sleep());
  const BodyId cart = world.add_body(box_body(Vec3(0, 1, 0), 0.25, 2.0));
  JointDesc desc = joint_at(world, JointType::slider, kWorldBodyId, cart, Vec3(0, 1, 0), Vec3::UnitX());
  desc.limits_enabled = true;
  desc.lower = -1;
  desc.upper = 1;
  const JointId slider = world.add_joint(desc);
  for (int i = 0; i < 3 * 240; ++i) {
    // Pushed along the axis, across it and turned: only the push moves it.
    world.add_force(cart, Vec3(10, 5, 3));
    world.add_torque(cart, Vec3(1, 2, 3));
    world.step(kTick);
  }
  EXPECT_NEAR(world.joint_state(slider).position, 1.0, 1e-3);
  EXPECT_NEAR(world.position(cart).x(), 1.0, 1e-3);
  EXPECT_NEAR(world.position(cart).y(), 1.0, 1e-3);  // gravity and the push across held
  EXPECT_NEAR(world.position(cart).z(), 0.0, 1e-3);
  EXPECT_LT(world.orientation(cart).angularDistance(Quat::Identity()), 1e-3);
}

TEST(JointTest, AWeldHoldsALoadedArm) {
  World world;
  world.set_settings(stiff_settings());
  // A beam welded to the world at one end, a heavy box welded to its tip.
  BodyDesc beam_desc = box_body(Vec3(0.5, 2, 0), 0.5, 2.0);
  beam_desc.shape = box_shape(Vec3(0.5, 0.05, 0.05));
  beam_desc.mass_properties = box_mass_properties(2.0, beam_desc.shape.half_extents);
  const BodyId beam = world.add_body(beam_desc);
  const BodyId tip = world.add_body(box_body(Vec3(1.1, 2, 0), 0.1, 20.0));
  world.add_joint(joint_at(world, JointType::fixed, kWorldBodyId, beam, Vec3(0, 2, 0)));
  world.add_joint(joint_at(world, JointType::fixed, beam, tip, Vec3(1.0, 2, 0)));
  const Vec3 start = world.position(tip);
  for (int i = 0; i < 5 * 240; ++i) world.step(kTick);
  EXPECT_LT((world.position(tip) - start).norm(), 1e-3);
}

TEST(JointTest, AJointBreaksAtItsBreakForceAndIsReported) {
  World world;
  world.set_settings(settings_without_sleep());
  const BodyId ball = world.add_body(sphere_body(Vec3(0, 1, 0), 0.1, 1.0));
  JointDesc desc = joint_at(world, JointType::ball, kWorldBodyId, ball, Vec3(0, 1.5, 0));
  desc.break_force = 50;
  const JointId joint = world.add_joint(desc);
  // A pull growing by 10 N a second on top of its weight.
  double pull = 0;
  for (int i = 0; i < 10 * 240 && world.contains_joint(joint); ++i) {
    pull = 10.0 * i * kTick;
    world.add_force(ball, Vec3(0, -pull, 0));
    world.step(kTick);
    if (!world.broken_joints().empty()) {
      ASSERT_EQ(world.broken_joints().size(), 1u);
      EXPECT_EQ(world.broken_joints()[0], joint);
    }
  }
  ASSERT_FALSE(world.contains_joint(joint));
  EXPECT_TRUE(world.body_joints(ball).empty());
  EXPECT_NEAR(pull + kGravity, 50.0, 0.05 * 50.0);
}

TEST(JointTest, JointedBodiesDoNotCollideUnlessTheJointSaysSo) {
  for (bool collide : {false, true}) {
    World world;
    world.set_settings(settings_without_sleep());
    world.set_gravity(Vec3::Zero());
    const BodyId a = world.add_body(box_body(Vec3(0, 0, 0), 0.5));
    const BodyId b = world.add_body(box_body(Vec3(0.8, 0, 0), 0.5));  // overlapping by 0.2 m
    world.step(kTick);
    ASSERT_EQ(world.contact_count(), 1u);
    JointDesc desc = joint_at(world, JointType::ball, a, b, Vec3(0.4, 0, 0));
    desc.collide_connected = collide;
    const JointId joint = world.add_joint(desc);
    world.step(kTick);
    EXPECT_EQ(world.contact_count(), collide ? 1u : 0u);
    // Moved (which pairs it with whatever it overlaps), b still does not
    // meet a.
    world.set_state(b, world.position(b), world.orientation(b), Vec3::Zero(), Vec3::Zero());
    world.step(kTick);
    EXPECT_EQ(world.contact_count(), collide ? 1u : 0u);
    // Removed, the joint no longer keeps them apart.
    world.remove_joint(joint);
    world.step(kTick);
    EXPECT_EQ(world.contact_count(), 1u) << "collide_connected " << collide;
  }
}

TEST(JointTest, APendulumAtRestSleepsAndWakesWithItsJoint) {
  World world;
  const BodyId upper = world.add_body(sphere_body(Vec3(0, 1, 0), 0.1));
  const BodyId lower = world.add_body(sphere_body(Vec3(0, 0.5, 0), 0.1));
  world.add_joint(rod(world, kWorldBodyId, upper, Vec3(0, 1.5, 0), world.position(upper)));
  world.add_joint(rod(world, upper, lower, world.position(upper), world.position(lower)));
  for (int i = 0; i < 240 * 2 && world.is_awake(lower); ++i) world.step(kTick);
  EXPECT_FALSE(world.is_awake(upper));
  EXPECT_FALSE(world.is_awake(lower));
  // A push to the lower bob wakes the whole pendulum.
  world.apply_impulse(lower, Vec3(0.5, 0, 0));
  EXPECT_TRUE(world.is_awake(upper));
  world.step(kTick);
  EXPECT_GT(world.linear_velocity(upper).norm(), 0);
}

TEST(JointTest, RemovingABodyRemovesItsJoints) {
  World world;
  const BodyId a = world.add_body(sphere_body(Vec3(0, 1, 0), 0.1));
  const BodyId b = world.add_body(sphere_body(Vec3(0, 0.5, 0), 0.1));
  const JointId top = world.add_joint(rod(world, kWorldBodyId, a, Vec3(0, 1.5, 0), world.position(a)));
  const JointId middle = world.add_joint(rod(world, a, b, world.position(a), world.position(b)));
  EXPECT_EQ(world.body_joints(a).size(), 2u);
  world.remove_body(a);
  EXPECT_FALSE(world.contains_joint(top));
  EXPECT_FALSE(world.contains_joint(middle));
  EXPECT_EQ(world.joint_count(), 0u);
  EXPECT_TRUE(world.body_joints(b).empty());
  world.step(kTick);  // b falls freely
  EXPECT_LT(world.linear_velocity(b).y(), 0);
}

TEST(JointTest, DescsThatCannotMakeAJointAreRefusedNamingTheField) {
  World world;
  const BodyId a = world.add_body(sphere_body(Vec3(0, 1, 0), 0.1));
  JointDesc desc = joint_at(world, JointType::hinge, kWorldBodyId, a, Vec3(0, 1.5, 0));
  EXPECT_EQ(world.joint_desc_error(desc), nullptr);
  auto error_of = [&](auto change) {
    JointDesc d = desc;
    change(d);
    const char* error = world.joint_desc_error(d);
    return std::string(error == nullptr ? "" : error);
  };
  EXPECT_EQ(error_of([](JointDesc& d) { d.body_b = 77; }), "body_b: unknown body");
  EXPECT_EQ(error_of([&](JointDesc& d) { d.body_a = a; }), "body_b: the same body as body_a");
  EXPECT_EQ(error_of([](JointDesc& d) {
              d.limits_enabled = true;
              d.lower = 1;
              d.upper = -1;
            }),
            "limits: lower above upper");
  EXPECT_EQ(error_of([](JointDesc& d) { d.local_anchor_b.x() = std::nan(""); }), "anchor: not finite");
  EXPECT_EQ(error_of([](JointDesc& d) {
              d.type = JointType::fixed;
              d.motor.mode = JointMotor::Mode::speed;
            }),
            "motor: only a hinge or a slider has a motor");
  EXPECT_EQ(error_of([](JointDesc& d) { d.cone_limit = 0.5; }), "cone_limit: only a ball joint has a cone");
  EXPECT_EQ(error_of([](JointDesc& d) { d.break_force = -1; }), "break_force: not > 0");
  EXPECT_EQ(error_of([](JointDesc& d) { d.friction = std::nan(""); }), "friction: not a finite number >= 0");
  EXPECT_EQ(error_of([](JointDesc& d) {
              d.type = JointType::fixed;
              d.friction = 1;
            }),
            "friction: only a ball joint, a hinge or a slider has friction");
}

}  // namespace
}  // namespace tumble::physics
