// The state one pose stream shows, whatever its encoding: FULL frames as
// they are, QUANTIZED frames decoded, DELTA frames applied to the bodies of
// the last key frame. Frames must come in the order SequenceGate lets them
// through; each decode() returns the whole state as a FULL-shaped frame
// (ids, positions, orientations and velocities as flat arrays, and the
// joint states the frame carries as they are), which is what PoseBuffer,
// JointStates and the selection panel read.
import { decodePackedPoses } from "./quantized_poses.js";

// PoseEncoding numbers (proto/tumble/v1/protocol.proto).
const kFull = 0;
const kDelta = 2;

export class PoseStream {
  constructor() {
    this.bodies = new Map();  // a DELTA stream's bodies: id -> {p[3], q[4], v[3] | null, w[3] | null}
    this.sortedIds = null;    // their ids in ascending order; null when the set changed
    this.velocities = false;  // the DELTA stream carries velocities
    this.hasKeyFrame = false; // a DELTA key frame was applied since clear()
  }

  // Forgets the state (a new session).
  clear() {
    this.bodies.clear();
    this.sortedIds = null;
    this.hasKeyFrame = false;
  }

  // The whole state `frame` shows, {tick, simTime, sequence, ids, positions,
  // orientations, linearVelocities, angularVelocities, jointIds,
  // jointPositions, jointSpeeds, jointMotorImpulses}: every frame of a
  // stream with joints carries every joint, a DELTA change's too. Throws on malformed
  // packed bytes (PackedPosesError) and on a DELTA change with no key frame
  // before it, which SequenceGate never lets through.
  decode(frame) {
    const base = {
      tick: Number(frame.tick), simTime: frame.simTime, sequence: Number(frame.sequence),
      jointIds: frame.jointIds ?? [], jointPositions: frame.jointPositions ?? [],
      jointSpeeds: frame.jointSpeeds ?? [], jointMotorImpulses: frame.jointMotorImpulses ?? [],
    };
    if (frame.encoding === kFull || frame.encoding === undefined) {
      return {
        ...base,
        ids: frame.ids,
        positions: frame.positions,
        orientations: frame.orientations,
        linearVelocities: frame.linearVelocities ?? [],
        angularVelocities: frame.angularVelocities ?? [],
      };
    }
    const poses = decodePackedPoses(frame.packed);
    if (frame.encoding !== kDelta) return { ...base, ...poses };
    if (frame.keyFrame) {
      this.clear();
    } else if (!this.hasKeyFrame) {
      throw new Error(`a DELTA change (sequence ${base.sequence}) before any key frame`);
    }
    this.hasKeyFrame = true;
    this.velocities = poses.velocities;
    for (const id of frame.removedIds ?? []) {
      if (this.bodies.delete(id)) this.sortedIds = null;
    }
    poses.ids.forEach((id, i) => {
      if (!this.bodies.has(id)) this.sortedIds = null;
      this.bodies.set(id, {
        p: poses.positions.subarray(3 * i, 3 * i + 3),
        q: poses.orientations.subarray(4 * i, 4 * i + 4),
        v: poses.velocities ? poses.linearVelocities.subarray(3 * i, 3 * i + 3) : null,
        w: poses.velocities ? poses.angularVelocities.subarray(3 * i, 3 * i + 3) : null,
      });
    });
    return { ...base, ...this.state() };
  }

  // The DELTA stream's bodies as flat arrays in id order.
  state() {
    if (!this.sortedIds) this.sortedIds = [...this.bodies.keys()].sort((a, b) => a - b);
    const n = this.sortedIds.length;
    const out = {
      ids: this.sortedIds,
      positions: new Float64Array(3 * n),
      orientations: new Float64Array(4 * n),
      linearVelocities: new Float64Array(this.velocities ? 3 * n : 0),
      angularVelocities: new Float64Array(this.velocities ? 3 * n : 0),
    };
    this.sortedIds.forEach((id, i) => {
      const body = this.bodies.get(id);
      out.positions.set(body.p, 3 * i);
      out.orientations.set(body.q, 4 * i);
      if (this.velocities && body.v) {
        out.linearVelocities.set(body.v, 3 * i);
        out.angularVelocities.set(body.w, 3 * i);
      }
    });
    return out;
  }
}
