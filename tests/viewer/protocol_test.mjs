// The viewer's protocol code (web/src/framing.js, protocol.js, schema.js)
// against the real tumbled over TCP: the server's bytes are the same on TCP
// and on the WebSocket, so this checks the decoding the page does, without a
// browser.
//
//   node protocol_test.mjs --tumbled PATH --scene scenes/demo.json
//
// Exits 77 (ctest's skip) when web/node_modules (protobufjs) is missing.
import assert from "node:assert/strict";
import net from "node:net";
import { parseArgs } from "node:util";
import { test } from "node:test";

import { missingNodeModules } from "./browser.mjs";
import { startTumbled } from "./tumbled.mjs";

const { values: options } = parseArgs({
  options: { tumbled: { type: "string" }, scene: { type: "string" } },
});
const missing = missingNodeModules();
if (missing) {
  console.log(`SKIP: the viewer's protocol test needs ${missing}`);
  process.exit(77);
}
// After the check: these import protobufjs from web/node_modules.
const { FrameReader, FramingError, encodeFrame } = await import("../../web/src/framing.js");
const { ProtocolError, Session } = await import("../../web/src/protocol.js");
const { protocolTypes } = await import("../../web/src/schema.js");
const { bodyMotion } = await import("../../web/src/body_motion.js");
const { JointStates } = await import("../../web/src/joint_states.js");
const { loadProtocolRoot } = await import("../../web/proto-schema.mjs");
const types = protocolTypes(loadProtocolRoot());
const kWaitMs = 20000;  // generous bound for anything the server should do at once

// A Session over a TCP socket to 127.0.0.1:port. With `bytesPerChunk`, what
// arrives is fed to the session that many bytes at a time, so frames are
// split at every possible place.
function connect(port, bytesPerChunk = 0) {
  return new Promise((resolve, reject) => {
    const socket = net.connect(port, "127.0.0.1");
    const session = new Session(types, (bytes) => socket.write(bytes));
    socket.on("data", (data) => {
      const bytes = new Uint8Array(data.buffer, data.byteOffset, data.length);
      if (!bytesPerChunk) return session.receive(bytes);
      for (let i = 0; i < bytes.length; i += bytesPerChunk) session.receive(bytes.slice(i, i + bytesPerChunk));
    });
    socket.on("close", () => session.close("the connection closed"));
    socket.once("error", reject);
    socket.once("connect", () => resolve({ session, socket }));
  });
}

// Resolves with the first pose frame for which `accept(frame)` is true.
function nextFrame(session, accept = () => true) {
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error("no matching pose frame")), kWaitMs);
    session.onPoseFrame = (frame) => {
      if (!accept(frame)) return;
      clearTimeout(timer);
      resolve(frame);
    };
  });
}

test("FrameReader splits a stream at any boundary and refuses broken prefixes", () => {
  const bodies = [new Uint8Array(0), new Uint8Array(300).fill(7), Uint8Array.of(1, 2, 3)];
  const stream = Uint8Array.from(bodies.flatMap((body) => [...encodeFrame(body)]));
  assert.deepEqual([...encodeFrame(new Uint8Array(300))].slice(0, 2), [0xac, 0x02]);  // 300 as a varint
  for (const chunk of [1, 2, 5, stream.length]) {
    const reader = new FrameReader();
    const got = [];
    for (let i = 0; i < stream.length; i += chunk) {
      reader.push(stream.subarray(i, i + chunk));
      for (let body = reader.next(); body !== null; body = reader.next()) got.push([...body]);
    }
    assert.deepEqual(got, bodies.map((body) => [...body]), `chunks of ${chunk} bytes`);
    assert.equal(reader.bufferedBytes(), 0);
  }
  const tooLong = new FrameReader();
  tooLong.push(Uint8Array.of(0x80, 0x80, 0x80, 0x80, 0x80, 0x01));
  assert.throws(() => tooLong.next(), FramingError);
  const tooLarge = new FrameReader(100);
  tooLarge.push(encodeFrame(new Uint8Array(101)).subarray(0, 2));  // the prefix alone decides
  assert.throws(() => tooLarge.next(), /101 bytes/);
});

