// The selection panel's joint states (web/src/joint_states.js): decoded
// from the bytes of pose frames with joints, as a session and a NATS pose
// stream hand them on, and kept against the listings' states by tick; and
// the panel's rows for the selected joint showing the frame's values.
//
//   node joint_states_test.mjs
//
// Exits 77 (ctest's skip) when web/node_modules (protobufjs) is missing.
import assert from "node:assert/strict";
import { test } from "node:test";

import { missingNodeModules } from "./browser.mjs";

const missing = missingNodeModules();
if (missing) {
  console.log(`SKIP: the viewer's joint state test needs ${missing}`);
  process.exit(77);
}
// After the check: these import protobufjs and three.js from web/node_modules.
const { encodeFrame } = await import("../../web/src/framing.js");
const { JointStates, frameJointStates } = await import("../../web/src/joint_states.js");
const { jointRows } = await import("../../web/src/inspector.js");
const { PoseStream } = await import("../../web/src/pose_stream.js");
const { Session } = await import("../../web/src/protocol.js");
const { protocolTypes } = await import("../../web/src/schema.js");
const { loadProtocolRoot } = await import("../../web/proto-schema.mjs");
const types = protocolTypes(loadProtocolRoot());
const { PoseEncoding } = types;

// Three joints whose values all differ, so a value read from the wrong
// array or at the wrong index shows; the wire carries them as float32.
const kJoints = [
  { id: 2, position: 0.3, speed: -1.7, motorImpulse: 0 },
  { id: 5, position: 1.1, speed: 4.2, motorImpulse: 0.05 },
  { id: 9, position: -0.6, speed: 0.25, motorImpulse: -2.5 },
];
const f32 = Math.fround;

// A PoseFrame's fields with `joints` at `tick` (FULL, one body).
const frameFields = (tick, joints = kJoints, extra = {}) => ({
  subscriptionId: 1, tick, simTime: tick / 240, encoding: PoseEncoding.POSE_ENCODING_FULL,
  ids: [1], positions: [0, 1, 0], orientations: [1, 0, 0, 0],
  jointIds: joints.map((j) => j.id), jointPositions: joints.map((j) => j.position),
  jointSpeeds: joints.map((j) => j.speed), jointMotorImpulses: joints.map((j) => j.motorImpulse),
  ...extra,
});

// The bytes the server sends for a ServerMessage with `fields`.
const serverBytes = (fields) =>
  encodeFrame(types.ServerMessage.encode(types.ServerMessage.fromObject(fields)).finish());

// The PoseFrames a Session decodes from `bytes`, fed `chunk` bytes at a time.
function sessionFrames(bytes, chunk) {
  const session = new Session(types, () => {});
  const frames = [];
  session.onPoseFrame = (frame) => frames.push(frame);
  session.onError = (error) => { throw error; };
  for (let i = 0; i < bytes.length; i += chunk) session.receive(bytes.subarray(i, i + chunk));
  return frames;
}

// The PoseFrame a session decodes from the bytes of one with `joints` at `tick`.
const wireFrame = (tick, joints = kJoints) => sessionFrames(serverBytes({ poseFrame: frameFields(tick, joints) }), 64)[0];

// Asserts a JointStates entry holds `expected`'s values as float32 at `tick`.
function assertState(actual, expected, tick) {
  assert.ok(actual, `no state of joint ${expected.id}`);
  assert.deepEqual({ tick: actual.tick, position: actual.position, speed: actual.speed, motorImpulse: actual.motorImpulse },
                   { tick, position: f32(expected.position), speed: f32(expected.speed),
                     motorImpulse: f32(expected.motorImpulse) }, `joint ${expected.id}`);
}

// A JointInfo as a listing gives it, with its JointState.
const listed = (id, type, state) => ({
  id, name: `j${id}`, type, bodyA: 1, bodyAName: "a", bodyB: 3, bodyBName: "b",
  state: { id, ...state },
});

test("each joint's state comes from the frame's bytes, as the session decodes them", () => {
  const bytes = Uint8Array.from([
    ...serverBytes({ poseFrame: frameFields(100) }),
    ...serverBytes({ poseFrame: frameFields(104, kJoints.map((j) => ({ ...j, position: j.position + 0.01 }))) }),
  ]);
  for (const chunk of [1, 7, bytes.length]) {
    const frames = sessionFrames(bytes, chunk);
    assert.equal(frames.length, 2);
    const states = new JointStates();
    assert.equal(states.noteFrame(frames[0]), 3);
    for (const joint of kJoints) assertState(states.get(joint.id), joint, 100);
    states.noteFrame(frames[1]);
    for (const joint of kJoints) assertState(states.get(joint.id), { ...joint, position: joint.position + 0.01 }, 104);
    assert.equal(states.get(3), null, "a joint no frame carried");
  }
});

