// WorldSettings: tuning of a World's collision pipeline and contact solver
// (World::set_settings). Lengths in metres, speeds in m/s, times in seconds.
#pragma once

namespace tumble::physics {

// The default number of substeps (WorldSettings::substeps): at least
// kSubstepRate a second and at least kMinSubsteps a step.
inline constexpr double kSubstepRate = 240;  // Hz
inline constexpr int kMinSubsteps = 2;

// Tuning of the collision pipeline and the solver. The defaults suit bodies
// of about 0.1 m to 10 m at 60 to 240 steps per second.
struct WorldSettings {
  // The contact solver (contact_solver.h) splits each step into substeps;
  // each substep makes `velocity_iterations` soft passes over the contact
  // rows and `relax_iterations` rigid ones. substeps = 0 (the default) takes
  // enough that a substep is at most 1/kSubstepRate s, and at least
  // kMinSubsteps (at most 64): 4 at 60 steps per second (Box2D v3's default), 2 at 120
  // and at 240. A faster step rate then costs little more solver work a
  // second while the narrowphase runs more often. Measured on a 210-box
  // pyramid over 10 s (largest displacement) and the top of a ten-box
  // column over 30 s (drift): 60 Hz x 4, 33 mm and 3.4 mm; 240 Hz x 2,
  // 8.2 mm and 0.7 mm; 240 Hz x 1, 31 mm and 3.8 mm; 240 Hz x 4, 2.1 mm and
  // under 0.1 mm at twice the solver work of x 2. Any other value: exactly
  // that many.
  int substeps = 0;
  int velocity_iterations = 1;
  int relax_iterations = 1;
  // Frequency of the spring that pushes overlapping bodies apart (Hz); 0
  // means an eighth of the substep rate (Box2D's 30 Hz at 60 steps of 4
  // substeps; 60 Hz at 240 steps of 2), which keeps the push equally stiff
  // relative to the substep whatever the rates. The solver caps it at a
  // quarter of the substep rate.
  double contact_hertz = 0;
  double contact_damping_ratio = 10;  // of that push
  // Frequency (Hz) and damping ratio of the spring that pulls a joint's
  // bodies back together when it has opened (joint.h); 0 means twice
  // contact_hertz (Box2D v3's choice), capped at 3/16 of the substep rate
  // (stiffer, chains folding onto themselves gain energy).
  double joint_hertz = 0;
  double joint_damping_ratio = 2;
  // After the substeps, each ball, hinge and fixed joint whose anchors are
  // more than half a millimetre apart has its bodies moved (not their
  // velocities) by this fraction of the gap, in one pass over the joints:
  // Baumgarte's factor of the position passes of Box2D v2 and Jolt. It
  // keeps a joint struck by a heavy body from opening while the spring
  // above closes it. 0 leaves the gap to the spring alone; above about
  // half, a chain with a heavy weight can overshoot and gain energy.
  double joint_position_correction = 0.2;
  // Torsional friction (m): a contact of a single point (a sphere's, a
  // capsule's end) resists spinning about its normal with a torque of at
  // most friction * spin_friction * its normal force, as the small patch a
  // real contact presses flat would (the default of MuJoCo's torsional
  // coefficient). Contacts of two or more points resist the spin
  // through their points' friction already. 0 lets a ball spin in place
  // for ever.
  double spin_friction = 0.005;
  double max_push_speed = 3;           // m/s: the push never separates faster
  double restitution_threshold = 1.0;  // m/s: slower impacts do not bounce
  // Every pair gets contact points up to this separation (m), plus the
  // distance the two bodies can close within the step (speculative contacts).
  double contact_margin = 0.02;
  double aabb_margin = 0.1;  // m: fat boxes in the broadphase tree
  bool sleep_enabled = true;
  // A body is still while it stays within sleep_speed * time_to_sleep / 2
  // of where it was time_to_sleep to twice that ago (its centre, and its
  // bounding sphere as it turns) and its speed is not rising steadily (a
  // body tipping over an edge); a group of bodies joined by joints and by
  // contacts that touch or can touch within the step sleeps when all its
  // bodies have been still for time_to_sleep and |v| and |w| times the
  // bounding radius are below sleep_speed for each. Only groups that touch
  // something sleep: a free body keeps drifting however slowly it moves.
  // While some bodies of a group still settle below sleep_speed, those
  // ready that rest on the ground or on sleeping bodies sleep already.
  double sleep_speed = 0.05;   // m/s
  double time_to_sleep = 0.5;  // s
  // The divergence guard (World::diverged_bodies): after each step, a
  // moving body with a position (m), velocity (m/s or rad/s) or momentum
  // component beyond this magnitude, or any that is not finite, is
  // reported. A body that far out has left any scene the solver is tuned
  // for and would overflow within a few steps. Infinity reports only
  // values that are not finite.
  double max_state_magnitude = 1e9;
};

}  // namespace tumble::physics
