// Joints: constraints that connect two bodies, or a body to the world.
//
// A joint holds a frame on each of its bodies: an anchor point and a basis
// whose x axis is the joint's axis (the hinge's or slider's axis, the ball
// joint's cone axis). Frames are given in body coordinates, relative to the
// centre of mass; a frame on the world is in world coordinates.
// World::set_joint_frames builds them from world anchors and a world axis at
// the bodies' current poses, as a scene file gives them.
//
// Types, and the relative motion each leaves free:
//   ball      anchors coincide; any rotation (optionally within a cone about
//             the axis: the angle between the two frames' x axes)
//   hinge     anchors coincide, x axes aligned; rotation about the axis
//             (angle 0 where the frames' y axes agree), optional limits and
//             motor
//   slider    no rotation, anchor B on the line through anchor A along the
//             axis; translation along it (position 0 where the anchors
//             coincide), optional limits and motor
//   fixed     none (the frames stay together)
//   distance  the anchors' distance between min_length and max_length; a
//             spring towards `length` when spring_hertz > 0; rigid at
//             `length` when min_length == max_length
//
// Joints are solved with the contacts in the same substeps (contact_solver
// in src/), soft like them (Catto, "Solver2D"; Box2D v3's joints), and
// bodies they connect share an island, sleep and wake together. Angles in
// radians, lengths in metres, forces in newtons, torques in N m.
#pragma once

#include <cstdint>
#include <limits>

#include "tumble/physics/body.h"
#include "tumble/physics/math.h"

namespace tumble::physics {

// Stable handle to a joint in a World, handed out in increasing order and
// never reused while the World lives (like BodyId).
using JointId = std::uint32_t;
inline constexpr JointId kInvalidJointId = 0xffffffff;
// JointDesc::body_a (or body_b) naming the world frame rather than a body.
inline constexpr BodyId kWorldBodyId = 0xfffffffe;

enum class JointType : std::uint8_t { ball, hinge, slider, fixed, distance };

// A hinge's or slider's motor. Speed mode drives the joint's speed (rad/s
// or m/s) to `target`; position mode drives its position (rad or m) to
// `target` through a spring of `hertz` with `damping_ratio` (a PD drive).
// Either way the motor's force stays within max_force (N m for a hinge, N
// for a slider). The position spring's stiffness is (2 pi hertz)^2 times the
// joint's effective mass along its axis (for a hinge, the bodies'
// inertias about their centres, as Box2D's), so a body hung on the hinge
// sags below the target by its load's torque over that stiffness.
struct JointMotor {
  enum class Mode : std::uint8_t { off, speed, position };
  Mode mode = Mode::off;
  double target = 0;
  double max_force = 0;
  double hertz = 2;
  double damping_ratio = 1;
};

// Everything a joint is created from; see the types above.
struct JointDesc {
  JointType type = JointType::ball;
  BodyId body_a = kWorldBodyId;
  BodyId body_b = kInvalidBodyId;
  Vec3 local_anchor_a = Vec3::Zero();
  Vec3 local_anchor_b = Vec3::Zero();
  Quat local_basis_a = Quat::Identity();  // frame A -> body A
  Quat local_basis_b = Quat::Identity();  // frame B -> body B
  // Hinge angle or slider position limits, lower <= upper.
  bool limits_enabled = false;
  double lower = 0;
  double upper = 0;
  // Ball joint: the largest angle between the frames' x axes, in (0, pi];
  // infinity for none.
  double cone_limit = std::numeric_limits<double>::infinity();
  // Distance joint: 0 <= min_length <= length <= max_length.
  double length = 0;
  double min_length = 0;
  double max_length = 0;
  double spring_hertz = 0;  // > 0: a spring towards length (min_length < max_length)
  double spring_damping_ratio = 0;
  JointMotor motor;  // hinge and slider only
  // Ball, hinge and slider: the largest torque (N m; ball, hinge) or force
  // (N; slider) with which the joint resists motion in its free directions,
  // as a worn hinge or a limb's muscles do; 0 for none. Below it the joint
  // holds still, above it the rest of the load turns or slides it.
  double friction = 0;
  // The joint breaks (is removed in the step, World::broken_joints) when
  // its constraint force or torque exceeds these.
  double break_force = std::numeric_limits<double>::infinity();
  double break_torque = std::numeric_limits<double>::infinity();
  bool collide_connected = false;  // whether the two bodies still collide
};

// What a joint does now, as of the last step.
struct JointState {
  // Hinge: angle (rad); slider: position (m); distance: length (m); ball:
  // the angle between the x axes (rad); fixed: 0.
  double position = 0;
  double speed = 0;            // its rate of change (rad/s or m/s)
  Vec3 force = Vec3::Zero();   // constraint force on body B (N), world frame
  Vec3 torque = Vec3::Zero();  // constraint torque on body B (N m), world frame
  // Impulse the motor applied over the last step (N m s or N s); at most
  // max_force times the step in magnitude.
  double motor_impulse = 0;
};

// The solver's accumulated impulses of a joint, which warm start the next
// step; saved and restored with a world so that it continues bit-exactly.
// Their meaning depends on the joint's type.
struct JointImpulses {
  Vec3 linear = Vec3::Zero();
  Vec3 angular = Vec3::Zero();
  double lower = 0;
  double upper = 0;
  double motor = 0;
  double spring = 0;
  Vec3 friction = Vec3::Zero();  // ball: angular; hinge, slider: x along the axis
};

}  // namespace tumble::physics
