// The viewer's interpolation (web/src/interpolation.js) against closed-form
// answers: positions between frames, rotations along the shorter arc at
// constant angular speed, and the page-time to tick mapping.
//
//   node interpolation_test.mjs
import assert from "node:assert/strict";
import { test } from "node:test";

import { PoseBuffer, TickClock, slerp } from "../../web/src/interpolation.js";

const close = (actual, expected, tolerance = 1e-9) =>
  assert.ok(actual.every((x, i) => Math.abs(x - expected[i]) <= tolerance), `${actual} != ${expected}`);

// A rotation of `angle` rad about unit axis [x, y, z], as [w, x, y, z].
const rotation = (angle, axis) => [Math.cos(angle / 2), ...axis.map((a) => a * Math.sin(angle / 2))];

// A FULL PoseFrame as protobufjs decodes it.
const frame = (tick, bodies) => ({
  tick,
  ids: bodies.map((b) => b.id),
  positions: bodies.flatMap((b) => b.p),
  orientations: bodies.flatMap((b) => b.q),
});

// Everything sample() visits at `tick`, by id, copied.
function sampleAt(buffer, tick) {
  const out = new Map();
  buffer.sample(tick, (id, p, q) => out.set(id, { p: Array.from(p), q: Array.from(q) }));
  return out;
}

test("slerp turns at constant angular speed along the shorter arc", () => {
  const from = rotation(0, [0, 1, 0]);
  const to = rotation(Math.PI / 2, [0, 1, 0]);
  for (const t of [0, 0.25, 0.5, 1]) close(slerp(from, 0, to, 0, t, [0, 0, 0, 0]), rotation(t * Math.PI / 2, [0, 1, 0]));
  // -q is the same rotation as q: the way from identity to -(90 degrees)
  // is still the 90 degree turn, not the 270 degree one.
  close(slerp(from, 0, to.map((x) => -x), 0, 0.5, [0, 0, 0, 0]), rotation(Math.PI / 4, [0, 1, 0]));
  // Nearly equal orientations: still unit length.
  const near = slerp(from, 0, rotation(1e-6, [1, 0, 0]), 0, 0.5, [0, 0, 0, 0]);
  assert.ok(Math.abs(Math.hypot(...near) - 1) < 1e-12);
});

test("PoseBuffer interpolates between the frames around a tick and never guesses ahead", () => {
  const buffer = new PoseBuffer();
  assert.equal(buffer.latestTick(), null);
  buffer.push(frame(100, [{ id: 1, p: [0, 0, 0], q: rotation(0, [0, 0, 1]) }, { id: 2, p: [5, 5, 5], q: [1, 0, 0, 0] }]));
  buffer.push(frame(104, [{ id: 1, p: [4, -2, 8], q: rotation(1, [0, 0, 1]) }, { id: 3, p: [1, 1, 1], q: [1, 0, 0, 0] }]));
  assert.equal(buffer.latestTick(), 104);

  const middle = sampleAt(buffer, 101);
  close(middle.get(1).p, [1, -0.5, 2], 1e-6);
  close(middle.get(1).q, rotation(0.25, [0, 0, 1]), 1e-6);
  assert.equal(middle.has(2), false);  // gone by the newer frame
  close(middle.get(3).p, [1, 1, 1]);   // new in it: shown where it is

  close(sampleAt(buffer, 90).get(1).p, [0, 0, 0]);              // before the oldest: the oldest
  close(sampleAt(buffer, 200).get(1).p, [4, -2, 8], 1e-6);      // after the newest: the newest

  // A frame that is not newer (a new connection) starts afresh.
  buffer.push(frame(50, [{ id: 1, p: [9, 9, 9], q: [1, 0, 0, 0] }]));
  assert.equal(buffer.latestTick(), 50);
  close(sampleAt(buffer, 104).get(1).p, [9, 9, 9]);
});

test("TickClock follows frame arrivals slowly and jumps after a pause", () => {
  const clock = new TickClock();
  assert.equal(clock.tickAt(0), null);
  clock.setRate(240);
  clock.observe(1000, 0, 60);
  assert.equal(clock.tickAt(0), 1000);
  assert.equal(clock.tickAt(500), 1120);  // 240 ticks a second
  // A frame 4 ticks later than expected moves the estimate by a twentieth.
  clock.observe(1000 + 240 - 4, 1000, 60);
  assert.ok(Math.abs(clock.tickAt(1000) - (1240 - 0.2)) < 1e-9);
  // The world was paused for 10 s: the next frame resets the estimate.
  clock.observe(1300, 11000, 60);
  assert.equal(clock.tickAt(11000), 1300);
  // A new tick rate drops the estimate until the next frame.
  clock.setRate(120);
  assert.equal(clock.tickAt(11000), null);
});

test("poseAt gives one body's pose as sample() draws it, and null for a body no frame holds", () => {
  const buffer = new PoseBuffer();
  buffer.push(frame(10, [{ id: 1, p: [0, 0, 0], q: rotation(0, [0, 0, 1]) }, { id: 2, p: [5, 5, 5], q: rotation(0, [0, 0, 1]) }]));
  buffer.push(frame(12, [{ id: 2, p: [7, 5, 5], q: rotation(Math.PI / 2, [0, 0, 1]) }]));
  const drawn = sampleAt(buffer, 11).get(2);
  const pose = buffer.poseAt(2, 11);
  close(pose.position, drawn.p);
  close(pose.orientation, drawn.q);
  close(pose.position, [6, 5, 5]);
  close(pose.orientation, rotation(Math.PI / 4, [0, 0, 1]));
  // Outside the frames held: the nearest; a body only the older frame has: its pose there.
  close(buffer.poseAt(2, 20).position, [7, 5, 5]);
  close(buffer.poseAt(2, 0).position, [5, 5, 5]);
  close(buffer.poseAt(1, 11).position, [0, 0, 0]);
  assert.equal(buffer.poseAt(3, 11), null);
});
