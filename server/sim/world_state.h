// WorldState: the whole of a running world as one protobuf message
// (proto/tumble/v1/state.proto), and back. What tumbled --state saves and
// resumes from, and what a journal starts from when a run was resumed.
//
// The round trip is exact: positions, orientations and momenta are saved as
// the doubles they are and put back without arithmetic, bodies keep their
// ids and their internal order (which the step's sums depend on), loads
// keep theirs, and joints keep their ids, order, frames (in body
// coordinates, as made) and the solver's warm-start impulses
// (physics::JointImpulses). Only the contact cache is not saved: the first step after a
// restore recomputes contacts and starts their impulses from zero, so a
// resting stack may settle by a few micrometres.
//
// Thread: the sim thread, which owns the world, directory and loads.
#pragma once

#include <cstddef>

#include "sim/body_directory.h"
#include "sim/body_loads.h"
#include "sim/joint_directory.h"
#include "sim/status.h"
#include "tumble/physics/world.h"
#include "tumble/v1/state.pb.h"

namespace tumble::sim {

inline constexpr std::uint32_t kWorldStateFormat = 1;

// The most body ids a world hands out over its life, spawns included. The
// world indexes its bodies by id (4 bytes an id), so a state whose
// next_body_id is near 2^32, as only a damaged file has, would have the
// restore allocate 16 GiB; restore_world refuses one beyond this, and
// SpawnBody refuses to hand out more, so that every saved world restores.
inline constexpr std::uint32_t kMaxBodyIds = std::uint32_t{1} << 26;
// Likewise the most joint ids a world hands out (AddJoint, restore_world).
inline constexpr std::uint32_t kMaxJointIds = std::uint32_t{1} << 26;

// Fills state->bodies, next_body_id, joints, next_joint_id, gravity and
// loads from the world (the clock fields and the scene are the caller's).
// A body whose state restore_world would refuse (not finite, or beyond
// kMaxMagnitude: the sim removes such a body after the step that made it,
// so this never happens unless that guard fails) is left out with its
// loads and joints, so that a saved world always restores; returns how
// many bodies were left out.
std::size_t capture_world(const physics::World& world, const BodyDirectory& directory, const JointDirectory& joints,
                          const BodyLoads& loads, tumble::v1::WorldState* state);

// The description of one body as it is now: what a scene file would say to
// create it here, moving as it moves; written into `spec` (which may live
// on an arena).
void body_spec_now(const physics::World& world, const BodyDirectory& directory, physics::BodyId id,
                   tumble::v1::BodySpec* spec);

// Rebuilds world, directories and loads (which must be empty) from a saved
// state, checking it as strictly as a scene file: every body spec, finite
// momenta, unique ids and names below next_body_id, loads on known bodies,
// joints the world accepts (World::joint_desc_error) on known bodies with
// unique ids and names below next_joint_id, and finite impulses.
// The one exception is a name string_limits.h refuses (too long, or digits
// only), which a file written by an older server may hold: the body is
// restored without it and a warning logged. On error the outputs are left
// partly filled and must be discarded.
Status restore_world(const tumble::v1::WorldState& state, physics::World* world, BodyDirectory* directory,
                     JointDirectory* joints, BodyLoads* loads);

// The scene a saved state keeps for Reset, with the names string_limits.h
// refuses cleared (and a warning logged for each), as restore_world does.
tumble::v1::Scene restorable_scene(const tumble::v1::Scene& scene);

}  // namespace tumble::sim
