// The joints' states the selection panel shows. A pose stream subscribed
// with `joints` carries every joint's position, speed and motor impulse in
// each frame (PoseFrame.joint_ids, joint_positions, joint_speeds,
// joint_motor_impulses; docs/protocol.md); a joint listing (JointList)
// carries each joint's whole JointState, its force and torque too, as of
// the listing's tick. Each value is kept from the newest of the two that
// has it: the frames keep position, speed and motor impulse current, and
// force and torque are the newest listing's.

// The joint states `frame` carries, [{id, position, speed, motorImpulse}]
// in its order: a PoseFrame as protobufjs decodes it, or the state
// PoseStream.decode() makes of one. Empty when the frame carries none (a
// subscription without `joints`, or a world without joints). Throws when
// the arrays' lengths disagree.
export function frameJointStates(frame) {
  const ids = frame.jointIds ?? [];
  const positions = frame.jointPositions ?? [];
  const speeds = frame.jointSpeeds ?? [];
  const impulses = frame.jointMotorImpulses ?? [];
  if (positions.length !== ids.length || speeds.length !== ids.length || impulses.length !== ids.length) {
    throw new Error(`a pose frame's joint states disagree in length: ${ids.length} ids, ${positions.length} ` +
                    `positions, ${speeds.length} speeds, ${impulses.length} motor impulses`);
  }
  return Array.from(ids, (id, i) => ({ id, position: positions[i], speed: speeds[i], motorImpulse: impulses[i] }));
}

export class JointStates {
  constructor() {
    // id -> {tick, position, speed, motorImpulse, force, torque, forceTick}:
    // `tick` that of position, speed and motor impulse; force and torque
    // (Vec3 {x, y, z}, or null) of the listing of `forceTick` (null: none).
    this.known = new Map();
  }

  // Forgets every state (a new session, or a reset's new joint ids).
  clear() {
    this.known.clear();
  }

  // Forgets the joints `ids` (anything with has(id)) does not hold.
  retain(ids) {
    for (const id of [...this.known.keys()]) if (!ids.has(id)) this.known.delete(id);
  }

  // Takes the joint states of pose frame `frame` (see frameJointStates);
  // returns how many it carried.
  noteFrame(frame) {
    const states = frameJointStates(frame);
    const tick = Number(frame.tick);
    for (const state of states) {
      const known = this.entry(state.id);
      if (known.tick !== null && known.tick > tick) continue;
      known.tick = tick;
      known.position = state.position;
      known.speed = state.speed;
      known.motorImpulse = state.motorImpulse;
    }
    return states.length;
  }

  // Takes the JointStates of listed `joints` (JointInfo[]) as of `tick`.
  noteListing(joints, tick) {
    for (const info of joints) {
      const state = info.state;
      if (!state) continue;
      const known = this.entry(info.id);
      if (known.tick === null || known.tick <= tick) {
        known.tick = tick;
        known.position = state.position ?? 0;
        known.speed = state.speed ?? 0;
        known.motorImpulse = state.motorImpulse ?? 0;
      }
      if (known.forceTick === null || known.forceTick <= tick) {
        known.forceTick = tick;
        known.force = state.force ?? null;
        known.torque = state.torque ?? null;
      }
    }
  }

  // Joint `id`'s state, {tick, position, speed, motorImpulse, force,
  // torque, forceTick}, or null when nothing is known of it.
  get(id) {
    const known = this.known.get(id);
    return known && known.tick !== null ? { ...known } : null;
  }

  entry(id) {
    let known = this.known.get(id);
    if (!known) {
      known = { tick: null, position: 0, speed: 0, motorImpulse: 0, force: null, torque: null, forceTick: null };
      this.known.set(id, known);
    }
    return known;
  }
}
