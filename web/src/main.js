// The viewer page: connects to tumbled's WebSocket, draws the world live
// with its joints, and lets the user select bodies and joints and push
// bodies. Wires the modules together: Connection (socket, reconnects) ->
// Session (protocol) -> PoseBuffer and TickClock (interpolation) ->
// WorldView and JointView (three.js), with Hud, Inspector and
// PointerControl around it. Opened as #nats=ws://HOST:PORT&world=NAME, it
// reads the world through NATS instead: NatsLink -> NatsSession, the same
// surface.
import { wsconnect } from "@nats-io/nats-core";
import descriptor from "tumble:protocol-descriptor";
import { bodyMotion } from "./body_motion.js";
import { Connection } from "./connection.js";
import { Hud } from "./hud.js";
import { Inspector } from "./inspector.js";
import { PoseBuffer, TickClock } from "./interpolation.js";
import { JointStates } from "./joint_states.js";
import { JointView } from "./joint_view.js";
import { NatsLink } from "./nats_link.js";
import { PointerControl } from "./pointer.js";
import { protocolTypes, rootFromDescriptor } from "./schema.js";
import { installTestHook } from "./test_hook.js";
import { WorldView } from "./world_view.js";

// Pose frames asked for, per second; the server rounds to a divisor of its
// tick rate and says what it chose.
const kStreamRateHz = 60;
// GetStats is asked this often, ms.
const kStatsIntervalMs = 1000;
// The selection panel is refreshed this often, ms.
const kInspectorIntervalMs = 100;
// A joint listing waits at most this long for the pose frame of its tick, ms.
const kFrameWaitMs = 500;

const types = protocolTypes(rootFromDescriptor(descriptor));
const Events = types.WorldEventKind;

class Viewer {
  constructor() {
    this.view = new WorldView(document.getElementById("scene"));
    this.joints = new JointView(this.view);
    this.hud = new Hud(document.getElementById("hud"));
    this.inspector = new Inspector(document.getElementById("inspector"));
    this.poses = new PoseBuffer();
    this.clock = new TickClock();
    this.session = null;
    this.role = "";
    this.ready = false;
    this.lastTick = null;
    this.latest = null;       // the newest PoseFrame, for the selection panel
    this.periodTicks = 1;     // of the pose stream
    this.statsTimer = null;
    // Each joint's newest state: from the pose frames (the subscription
    // asks for every joint's), force and torque from the listings.
    this.jointStates = new JointStates();
    this.jointsListed = false;     // this session listed the joints already
    this.frameWaiters = [];        // {tick, resolve}: joint listings waiting for their tick's frame
    this.listBodies = coalescing(() => this.listBodiesOnce());
    this.listJoints = coalescing(() => this.listJointsOnce());

    this.pointer = new PointerControl(this.view, {
      onSelect: (id) => this.select(id),
      canPush: (id) => this.view.bodies.get(id)?.motion === "dynamic",
      onPush: (id, impulse, point) => this.push(id, impulse, point),
      pickJoint: (x, y) => this.joints.pick(x, y),
      onSelectJoint: (id) => this.selectJoint(id),
    });

    this.connection = connectionFor(new URLSearchParams(location.hash.slice(1)));
    this.connection.onState = (state, detail) => this.hud.setConnection(state, detail);
    this.connection.onSession = (session, welcome) => this.start(session, welcome);
    this.connection.onClose = () => this.stop();
    this.connection.start();

    setInterval(() => this.refreshInspector(), kInspectorIntervalMs);
    requestAnimationFrame((now) => this.frame(now));
  }

