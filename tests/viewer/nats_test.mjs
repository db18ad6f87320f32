// The viewer's NATS transport (web/src/nats_session.js, sequence_gate.js,
// pose_stream.js, quantized_poses.js) against a real nats-server with a
// WebSocket listener, started here. The test plays the world's server on
// the contract's subjects, so every frame the page is sent is known: the
// world is found among others by its name, a DELTA stream joined late or
// with a gap shows nothing until a key frame and then exactly the server's
// state, and an observer's requests are refused by NATS.
//
//   node nats_test.mjs
//
// Exits 77 (ctest's skip) when web/node_modules or nats-server is missing.
import assert from "node:assert/strict";
import { createRequire } from "node:module";
import { after, before, test } from "node:test";

import { missingNodeModules } from "./browser.mjs";
import { kUsers, natsServerPath, startNatsServer } from "./nats_server.mjs";

const missing = missingNodeModules() || (natsServerPath() ? "" : "nats-server, which is missing");
if (missing) {
  console.log(`SKIP: the viewer's NATS test needs ${missing}`);
  process.exit(77);
}
// After the check: these import from web/node_modules.
const { connect } = createRequire(new URL("../../web/package.json", import.meta.url))("@nats-io/transport-node");
const { NatsSession, findWorld, listWorlds } = await import("../../web/src/nats_session.js");
const { decodePackedPoses, PackedPosesError } = await import("../../web/src/quantized_poses.js");
const { protocolTypes } = await import("../../web/src/schema.js");
const { loadProtocolRoot } = await import("../../web/proto-schema.mjs");
const types = protocolTypes(loadProtocolRoot());
const { PoseEncoding } = types;
const kWaitMs = 20000;  // generous bound for anything that should take a moment
const kStep = 1 / 1024;  // the position grid, m

let nats = null;
before(async () => {
  nats = await startNatsServer();
});
after(async () => {
  await nats?.stop();
});

const connectAs = (who) => connect({ servers: nats.url, ...kUsers[who] });

// --- the test's side of the wire: packed bytes as proto/wire/quantized_poses.cpp makes them

function appendVarint(out, value) {
  while (value >= 0x80) {
    out.push((value % 0x80) | 0x80);
    value = Math.floor(value / 0x80);
  }
  out.push(value);
}
const zigzag = (value) => (value >= 0 ? 2 * value : -2 * value - 1);

// Bodies {id, cell: [x, y, z] (grid steps), orientation (smallest three)}, in id order, without velocities.
function encodePacked(bodies) {
  const out = [];
  appendVarint(out, bodies.length);
  appendVarint(out, 0);
  appendVarint(out, 10);
  let previous = 0;
  for (const body of bodies) {
    appendVarint(out, zigzag(body.id - previous));
    previous = body.id;
  }
  if (!bodies.length) return Uint8Array.from(out);
  const origin = [0, 1, 2].map((a) => Math.min(...bodies.map((b) => b.cell[a])));
  const width = [0, 1, 2].map((a) => {
    const extent = Math.max(...bodies.map((b) => b.cell[a])) - origin[a];
    return extent ? Math.floor(Math.log2(extent)) + 1 : 0;
  });
  for (const o of origin) appendVarint(out, zigzag(o));
  out.push(...width);
  let bits = [];
  const write = (value, n) => {
    for (let i = 0; i < n; ++i) bits.push(Math.floor(value / 2 ** i) % 2);
  };
  for (const body of bodies) {
    for (let a = 0; a < 3; ++a) write(body.cell[a] - origin[a], width[a]);
    write(body.orientation, 32);
  }
  while (bits.length % 8) bits.push(0);
  for (let i = 0; i < bits.length; i += 8) out.push(bits.slice(i, i + 8).reduce((byte, bit, k) => byte | (bit << k), 0));
  return Uint8Array.from(out);
}

// The smallest three of the identity: largest w, x = y = z at level 511.
const kIdentity = 511 * 4 + 511 * 4096 + 511 * 4194304;