test("a frame without joints leaves the states as they are, and a malformed one is refused", () => {
  const states = new JointStates();
  states.noteFrame(wireFrame(10));
  const bare = wireFrame(14, []);
  assert.deepEqual(frameJointStates(bare), []);
  assert.equal(states.noteFrame(bare), 0);
  assertState(states.get(5), kJoints[1], 10);
  assert.throws(() => states.noteFrame({ tick: 18, jointIds: [2, 5], jointPositions: [0.1], jointSpeeds: [0, 0],
                                         jointMotorImpulses: [0, 0] }), /disagree in length/);
});

test("a NATS stream's frames hand the joints on in every encoding", () => {
  // An empty body list in packed bytes: count 0, no flags, step 2^-10 m.
  const empty = Uint8Array.of(0, 0, 10);
  const stream = new PoseStream();
  const cases = [
    frameFields(40),
    frameFields(44, kJoints, { encoding: PoseEncoding.POSE_ENCODING_QUANTIZED, ids: [], positions: [], orientations: [], packed: empty }),
    frameFields(48, kJoints, { encoding: PoseEncoding.POSE_ENCODING_DELTA, ids: [], positions: [], orientations: [],
                               packed: empty, keyFrame: true }),
    // A DELTA change with no body changed still carries every joint.
    frameFields(52, kJoints, { encoding: PoseEncoding.POSE_ENCODING_DELTA, ids: [], positions: [], orientations: [],
                               packed: empty }),
  ];
  for (const fields of cases) {
    const decoded = types.ServerMessage.decode(types.ServerMessage.encode(types.ServerMessage.fromObject({ poseFrame: fields })).finish());
    const states = new JointStates();
    states.noteFrame(stream.decode(decoded.poseFrame));
    for (const joint of kJoints) assertState(states.get(joint.id), joint, fields.tick);
  }
});

test("frames and listings: the newer state is kept, force and torque the newest listing's", () => {
  const states = new JointStates();
  const force = { x: 0, y: 9.81, z: 0 };
  const torque = { x: 0.5, y: 0, z: 0 };
  // A listing of tick 100, then frames after it: the frames' values.
  states.noteListing([listed(5, 2, { position: 0.9, speed: 3, force, torque, motorImpulse: 0.01 })], 100);
  assert.deepEqual(states.get(5), { tick: 100, position: 0.9, speed: 3, motorImpulse: 0.01, force, torque, forceTick: 100 });
  states.noteFrame(wireFrame(104));
  const afterFrame = states.get(5);
  assertState(afterFrame, kJoints[1], 104);
  assert.deepEqual([afterFrame.force, afterFrame.torque, afterFrame.forceTick], [force, torque, 100]);

  // An older listing (it was asked for before that frame) changes nothing
  // the frame gave, nor the newer force.
  states.noteListing([listed(5, 2, { position: -3, speed: -3, force: { x: 1, y: 1, z: 1 }, motorImpulse: 7 })], 96);
  assert.deepEqual(states.get(5), afterFrame);
  // A newer listing gives everything; a frame older than it, nothing.
  states.noteListing([listed(5, 2, { position: 1.5, speed: 2, force: { x: 1, y: 2, z: 3 }, torque, motorImpulse: 0 })], 108);
  states.noteFrame(wireFrame(106));
  assert.deepEqual(states.get(5), { tick: 108, position: 1.5, speed: 2, motorImpulse: 0, force: { x: 1, y: 2, z: 3 },
                                    torque, forceTick: 108 });
  // Joints no longer listed are forgotten; a new session forgets all.
  states.noteFrame(wireFrame(112));
  states.retain(new Set([5, 9]));
  assert.equal(states.get(2), null);
  assertState(states.get(9), kJoints[2], 112);
  states.clear();
  assert.equal(states.get(5), null);
});

test("the panel shows the selected joint's state of the newest frame", () => {
  const states = new JointStates();
  const hinge = listed(5, 2, { position: 0.9, speed: 3, force: { x: 0, y: 9.81, z: 0 }, motorImpulse: 0.01 });
  const slider = listed(9, 3, { position: 0.2, speed: 0, motorImpulse: 0 });
  states.noteListing([hinge, slider], 100);
  states.noteFrame(wireFrame(104));
  const rows = (info) => Object.fromEntries(jointRows(info, states.get(info.id)));

  const shownHinge = rows(hinge);
  assert.equal(shownHinge.angle, `${f32(1.1).toFixed(3)} rad (${((f32(1.1) * 180) / Math.PI).toFixed(1)}\u00b0)`);
  assert.equal(shownHinge.speed, `${f32(4.2).toFixed(3)} rad/s`);
  assert.equal(shownHinge["motor impulse"], `${f32(0.05).toFixed(3)} N m s`);
  assert.equal(shownHinge.force, "9.810 N (0.000, 9.810, 0.000), listed at tick 100");
  const shownSlider = rows(slider);
  assert.equal(shownSlider.position, "-0.600 m");
  assert.equal(shownSlider.speed, "0.250 m/s");
  assert.equal(shownSlider["motor impulse"], "-2.500 N s");
});