test("a session decodes the handshake, the body list, frames and replies of the real server", async () => {
  const server = await startTumbled(options.tumbled, ["--scene", options.scene]);
  try {
    const { session, socket } = await connect(server.port, 3);
    const welcome = await session.hello("");
    assert.equal(welcome.role, types.Role.ROLE_CONTROLLER);
    assert.equal(welcome.tickRateHz, 240);
    assert.equal(welcome.bodyCount, 5);

    const list = await session.request("listBodies");
    const byName = new Map(list.bodies.map((body) => [body.name, body]));
    assert.deepEqual([...byName.keys()].sort(), ["ball", "crate", "dumbbell", "pill", "tumbler"]);
    assert.equal(byName.get("crate").shape.kind, "box");
    assert.deepEqual({ ...byName.get("crate").shape.box.halfExtents }, { x: 0.5, y: 0.5, z: 0.5 });
    assert.equal(byName.get("ball").shape.sphere.radius, 0.3);
    assert.deepEqual([byName.get("pill").shape.capsule.radius, byName.get("pill").shape.capsule.halfHeight], [0.2, 0.4]);
    assert.deepEqual(byName.get("dumbbell").shape.points.masses, [1, 1, 0.5]);
    assert.equal(byName.get("crate").mass, 2);
    assert.equal(byName.get("ball").position.x, 3);
    assert.equal(bodyMotion(byName.get("crate")), "dynamic");

    const subscribed = await session.request("subscribe", {
      rateHz: 60,
      encoding: types.PoseEncoding.POSE_ENCODING_FULL,
      events: [types.WorldEventKind.WORLD_EVENT_BODY_SPAWNED, types.WorldEventKind.WORLD_EVENT_BODY_REMOVED],
    });
    assert.equal(subscribed.periodTicks, 4);
    assert.equal(subscribed.rateHz, 60);
    const first = await nextFrame(session);
    assert.equal(first.subscriptionId, subscribed.subscriptionId);
    assert.equal(first.ids.length, 5);
    assert.equal(first.positions.length, 15);
    assert.equal(first.orientations.length, 20);
    assert.equal(first.linearVelocities.length, 15);
    // The first frame is the state at once; those after it come every 4 ticks.
    const second = await nextFrame(session, (frame) => frame.tick > first.tick);
    const later = await nextFrame(session, (frame) => frame.tick > second.tick);
    assert.equal((later.tick - second.tick) % 4, 0);
    assert.ok(Math.abs(later.simTime - later.tick / 240) < 1e-9);

    // In zero gravity an impulse J on the crate (2 kg) gives it J / m.
    const crate = byName.get("crate").id;
    const ack = await session.request("applyImpulse", { body: { id: crate }, impulse: { x: 3, y: 0, z: -1 } });
    const pushed = await nextFrame(session, (frame) => frame.tick >= ack.appliedTick);
    const i = pushed.ids.indexOf(crate);
    assert.ok(Math.abs(pushed.linearVelocities[3 * i] - 1.5) < 1e-6, `v.x ${pushed.linearVelocities[3 * i]}`);
    assert.ok(Math.abs(pushed.linearVelocities[3 * i + 2] + 0.5) < 1e-6);

    const spawnedEvent = new Promise((resolve) => { session.onWorldEvent = resolve; });
    const spawned = await session.request("spawnBody", {
      body: { name: "rock", shape: { sphere: { radius: 0.2 } }, mass: 1, position: { x: 0, y: 5, z: 0 } },
    });
    const event = await spawnedEvent;
    assert.equal(event.kind, types.WorldEventKind.WORLD_EVENT_BODY_SPAWNED);
    assert.equal(event.bodyId, spawned.bodyId);
    assert.equal(event.bodyName, "rock");

    // Static and kinematic (standing still: no velocity, no mass) told apart by their motion.
    await session.request("spawnBody", {
      body: { name: "wall", shape: { box: { halfExtents: { x: 1, y: 1, z: 0.1 } } }, motion: types.Motion.MOTION_STATIC,
              position: { x: 0, y: 0, z: -5 } },
    });
    await session.request("spawnBody", {
      body: { name: "lift", shape: { box: { halfExtents: { x: 1, y: 0.1, z: 1 } } }, motion: types.Motion.MOTION_KINEMATIC,
              position: { x: 0, y: 0, z: 5 } },
    });
    const motions = new Map((await session.request("listBodies")).bodies.map((body) => [body.name, bodyMotion(body)]));
    assert.deepEqual([motions.get("crate"), motions.get("wall"), motions.get("lift")], ["dynamic", "static", "kinematic"]);

    await assert.rejects(session.request("applyImpulse", { body: { name: "nobody" }, impulse: { x: 1 } }),
                         (error) => error instanceof ProtocolError && error.codeName === "UNKNOWN_BODY");
    const stats = await session.request("getStats");  // the session goes on after an Error
    assert.equal(stats.bodies, 8);
    assert.ok(stats.tick >= pushed.tick);
    socket.destroy();
  } finally {
    await server.stop();
  }
});

