// Joint rows: how the contact solver's substeps (contact_solver.h) solve a
// joint. A joint is solved in the task of the group that holds its bodies,
// on the same slots as the group's contacts and in the same stages, before
// the contacts of each stage as Box2D v3 does (solver.c): warm start, soft
// pass, the move, relax pass, and after the substeps its impulses are
// stored for the next step's warm start.
//
// Geometry. At the start of the step each side has its anchor r (relative to
// the centre of mass) and its joint frame F (three axes), in world
// coordinates; during the step they turn with the body's rotation so far,
// exp(dtheta), and the centres move by dp (solver_body.h). With
//   d = (x_b + dp_b + r_b) - (x_a + dp_a + r_a)   (anchor B minus anchor A)
// the types' rows are:
//   point (ball, hinge, fixed)  C = d, three rows solved as one block with
//       K = (1/M_a + 1/M_b) E - [r_a]x I_a^-1 [r_a]x - [r_b]x I_b^-1 [r_b]x
//       (Catto, "Modeling and Solving Constraints", GDC 2009, the
//       point-to-point constraint);
//   hinge alignment  C_1 = a_A.b_B, C_2 = a_A.c_B for the hinge axis a_A of
//       frame A and the other two axes b_B, c_B of frame B; angular
//       Jacobians j_i = b_B x a_A, c_B x a_A (dC_i/dt = j_i.(w_b - w_a));
//   rotation lock (fixed, slider)  C = 2 vec(q_B q_A^-1) for the frames'
//       orientations (the small-angle rotation from A's frame to B's),
//       Cdot = w_b - w_a, K = I_a^-1 + I_b^-1;
//   slider line  C_i = d.n_i for the axes n_1, n_2 of frame A across the
//       slide; n_i turns with A, so the Jacobian on A is -n_i and
//       -(r_a + d) x n_i, on B n_i and r_b x n_i;
//   distance  C = |d| - length along n = d / |d|;
//   axial rows  the hinge angle (atan2 of the frames' y axes about a_A) and
//       the slider position d.a_A: a lower and an upper limit (one-sided,
//       speculative while apart, soft while violated), a motor (speed: a
//       rigid row towards the target speed; position: a spring of the
//       motor's frequency and damping ratio towards the target), its
//       accumulated impulse within max_force h;
//   cone (ball)  C = cone_limit - phi for the angle phi between the two x
//       axes, about n = a_A x a_B / |a_A x a_B|, one-sided.
// Each row's impulse is lambda = -m s_m (Cdot + bias) - s_i lambda_acc as
// for the contacts; the position terms (bias) of the rigid rows are soft and
// only in the soft passes, with the joint spring (WorldSettings::joint_hertz,
// joint_damping_ratio); springs and motors act in every pass, as physical
// forces do.
//
// The geometry moves only when the bodies do, in the substep's move: it is
// measured at the start of the step and after each move, and every pass
// between two moves reads that measure.
//
// After the substeps, a ball, hinge or fixed joint's remaining gap is
// partly closed at the position level (correct_joint_position).
//
// Thread: a row is touched only by the task that solves its group.
#pragma once

#include <cstdint>

#include "solver_body.h"
#include "tumble/physics/joint.h"
#include "tumble/physics/math.h"
#include "wide_constraint.h"