// --- a world's server, played by the test: it answers tumble.v1.worlds,
// .rpc (Hello, ListBodies) and .key.<stream>, and publishes frames on demand.
class FakeWorld {
  // `query`: whether it answers on `.query` too, as tumbled does (a server
  // that does not stands for an older one, or a NATS without the subject).
  constructor(nc, name, { encoding = PoseEncoding.POSE_ENCODING_DELTA, stream = "d60", query = true } = {}) {
    this.nc = nc;
    this.name = name;
    this.stream = stream;
    this.encoding = encoding;
    this.sequence = 0;
    this.tick = 0;
    this.bodies = new Map();  // id -> cell [x, y, z]
    this.joints = [];         // joint ids, ascending
    this.previous = new Map();  // what the last frame published held
    this.keyRequests = 0;
    this.info = types.WorldInfo.fromObject({
      world: name, tick: 0, tickRateHz: 120, bodies: 0, version: "test",
      streams: [{ name: stream, subject: `tumble.v1.${name}.poses.${stream}`, encoding, rateHz: 60, keyIntervalS: 1 }],
      eventsSubject: `tumble.v1.${name}.events`, rpcSubject: `tumble.v1.${name}.rpc`, serverId: `test-${name}`,
    });
    const reply = (handler) => (error, message) => {
      if (!error) message.respond(types.ServerMessage.encode(types.ServerMessage.fromObject(handler(message))).finish());
    };
    const answer = reply((message) => {
      const request = types.ClientMessage.decode(message.data);
      if (request.kind === "hello") {
        return { welcome: { tickRateHz: 120, tick: this.tick, role: types.Role.ROLE_CONTROLLER } };
      }
      if (request.kind === "listBodies") {
        // Pages of two bodies, to be read page after page.
        const ids = [...this.bodies.keys()].filter((id) => id >= request.listBodies.startId).sort((a, b) => a - b);
        return { bodyList: { requestId: request.requestId, tick: this.tick,
                             bodies: ids.slice(0, 2).map((id) => ({ id, name: `body${id}` })),
                             nextStartId: ids.length > 2 ? ids[2] : 0, totalBodies: this.bodies.size } };
      }
      if (request.kind === "listJoints") {
        // Pages of two joints, each page a tick later than the one before.
        const ids = this.joints.filter((id) => id >= request.listJoints.startId);
        this.tick += 1;
        return { jointList: { requestId: request.requestId, tick: this.tick,
                              joints: ids.slice(0, 2).map((id) => ({ id, name: `joint${id}`, type: 2 })),
                              nextStartId: ids.length > 2 ? ids[2] : 0, totalJoints: this.joints.length } };
      }
      return { error: { requestId: request.requestId, code: types.ErrorCode.INVALID_ARGUMENT, message: "not here" } };
    });
    this.subscriptions = [
      nc.subscribe("tumble.v1.worlds", { callback: (error, message) => {
        if (!error) message.respond(types.WorldInfo.encode(this.info).finish());
      } }),
      nc.subscribe(`tumble.v1.${name}.key.${stream}`, { callback: reply(() => {
        ++this.keyRequests;
        return { poseFrame: this.frame(true, this.sequence) };
      }) }),
      // In tumbled's queue group, the only way docker/nats/auth.conf lets the tumbled user read .rpc and .query.
      nc.subscribe(`tumble.v1.${name}.rpc`, { queue: `tumble.${name}.rpc`, callback: answer }),
    ];
    if (query) this.subscriptions.push(nc.subscribe(`tumble.v1.${name}.query`, { queue: `tumble.${name}.rpc`, callback: answer }));
  }

  // The state at the current sequence: every body (key) or those changed since the previous frame.
  frame(key, sequence) {
    const ids = [...this.bodies.keys()].sort((a, b) => a - b)
      .filter((id) => key || String(this.previous.get(id)) !== String(this.bodies.get(id)));
    const removed = key ? [] : [...this.previous.keys()].filter((id) => !this.bodies.has(id));
    return {
      tick: this.tick, simTime: this.tick / 120, sequence, encoding: this.encoding, keyFrame: key,
      packed: encodePacked(ids.map((id) => ({ id, cell: this.bodies.get(id), orientation: kIdentity }))),
      removedIds: removed,
    };
  }

  // Steps: moves the bodies, then publishes the next frame (unless `lose`,
  // which numbers it but keeps it from the wire, as a dropped message).
  async publish({ key = false, lose = false, move = (id, cell) => [cell[0] + id, cell[1], cell[2]] } = {}) {
    this.tick += 2;
    for (const [id, cell] of this.bodies) this.bodies.set(id, move(id, cell));
    this.sequence += 1;
    const frame = this.frame(key, this.sequence);
    this.previous = new Map([...this.bodies].map(([id, cell]) => [id, [...cell]]));
    if (!lose) {
      this.nc.publish(this.info.streams[0].subject, types.ServerMessage.encode(types.ServerMessage.fromObject({ poseFrame: frame })).finish());
      await this.nc.flush();
    }
    return { tick: this.tick, sequence: this.sequence, bodies: new Map([...this.bodies].map(([id, c]) => [id, [...c]])) };
  }

