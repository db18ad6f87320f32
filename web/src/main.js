// The viewer page: connects to tumbled's WebSocket, draws the world live,
// and lets the user select and push bodies. Wires the modules together:
// Connection (socket, reconnects) -> Session (protocol) -> PoseBuffer and
// TickClock (interpolation) -> WorldView (three.js), with Hud, Inspector and
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

const types = protocolTypes(rootFromDescriptor(descriptor));
const Events = types.WorldEventKind;

class Viewer {
  constructor() {
    this.view = new WorldView(document.getElementById("scene"));
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
    this.listing = null;      // a ListBodies under way
    this.listAgain = false;   // another was asked for meanwhile

    this.pointer = new PointerControl(this.view, {
      onSelect: (id) => this.select(id),
      canPush: (id) => this.view.bodies.get(id)?.motion === "dynamic",
      onPush: (id, impulse, point) => this.push(id, impulse, point),
    });

    this.connection = connectionFor(new URLSearchParams(location.hash.slice(1)));
    this.connection.onState = (state, detail) => this.hud.setConnection(state, detail);
    this.connection.onSession = (session, welcome) => this.start(session, welcome);
    this.connection.onClose = () => this.stop();
    this.connection.start();

    setInterval(() => this.refreshInspector(), kInspectorIntervalMs);
    requestAnimationFrame((now) => this.frame(now));
  }

  // A new session after its Welcome: list the bodies, subscribe, poll stats.
  async start(session, welcome) {
    this.session = session;
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
        events: [Events.WORLD_EVENT_BODY_SPAWNED, Events.WORLD_EVENT_BODY_REMOVED, Events.WORLD_EVENT_WORLD_RESET,
                 Events.WORLD_EVENT_BODY_ASLEEP, Events.WORLD_EVENT_BODY_AWAKE],
      });
      if (session !== this.session) return;  // it closed meanwhile
      this.periodTicks = subscribed.periodTicks;
      this.clock.setRate(subscribed.rateHz * subscribed.periodTicks);
      this.hud.setStream(subscribed.rateHz, subscribed.periodTicks);
      this.pollStats();
      clearInterval(this.statsTimer);
      this.statsTimer = setInterval(() => this.pollStats(), kStatsIntervalMs);
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
  }

  // Asks for the body list and redraws the bodies; while one is under way,
  // another is asked for once it is done (events come in bursts).
  async listBodies() {
    if (this.listing) {
      this.listAgain = true;
      return this.listing;
    }
    const session = this.session;
    this.listing = (async () => {
      do {
        this.listAgain = false;
        const bodies = await session.listAllBodies();
        if (session !== this.session) return;
        this.view.setBodies(bodies);
      } while (this.listAgain);
    })();
    try {
      await this.listing;
    } finally {
      this.listing = null;
    }
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
  }

  onEvent(event) {
    switch (event.kind) {
      case Events.WORLD_EVENT_BODY_ASLEEP: this.view.setAsleep(event.bodyId, true); break;
      case Events.WORLD_EVENT_BODY_AWAKE: this.view.setAsleep(event.bodyId, false); break;
      default: this.listBodies().catch(() => {}); break;  // spawned, removed, reset
    }
  }

  // Draws one picture: the poses about one frame period behind the newest.
  frame(now) {
    const tick = this.clock.tickAt(now);
    if (tick !== null) this.poses.sample(tick - this.periodTicks, (id, p, q) => this.view.setPose(id, p, q));
    this.view.render();
    if (this.session && this.latest && this.view.bodies.size) this.ready = true;
    requestAnimationFrame((next) => this.frame(next));
  }

  select(id) {
    this.view.select(id);
    this.refreshInspector();
  }

  refreshInspector() {
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