  // A new session after its Welcome: list the bodies, subscribe (with the
  // joints' states in each frame), list the joints, poll stats.
  async start(session, welcome) {
    this.session = session;
    // Another server's ticks may be behind this one's: states start afresh.
    this.jointStates.clear();
    this.jointsListed = false;
    this.role = types.roleName(welcome.role);
    this.hud.setRole(this.role);
    this.hud.setClock(welcome.tick, welcome.simTime);
    this.clock.setRate(welcome.tickRateHz);
    this.inspector.setNote(this.role === "ROLE_CONTROLLER" ? "" : this.connection.pushNote);
    session.onPoseFrame = (frame) => this.onFrame(frame);
    session.onWorldEvent = (event) => this.onEvent(event);
    session.onError = (error) => console.warn("tumble:", error.message);
    try {
      await this.listBodies();
      const subscribed = await session.subscribePoses({
        rateHz: kStreamRateHz,
        fields: types.PoseFields.POSE_FIELDS_POSE_AND_VELOCITY,
        encoding: types.PoseEncoding.POSE_ENCODING_FULL,
        // Every joint's position, speed and motor impulse in each frame
        // (a few floats per joint; the protocol has no per-joint choice):
        // the panel's state of the selected joint comes from there.
        joints: true,
        events: [Events.WORLD_EVENT_BODY_SPAWNED, Events.WORLD_EVENT_BODY_REMOVED, Events.WORLD_EVENT_WORLD_RESET,
                 Events.WORLD_EVENT_BODY_ASLEEP, Events.WORLD_EVENT_BODY_AWAKE, Events.WORLD_EVENT_JOINT_ADDED,
                 Events.WORLD_EVENT_JOINT_REMOVED, Events.WORLD_EVENT_JOINT_BROKEN],
      });
      if (session !== this.session) return;  // it closed meanwhile
      this.periodTicks = subscribed.periodTicks;
      this.clock.setRate(subscribed.rateHz * subscribed.periodTicks);
      this.hud.setStream(subscribed.rateHz, subscribed.periodTicks);
      this.pollStats();
      clearInterval(this.statsTimer);
      this.statsTimer = setInterval(() => this.pollStats(), kStatsIntervalMs);
      // After the subscription, so the listing's poses are in the frames.
      this.listJoints().catch((error) => console.warn("tumble: the joints could not be listed:", error.message));
    } catch (error) {
      console.warn("tumble: the session could not start:", error.message);
    }
  }

  // The session ended; Connection retries.
  stop() {
    clearInterval(this.statsTimer);
    this.session = null;
    this.ready = false;
    this.poses.clear();
    for (const waiter of this.frameWaiters) waiter.resolve();
    this.frameWaiters = [];
  }

  // Asks for the body list and redraws the bodies (listBodies() runs it,
  // once more after one under way).
  async listBodiesOnce() {
    const session = this.session;
    const bodies = await session.listAllBodies();
    if (session !== this.session) return;
    this.view.setBodies(bodies);
  }

  // Asks for the joint list and redraws the joints (listJoints() runs it,
  // once more after one under way). A new joint's anchors are taken into
  // its bodies' frames at their poses of the listing's tick, so the
  // listing waits for that tick's frame.
  async listJointsOnce() {
    const session = this.session;
    const { joints, tick } = await session.listAllJoints();
    if (session !== this.session) return;
    if (tick !== null) await this.frameAt(tick);
    if (session !== this.session) return;
    this.joints.setJoints(joints, (id) => this.poses.poseAt(id, tick), this.jointsListed);
    this.jointsListed = true;
    this.jointStates.retain(this.joints.joints);
    this.jointStates.noteListing(joints, tick ?? 0);
    this.hud.setJoints(joints.length);
    this.refreshInspector();
  }

  // Resolves once a pose frame of `tick` or later is held, or after
  // kFrameWaitMs (a stream that stopped).
  frameAt(tick) {
    if (this.lastTick !== null && this.lastTick >= tick) return Promise.resolve();
    return new Promise((resolve) => {
      const waiter = { tick, resolve };
      this.frameWaiters.push(waiter);
      setTimeout(() => {
        this.frameWaiters = this.frameWaiters.filter((w) => w !== waiter);
        resolve();
      }, kFrameWaitMs);
    });
  }

  async pollStats() {
    try {
      const stats = await this.session?.request("getStats");
      if (!stats) return;
      this.hud.setStats(stats);
      this.clock.setRate(stats.tickRateHz);
    } catch (error) {
      // RATE_LIMITED or a closed session: the next poll tries again.
    }
  }

  onFrame(frame) {
    this.poses.push(frame);
    this.latest = frame;
    this.lastTick = Number(frame.tick);
    // Arrivals that disagree with the estimate by more than a quarter
    // second (or a few frames) mean a pause, a step or a stalled page.
    this.clock.observe(this.lastTick, performance.now(), Math.max(this.clock.rateHz / 4, 4 * this.periodTicks));
    this.hud.setClock(this.lastTick, frame.simTime);
    // The selected joint's panel shows each frame's state of it.
    try {
      if (this.jointStates.noteFrame(frame) && this.joints.selectedId !== null) this.refreshInspector();
    } catch (error) {
      console.warn("tumble:", error.message);
    }
    const waiting = this.frameWaiters;
    this.frameWaiters = waiting.filter((waiter) => waiter.tick > this.lastTick);
    for (const waiter of waiting) if (waiter.tick <= this.lastTick) waiter.resolve();
  }