  close() {
    for (const subscription of this.subscriptions) subscription.unsubscribe();
  }
}

// Collects the states a session shows.
function collect(session) {
  const shown = [];
  const waiters = [];
  session.onPoseFrame = (state) => {
    shown.push(state);
    for (const waiter of [...waiters]) {
      if (waiter.accept(state)) {
        waiters.splice(waiters.indexOf(waiter), 1);
        waiter.resolve(state);
      }
    }
  };
  session.onError = (error) => shown.push({ error });
  return {
    shown,
    // The first state shown (from now, or already) that `accept` takes.
    until(accept) {
      const done = shown.find((s) => !s.error && accept(s));
      if (done) return Promise.resolve(done);
      return new Promise((resolve, reject) => {
        const timer = setTimeout(() => reject(new Error(`no such state; shown: ${JSON.stringify(shown.map((s) => s.sequence))}`)), kWaitMs);
        waiters.push({ accept, resolve: (s) => { clearTimeout(timer); resolve(s); } });
      });
    },
  };
}

// Every body of `state` is where `truth` (Map id -> cell) says, within half a grid step.
function assertShows(state, truth) {
  assert.deepEqual([...state.ids], [...truth.keys()].sort((a, b) => a - b), `ids of sequence ${state.sequence}`);
  state.ids.forEach((id, i) => {
    for (let a = 0; a < 3; ++a) {
      const want = truth.get(id)[a] * kStep;
      assert.ok(Math.abs(state.positions[3 * i + a] - want) <= kStep / 2,
                `body ${id} axis ${a} at sequence ${state.sequence}: ${state.positions[3 * i + a]}, want ${want}`);
    }
    assert.deepEqual(Array.from(state.orientations.slice(4 * i, 4 * i + 4)), [1, 0, 0, 0]);
  });
}

test("packed poses decode to the bytes' grid values, and malformed bytes are refused by name", () => {
  // One body, id 5, at cells (1024, 0, -1024), identity orientation: worked out by hand from the layout.
  const bytes = Uint8Array.from([0x01, 0x00, 0x0a, 0x0a, 0x80, 0x10, 0x00, 0xff, 0x0f, 0x00, 0x00, 0x00,
                                 0xfc, 0xf7, 0xdf, 0x7f]);
  const poses = decodePackedPoses(bytes);
  assert.deepEqual(poses.ids, [5]);
  assert.deepEqual(Array.from(poses.positions), [1, 0, -1]);
  assert.deepEqual(Array.from(poses.orientations), [1, 0, 0, 0]);
  assert.equal(poses.velocities, false);
  // Three bodies spread out: offsets in several widths straddling bytes.
  const bodies = [{ id: 1, cell: [-3, 7, 100000] }, { id: 2, cell: [4096, 0, 99999] }, { id: 70, cell: [5, 1, 123456] }]
    .map((b) => ({ ...b, orientation: kIdentity }));
  const decoded = decodePackedPoses(encodePacked(bodies));
  assert.deepEqual(decoded.ids, [1, 2, 70]);
  assert.deepEqual(Array.from(decoded.positions), bodies.flatMap((b) => b.cell.map((c) => c * kStep)));
  // A quarter turn about y, (w, y) = (1/sqrt2, 1/sqrt2): largest w; y at level 1022.
  const turn = decodePackedPoses(encodePacked([{ id: 1, cell: [0, 0, 0], orientation: 511 * 4 + 1022 * 4096 + 511 * 4194304 }]));
  assert.ok(Math.abs(turn.orientations[0] - Math.SQRT1_2) < 1e-3 && Math.abs(turn.orientations[2] - Math.SQRT1_2) < 1e-3,
            `quarter turn: ${Array.from(turn.orientations)}`);
  assert.throws(() => decodePackedPoses(bytes.slice(0, 14)), (e) => e instanceof PackedPosesError && /cut short/.test(e.message));
  assert.throws(() => decodePackedPoses(Uint8Array.from([...bytes, 0])), /left over/);
  assert.throws(() => decodePackedPoses(Uint8Array.from([0x05, 0x00, 0x0a])), /body count 5/);
});