test("a subscription with joints carries every joint's state, as the page keeps it, equal to ListJoints'", async () => {
  const server = await startTumbled(options.tumbled, ["--scene", options.scene]);
  try {
    const { session, socket } = await connect(server.port, 5);
    await session.hello("");
    await session.request("pause");
    // Each joint moves differently: the tumbler spins about y at 5 rad/s
    // and the pill at 0.5, the slider's motor drives the ball along x.
    const y = { x: 0, y: 1, z: 0 };
    const added = {};
    for (const spec of [
      { name: "spin", type: 2, bodyA: "world", bodyB: "tumbler", anchor: { x: 0, y: 3, z: 0 }, axis: y },
      { name: "turn", type: 2, bodyA: "world", bodyB: "pill", anchor: { x: -3, y: 0, z: 0 }, axis: y },
      { name: "rail", type: 3, bodyA: "world", bodyB: "ball", anchor: { x: 3, y: 0, z: 0 }, axis: { x: 1, y: 0, z: 0 },
        motor: { speed: 1, maxForce: 10 } },
    ]) {
      added[spec.name] = (await session.request("addJoint", { joint: spec })).jointId;
    }
    await session.request("step", { ticks: 60 });

    // Paused, the subscription's first frame and the listing are of one tick.
    const first = nextFrame(session);  // it may come with the Subscribed
    await session.request("subscribe", { rateHz: 60, encoding: types.PoseEncoding.POSE_ENCODING_FULL, joints: true });
    const frame = await first;
    const list = await session.request("listJoints");
    assert.equal(Number(list.tick), Number(frame.tick));
    assert.deepEqual(frame.jointIds, list.joints.map((joint) => joint.id));
    const states = new JointStates();
    assert.equal(states.noteFrame(frame), 3);
    for (const joint of list.joints) {
      const state = states.get(joint.id);
      assert.equal(state.tick, Number(frame.tick));
      for (const field of ["position", "speed", "motorImpulse"]) {
        assert.equal(state[field], Math.fround(joint.state[field] ?? 0), `${joint.name}'s ${field}`);
      }
    }
    // Each is its own joint's: the spin turned 60 / 240 s at 5 rad/s, the
    // turn at 0.5, and the rail's motor pushed.
    assert.ok(Math.abs(states.get(added.spin).speed - 5) < 0.1, `spin's speed ${states.get(added.spin).speed}`);
    assert.ok(Math.abs(states.get(added.turn).speed - 0.5) < 0.05, `turn's speed ${states.get(added.turn).speed}`);
    assert.ok(Math.abs(states.get(added.spin).position - 1.25) < 0.05, `spin's angle ${states.get(added.spin).position}`);
    assert.ok(states.get(added.rail).motorImpulse > 0, `rail's motor impulse ${states.get(added.rail).motorImpulse}`);

    // Stepped on, the next frame moves the states on without a listing.
    const stepped = nextFrame(session, (f) => f.tick > frame.tick);
    await session.request("step", { ticks: 4 });
    const next = await stepped;
    states.noteFrame(next);
    assert.equal(states.get(added.spin).tick, Number(next.tick));
    const listedSpin = list.joints.find((joint) => joint.id === added.spin).state.position;
    const ticks = Number(next.tick) - Number(frame.tick);
    assert.ok(Math.abs(states.get(added.spin).position - listedSpin - (5 * ticks) / 240) < 0.005,
              `spin's angle went from ${listedSpin} to ${states.get(added.spin).position} in ${ticks} ticks`);
    socket.destroy();
  } finally {
    await server.stop();
  }
});

test("the body list of a world larger than one page comes whole, page after page", async () => {
  // Pages of at most 2048 bytes: half of what a client may leave unread.
  const server = await startTumbled(options.tumbled, ["--scene", options.scene, "--max-pending-bytes", "4096"]);
  try {
    const { session, socket } = await connect(server.port);
    await session.hello("");
    for (let i = 0; i < 60; ++i) {
      await session.request("spawnBody", {
        body: { name: `rock-${i}`, shape: { sphere: { radius: 0.25 } }, mass: 1, position: { x: i, y: 20, z: 0 } },
      });
    }
    const first = await session.request("listBodies");
    assert.equal(first.totalBodies, 65);
    assert.ok(first.bodies.length < 65, `one page held all ${first.bodies.length} bodies`);
    assert.equal(first.nextStartId, first.bodies.at(-1).id + 1);

    const bodies = await session.listAllBodies();
    assert.deepEqual(bodies.map((body) => body.id), [...Array(65).keys()]);
    assert.equal(bodies[64].name, "rock-59");
    socket.destroy();
  } finally {
    await server.stop();
  }
});

test("roles come from the token, and an observer may not push", async () => {
  const server = await startTumbled(options.tumbled, ["--scene", options.scene, "--token", "pilot", "--observer-token", "guest"]);
  try {
    const observer = await connect(server.port);
    const welcome = await observer.session.hello("guest");
    assert.equal(types.roleName(welcome.role), "ROLE_OBSERVER");
    await assert.rejects(observer.session.request("applyImpulse", { body: { name: "crate" }, impulse: { x: 1 } }),
                         (error) => error.codeName === "PERMISSION_DENIED");
    observer.socket.destroy();

    const stranger = await connect(server.port);
    await assert.rejects(stranger.session.hello("wrong"), (error) => error.codeName === "UNAUTHENTICATED");
    stranger.socket.destroy();

    const controller = await connect(server.port);
    assert.equal(types.roleName((await controller.session.hello("pilot")).role), "ROLE_CONTROLLER");
    controller.socket.destroy();
  } finally {
    await server.stop();
  }
});
