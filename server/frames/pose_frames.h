// The PoseFrames a stream of a snapshot is published as, whatever carries
// them: FULL (floats), QUANTIZED (every body on the grids) and DELTA (a key
// frame of every body, or the change from the previous frame). net frames
// them for its sessions; the NATS publisher sends them as they are. Only
// the bodies (and the joints, fill_joints) are filled in: the caller sets
// the header (subscription id, tick, sim time, sequence).
//
// Thread: any; the functions keep no state.
#pragma once

#include <vector>

#include "sim/snapshot.h"
#include "tumble/physics/body.h"
#include "tumble/v1/protocol.pb.h"
#include "wire/quantized_poses.h"

namespace tumble::frames {

// FULL: the bodies of `snapshot` a stream reads (every one, or those in the
// sorted `filter`), as floats, with velocities or without.
void fill_full(const sim::Snapshot& snapshot, bool all_bodies, const std::vector<physics::BodyId>& filter,
               bool velocities, tumble::v1::PoseFrame* out);

// QUANTIZED: `bodies` (sorted by id) packed on the grids.
void fill_quantized(const std::vector<wire::QuantizedBody>& bodies, bool velocities, tumble::v1::PoseFrame* out);

// DELTA key frame: every body of `bodies` (sorted by id).
void fill_delta_key(const std::vector<wire::QuantizedBody>& bodies, bool velocities, tumble::v1::PoseFrame* out);

// The joints' states of `snapshot` (Subscribe.joints), whatever the
// encoding; nothing when it holds none.
void fill_joints(const sim::Snapshot& snapshot, tumble::v1::PoseFrame* out);

// DELTA change: the bodies of `after` whose record differs from (or is
// missing in) `before`, and the ids of `before` missing in `after`; both
// sorted by id. `changed` is scratch space reused between calls.
void fill_delta_change(const std::vector<wire::QuantizedBody>& before, const std::vector<wire::QuantizedBody>& after,
                       bool velocities, tumble::v1::PoseFrame* out, std::vector<wire::QuantizedBody>* changed);

}  // namespace tumble::frames