namespace tumble::physics {

// A joint as the World keeps it: what it was made from, the solver's
// accumulated impulses and what the last step measured.
struct Joint {
  JointId id = kInvalidJointId;
  JointDesc desc;
  JointImpulses impulses;
  Vec3 force = Vec3::Zero();   // on body B over the last step (N)
  Vec3 torque = Vec3::Zero();  // on body B over the last step (N m)
  double motor_impulse = 0;    // over the last step (N m s or N s)
};

// The gap (m) between a joint's anchors that correct_joint_position leaves
// to the joint spring: smaller gaps are not worth a move.
inline constexpr double kJointSlop = 0.0005;

// The springs and the substep a group's joints are solved with.
struct JointStepSettings {
  Softness joint_soft;  // the rigid rows' position correction
  double h = 0;         // substep (s)
  double inverse_h = 0;
};

// The joint as the bodies have moved so far (joint_solver.h, "Geometry"):
// anchors and frames turned by each body's rotation, d = anchor B minus
// anchor A, and the angles its rows measure from the frames.
struct JointGeometry {
  Vec3 anchor_a = Vec3::Zero();
  Vec3 anchor_b = Vec3::Zero();
  Mat3 frame_a = Mat3::Identity();  // columns: the frame's x, y, z axes in the world
  Mat3 frame_b = Mat3::Identity();
  Vec3 d = Vec3::Zero();
  // A hinge's angle (rad); a ball joint's cone angle between the frames'
  // x axes (rad) and the axis it grows about, when cone_axis_valid (the
  // axes do not nearly agree).
  double angle = 0;
  Vec3 cone_axis = Vec3::Zero();
  bool cone_axis_valid = false;
  // 1 / (J M^-1 J^T) of the rows along the joint's free direction, which
  // share their Jacobian: a hinge's axis, a ball joint's cone axis, a
  // slider's axis, a distance joint's line.
  double axial_mass = 0;
  // The inverse of the 2x2 block K of a hinge's alignment rows or a
  // slider's line rows.
  Eigen::Matrix2d block_mass = Eigen::Matrix2d::Zero();
};

// One joint during a step, built at the start of its group's solve: its
// slots in the group, its bodies' step constants, its geometry at the
// start of the step and its impulses.
struct JointRow {
  JointType type = JointType::ball;
  std::uint32_t slot_a = 0;
  std::uint32_t slot_b = 0;
  double inverse_mass_a = 0;
  double inverse_mass_b = 0;
  Mat3 inverse_inertia_a = Mat3::Zero();
  Mat3 inverse_inertia_b = Mat3::Zero();
  Vec3 anchor_a = Vec3::Zero();  // r_a at the start of the step, world frame
  Vec3 anchor_b = Vec3::Zero();
  Quat frame_a = Quat::Identity();  // frame A -> world at the start of the step
  Quat frame_b = Quat::Identity();
  Vec3 delta_center = Vec3::Zero();  // x_b - x_a at the start of the step
  // The point block's K^-1 (ball, hinge, fixed) and the rotation lock's
  // (I_a^-1 + I_b^-1)^-1 (fixed, slider, and a ball joint with friction),
  // from the step's start: the arms turn little within a step, and the
  // error is measured afresh each pass.
  Mat3 point_mass = Mat3::Zero();
  Mat3 lock_mass = Mat3::Zero();
  bool frames = true;    // whether a pass needs the frames (not a ball joint without a cone, nor a distance joint)
  Softness motor_soft;   // a position motor's spring
  Softness spring_soft;  // a distance joint's spring
  JointImpulses impulses;
  double motor_sum = 0;    // the motor's impulse over the substeps so far
  JointGeometry geometry;  // as of the last move
};

// Builds row from joint, whose bodies are at dense indices body_a, body_b
// (kNoJointBody for the world) and read slots slot_a, slot_b of the group.
void prepare_joint_row(const Joint& joint, std::uint32_t body_a, std::uint32_t body_b, std::uint32_t slot_a,
                       std::uint32_t slot_b, const ContactSolverBodies& bodies, const JointStepSettings& settings,
                       JointRow& row);
// Measures row.geometry from the slots' motion so far, with turns[s] the
// rotation of slot s so far (exp of its rotation vector; identity for the
// slot of zeros): after prepare_joint_row and after each move of the bodies.
void measure_joint(JointRow& row, const SolverBody* slots, const Quat* turns);
// Applies the accumulated impulses again (a substep's warm start).
void warm_start_joint(const JointRow& row, SolverBody* slots);
// One pass over the joint's rows: soft (with the position terms) or relax.
void solve_joint(JointRow& row, const Joint& joint, SolverBody* slots, const JointStepSettings& settings, bool soft);
// At the end of a substep: adds the motor's impulse of the substep.
inline void end_joint_substep(JointRow& row) { row.motor_sum += row.impulses.motor; }
// After the substeps: moves the bodies of a ball, hinge or fixed joint
// (their slots' motion, and turns with it) by `fraction` of the gap d
// between its anchors, if the gap is over kJointSlop: the position impulse
// p = -fraction K^-1 d, with K of the point block for the arms as they
// have turned (Catto's point-to-point K; Box2D v2's and Jolt's position
// passes). Velocities are not touched.
void correct_joint_position(JointRow& row, SolverBody* slots, Quat* turns, double fraction);
// After the substeps: stores the impulses in the joint for the next step's
// warm start, and its force, torque and motor impulse over the step.
void store_joint(const JointRow& row, const JointStepSettings& settings, Joint& joint);

}  // namespace tumble::physics