test("the world is found by name among the worlds that answer", async () => {
  // A connection for each world, as each tumbled has its own: NATS lets the
  // tumbled user send one reply to a request per connection.
  const servers = [await connectAs("tumbled"), await connectAs("tumbled")];
  const demo = new FakeWorld(servers[0], "demo");
  const other = new FakeWorld(servers[1], "other");
  const page = await connectAs("observer");
  try {
    const names = (await listWorlds(page, types)).map((w) => w.world).sort();
    assert.deepEqual(names, ["demo", "other"]);
    const found = await findWorld(page, types, "other");
    assert.equal(found.serverId, "test-other");
    assert.equal(found.streams[0].subject, "tumble.v1.other.poses.d60");
    await assert.rejects(findWorld(page, types, "nowhere"), /no world "nowhere" answered on tumble.v1.worlds \(worlds: demo, other\)/);
    // A stream the world does not publish is refused by name.
    assert.throws(() => new NatsSession(page, types, found, "q30"), /world "other" has no stream "q30" \(streams: d60\)/);
  } finally {
    demo.close();
    other.close();
    await page.close();
    for (const server of servers) await server.close();
  }
  const alone = await connectAs("observer");
  await assert.rejects(findWorld(alone, types, "demo"), /\(no world answered\)/);
  await alone.close();
});

test("a standby's answer (tumbled --standby: no streams) is passed over for the leader's", async () => {
  const servers = [await connectAs("tumbled"), await connectAs("tumbled")];
  const leader = new FakeWorld(servers[0], "kept");
  // The standby answers first, for "kept" and for "orphan", whose leader is gone.
  const standby = ["kept", "orphan"].map((world) => types.WorldInfo.fromObject({ world, serverId: "0000", standby: true }));
  const subscription = servers[1].subscribe("tumble.v1.worlds", { callback: (error, message) => {
    if (error) return;
    message.respond(types.WorldInfo.encode(standby[0]).finish());
  } });
  const page = await connectAs("observer");
  try {
    const found = await findWorld(page, types, "kept");
    assert.equal(found.serverId, "test-kept");
    assert.equal(found.streams[0].subject, "tumble.v1.kept.poses.d60");
    standby.reverse();  // now it answers for "orphan" only
    await assert.rejects(findWorld(page, types, "orphan"), /world "orphan" has no leader now, only standbys/);
  } finally {
    subscription.unsubscribe();
    leader.close();
    await page.close();
    for (const server of servers) await server.close();
  }
});

test("a DELTA stream joined late shows nothing until a key frame, then exactly the server's state", async () => {
  const server = await connectAs("tumbled");
  const world = new FakeWorld(server, "late");
  for (const id of [1, 2, 3]) world.bodies.set(id, [0, 100 * id, 0]);
  await world.publish({ key: true });
  await world.publish();  // the page was not there for these two
  const page = await connectAs("controller");
  const session = new NatsSession(page, types, await findWorld(page, types, "late"));
  const seen = collect(session);
  try {
    await page.flush();  // the subscription is in place before the next frame
    // The first frame it gets is a change on top of sequence 2, which it never had: it asks for a key frame.
    const third = await world.publish();
    const keyed = await seen.until(() => true);
    assert.equal(world.keyRequests, 1);
    // The key reply is the stream's latest frame, sequence 3, whole.
    assert.equal(keyed.sequence, third.sequence);
    assertShows(keyed, third.bodies);
    // From then on every change applies on top of the one before.
    for (let i = 0; i < 5; ++i) {
      const truth = await world.publish();
      assertShows(await seen.until((s) => s.sequence === truth.sequence), truth.bodies);
    }
    // A body leaves and another comes: the change carries both.
    world.bodies.delete(2);
    world.bodies.set(9, [5, 5, 5]);
    const changed = await world.publish();
    assertShows(await seen.until((s) => s.sequence === changed.sequence), changed.bodies);
    assert.deepEqual(seen.shown.filter((s) => s.error), []);
    assert.equal(seen.shown[0], keyed, "a state was shown before the key frame");
  } finally {
    session.close();
    world.close();
    await page.close();
    await server.close();
  }
});

