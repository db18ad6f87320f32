// An immutable copy of the world's poses after one step (or, while paused,
// after an edit), shared by the publisher and every subscription that reads
// it. It holds every body, or only those the streams due at its tick asked
// for (sim/publish_interest.h): covers() tells whether a stream can be
// served from it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "tumble/physics/body.h"
#include "tumble/physics/joint.h"

namespace tumble::sim {

// Body i of the snapshot is ids[i]; its values are at 3i (vectors) and 4i
// (orientations: w, x, y, z). All in the world frame, SI units.
struct Snapshot {
  std::uint64_t tick = 0;
  double sim_time = 0;  // s
  std::vector<physics::BodyId> ids;
  std::vector<double> positions;           // m, centre of mass
  std::vector<double> orientations;        // unit quaternions, w x y z
  std::vector<double> linear_velocities;   // m/s
  std::vector<double> angular_velocities;  // rad/s
  // When a stream asked for joints (PublishInterest::joints): every joint,
  // in ascending id order, with its position (rad or m), speed (rad/s or
  // m/s) and motor impulse over the step (N m s or N s) at i.
  bool has_joints = false;
  std::vector<physics::JointId> joint_ids;
  std::vector<double> joint_positions;
  std::vector<double> joint_speeds;
  std::vector<double> joint_motor_impulses;
  // The world was edited while paused (spawn, remove, set, impulse, reset):
  // every subscription gets this frame although its tick is not new.
  bool out_of_band = false;
  // Every body of the world, in the world's order. Otherwise the bodies of
  // `wanted` (sorted) that were in the world, in ascending id order.
  bool all_bodies = true;
  std::vector<physics::BodyId> wanted;
  // A larger snapshot of the same tick is handed over next: the small
  // streams' frames are made from this one without waiting for the copy of
  // the large one, and the streams it does not cover wait for that.
  bool more_follows = false;

  std::size_t body_count() const { return ids.size(); }

  // Whether the frame of a stream of every body (all) or of the sorted
  // `bodies`, with the joints or without, can be made from this snapshot: a
  // body asked for and missing from it is then one that has left the world.
  bool covers(bool all, const std::vector<physics::BodyId>& bodies, bool joints = false) const {
    if (joints && !has_joints) return false;
    if (all_bodies) return true;
    return !all && std::includes(wanted.begin(), wanted.end(), bodies.begin(), bodies.end());
  }
};

}  // namespace tumble::sim