  onEvent(event) {
    switch (event.kind) {
      case Events.WORLD_EVENT_BODY_ASLEEP: this.view.setAsleep(event.bodyId, true); break;
      case Events.WORLD_EVENT_BODY_AWAKE: this.view.setAsleep(event.bodyId, false); break;
      case Events.WORLD_EVENT_JOINT_ADDED:
      case Events.WORLD_EVENT_JOINT_REMOVED:
      case Events.WORLD_EVENT_JOINT_BROKEN:
        this.listJoints().catch(() => {});
        break;
      case Events.WORLD_EVENT_WORLD_RESET:
        // Joint ids start afresh: the joints are listed anew, not kept.
        this.joints.clear();
        this.jointStates.clear();
        this.listBodies().then(() => this.listJoints()).catch(() => {});
        break;
      default: this.listBodies().catch(() => {}); break;  // spawned, removed
    }
  }

  // Draws one picture: the poses about one frame period behind the newest.
  frame(now) {
    const tick = this.clock.tickAt(now);
    if (tick !== null) this.poses.sample(tick - this.periodTicks, (id, p, q) => this.view.setPose(id, p, q));
    this.joints.update();
    this.view.render();
    if (this.session && this.latest && this.view.bodies.size) this.ready = true;
    requestAnimationFrame((next) => this.frame(next));
  }

  select(id) {
    this.joints.select(null);
    this.view.select(id);
    this.refreshInspector();
  }

  selectJoint(id) {
    this.view.select(null);
    this.joints.select(id);
    this.refreshInspector();
  }

  refreshInspector() {
    const joint = this.joints.joints.get(this.joints.selectedId);
    if (joint) return this.inspector.showJoint(joint.info, this.jointStates.get(joint.info.id));
    const body = this.view.bodies.get(this.view.selectedId);
    if (!body) return this.inspector.clear();
    const state = { position: [0, 0, 0], linearVelocity: [0, 0, 0], angularVelocity: [0, 0, 0] };
    const i = this.latest ? this.latest.ids.indexOf(body.info.id) : -1;
    const at = (array, n) => (array.length ? Array.from(array.slice(n * i, n * i + n)) : [0, 0, 0]);
    if (i >= 0) {
      state.position = at(this.latest.positions, 3);
      state.linearVelocity = at(this.latest.linearVelocities, 3);
      state.angularVelocity = at(this.latest.angularVelocities, 3);
    } else {
      const v = (vector) => [vector?.x ?? 0, vector?.y ?? 0, vector?.z ?? 0];
      state.position = v(body.info.position);
      state.linearVelocity = v(body.info.linearVelocity);
      state.angularVelocity = v(body.info.angularVelocity);
    }
    this.inspector.show(body.info, bodyMotion(body.info), state, body.asleep);
  }

  // Sends ApplyImpulse when this connection may; otherwise says why not.
  push(id, impulse, point) {
    if (this.role !== "ROLE_CONTROLLER" || !this.session) {
      this.inspector.setNote(this.connection.pushNote);
      this.refreshInspector();
      return;
    }
    const v = (vector) => ({ x: vector.x, y: vector.y, z: vector.z });
    this.session.request("applyImpulse", {
      body: { id },
      impulse: v(impulse),
      point: v(point),
      pointFrame: 0,  // FRAME_WORLD
    }).then(
      () => this.inspector.setNote(""),
      (error) => this.inspector.setNote(`The push was refused: ${error.codeName || error.message}`),
    ).finally(() => this.refreshInspector());
  }
}

// `run` (async) as a function that runs it, or, called while a run is under
// way, runs it once more after that one (events come in bursts); resolves
// when a run begun after the call is done.
function coalescing(run) {
  let running = null;
  let again = false;
  return async () => {
    if (running) {
      again = true;
      return running;
    }
    running = (async () => {
      do {
        again = false;
        await run();
      } while (again);
    })();
    try {
      await running;
    } finally {
      running = null;
    }
  };
}

// The link the page's address asks for: through NATS with `nats=` (and
// `world=`, `stream=`, `user=` and `pass=` or `token=`), else tumbled's own
// WebSocket with `token=`.
function connectionFor(params) {
  const get = (name) => params.get(name) ?? "";
  if (params.has("nats")) {
    return new NatsLink(wsconnect, {
      servers: get("nats"), world: get("world"), stream: get("stream"),
      user: get("user"), pass: get("pass"), token: get("token"),
    }, types);
  }
  const scheme = location.protocol === "https:" ? "wss" : "ws";
  return new Connection(`${scheme}://${location.host}/ws`, types, get("token"));
}

installTestHook(new Viewer());