test("after a lost DELTA frame nothing new is shown until a key frame restores the state", async () => {
  const server = await connectAs("tumbled");
  const world = new FakeWorld(server, "gap");
  for (const id of [1, 2]) world.bodies.set(id, [0, 0, 10 * id]);
  const page = await connectAs("observer");
  const session = new NatsSession(page, types, await findWorld(page, types, "gap"));
  const seen = collect(session);
  try {
    await page.flush();  // the subscription is in place before the first frame
    const first = await world.publish({ key: true });
    assertShows(await seen.until((s) => s.sequence === first.sequence), first.bodies);
    const second = await world.publish();
    assertShows(await seen.until((s) => s.sequence === second.sequence), second.bodies);
    // Sequence 3 is lost on the way; 4 is a change on top of 3, which the page never had.
    await world.publish({ lose: true });
    const requestsBefore = world.keyRequests;
    const fourth = await world.publish();
    // The key reply comes for the latest frame, 4, and is shown whole and right.
    const restored = await seen.until((s) => s.sequence >= fourth.sequence);
    assert.equal(world.keyRequests, requestsBefore + 1);
    assertShows(restored, fourth.bodies);
    const fifth = await world.publish();
    assertShows(await seen.until((s) => s.sequence === fifth.sequence), fifth.bodies);
    // Nothing but frames 1, 2, then the restored 4 and 5: the change 4 was not applied on top of 2.
    assert.deepEqual(seen.shown.map((s) => s.sequence), [1, 2, 4, 5]);
  } finally {
    session.close();
    world.close();
    await page.close();
    await server.close();
  }
});

test("an observer lists the bodies and joints by name on .query, page by page", async () => {
  const server = await connectAs("tumbled");
  const world = new FakeWorld(server, "reads");
  for (const id of [3, 5, 9]) world.bodies.set(id, [id, 0, 0]);
  world.joints = [1, 2, 6];
  const observer = await connectAs("observer");
  const asObserver = new NatsSession(observer, types, await findWorld(observer, types, "reads"));
  try {
    assert.equal((await asObserver.hello()).role, types.Role.ROLE_OBSERVER);
    assert.deepEqual((await asObserver.listAllBodies()).map((b) => b.name), ["body3", "body5", "body9"]);
    // The listing's tick is its first page's.
    const tick = world.tick + 1;
    const { joints, tick: listed } = await asObserver.listAllJoints();
    assert.deepEqual(joints.map((j) => j.name), ["joint1", "joint2", "joint6"]);
    assert.equal(listed, tick);
  } finally {
    asObserver.close();
    world.close();
    await observer.close();
    await server.close();
  }
});

test("a controller lists the bodies page by page; NATS refuses an observer's commands; without .query its bodies come from the stream", async () => {
  const server = await connectAs("tumbled");
  const world = new FakeWorld(server, "roles", { query: false });
  for (const id of [4, 7, 8, 11, 12]) world.bodies.set(id, [id, 0, 0]);
  world.joints = [2, 3];
  const controller = await connectAs("controller");
  const observer = await connectAs("observer");
  const asController = new NatsSession(controller, types, await findWorld(controller, types, "roles"));
  const asObserver = new NatsSession(observer, types, await findWorld(observer, types, "roles"));
  try {
    assert.equal((await asController.hello()).role, types.Role.ROLE_CONTROLLER);
    assert.deepEqual((await asController.listAllBodies()).map((b) => b.name), ["body4", "body7", "body8", "body11", "body12"]);
    assert.deepEqual((await asController.listAllJoints()).joints.map((j) => j.name), ["joint2", "joint3"]);
    // The server's own Error comes back as such.
    await assert.rejects(asController.request("step", { ticks: 1 }), (e) => e.codeName === "INVALID_ARGUMENT" && e.message === "not here");

    const welcome = await asObserver.hello();
    assert.equal(welcome.role, types.Role.ROLE_OBSERVER);
    await assert.rejects(asObserver.request("applyImpulse", { body: { id: 4 } }),
                         (e) => e.codeName === "PERMISSION_DENIED" && /NATS does not permit this user to publish to tumble.v1.roles.rpc/.test(e.message));
    // Its bodies: the ids of the stream's frame, shapes unknown.
    await observer.flush();
    const listing = asObserver.listAllBodies();
    await world.publish({ key: true });
    assert.deepEqual((await listing).map((b) => [b.id, b.shape]), [[4, null], [7, null], [8, null], [11, null], [12, null]]);
    // Its joints: none, where nothing it may ask lists them.
    assert.deepEqual(await asObserver.listAllJoints(), { joints: [], tick: null });
  } finally {
    asController.close();
    asObserver.close();
    world.close();
    await controller.close();
    await observer.close();
    await server.close();
  }
});
