// StepStats: counters of a World's last step (World::last_step_stats), for
// diagnostics and tests.
#pragma once

#include <cstddef>

namespace tumble::physics {

// Counters of the last step, for diagnostics and tests.
struct StepStats {
  std::size_t integrated_bodies = 0;   // awake dynamic and moving kinematic bodies advanced
  std::size_t moved_proxies = 0;       // fat boxes replaced in the broadphase
  std::size_t pairs = 0;               // contacts alive after it: pairs whose fat boxes overlap
  std::size_t narrowphase_pairs = 0;   // contacts whose manifold was updated (computed or reused)
  std::size_t manifolds_computed = 0;  // of those, recomputed from the shapes
  std::size_t solved_contacts = 0;     // manifolds with points given to the solver
  std::size_t solved_points = 0;       // their points
  std::size_t solved_joints = 0;       // joints with an awake dynamic body, solved with the contacts
  std::size_t islands = 0;             // groups of those that share no dynamic body, solved apart
  // The solver kept the last step's islands and plan (its colouring and
  // packing): the constraints were the same as then (a resting heap).
  bool plan_kept = false;
};

}  // namespace tumble::physics
