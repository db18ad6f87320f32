// One world read through NATS, with the same surface as protocol.js's
// Session so the viewer does not tell them apart: request() over the
// world's `.rpc` subject, listAllBodies() over `.query`, onPoseFrame with the
// whole state of the world's pose stream, onWorldEvent from its `.events`
// subject. Subjects and payloads: docs/protocol.md, "NATS"; every payload is
// one protobuf message without tumble's length prefix.
//
// NATS's permissions are the role: a user that may publish to `.rpc` is a
// controller; an observer may read the stream and the events, ask for key
// frames and list the bodies on `.query`, and NATS refuses its commands.
// Where `.query` is not answered or not permitted, an observer's bodies are
// those the stream carries, without shapes or names.
import { PermissionViolationError } from "@nats-io/nats-core";
import { PoseStream } from "./pose_stream.js";
import { ProtocolError, listJointPages, listPages } from "./protocol.js";
import { SequenceGate } from "./sequence_gate.js";

// Replies to `tumble.v1.worlds` are collected until none came for this long, ms.
export const kWorldsStallMs = 250;
// ... or until this long passed, ms.
const kWorldsMaxWaitMs = 3000;
// An `.rpc` or `.key` request waits this long for its reply, ms.
const kRequestTimeoutMs = 5000;

// The discovery subject every server answers.
export const kWorldsSubject = "tumble.v1.worlds";

// The subject a stream's key frames are asked for on.
export const keySubject = (world, stream) => `tumble.v1.${world}.key.${stream}`;

// Every WorldInfo that answered one request on `tumble.v1.worlds`, in the
// order they came: replies are collected until none came for
// kWorldsStallMs. `nc`: a NatsConnection of @nats-io/nats-core.
export async function listWorlds(nc, types, { stallMs = kWorldsStallMs, maxWaitMs = kWorldsMaxWaitMs } = {}) {
  const worlds = [];
  let replies;
  try {
    replies = await nc.requestMany(kWorldsSubject, new Uint8Array(0),
                                   { strategy: "stall", stall: stallMs, maxWait: maxWaitMs });
  } catch (error) {
    throw natsError(error, kWorldsSubject);
  }
  try {
    for await (const reply of replies) worlds.push(types.WorldInfo.decode(reply.data));
  } catch (error) {
    // No server at all answers as "no responders": an empty list.
    if ((error?.cause ?? error)?.name !== "NoRespondersError" && !/no responders/i.test(error?.message)) {
      throw natsError(error, kWorldsSubject);
    }
  }
  return worlds;
}

// The WorldInfo of world `name`, or a ProtocolError saying which worlds
// answered instead.
export async function findWorld(nc, types, name, options) {
  const worlds = await listWorlds(nc, types, options);
  // The leader's answer: a standby's (tumbled --standby) names no streams.
  const world = worlds.find((info) => info.world === name && !info.standby);
  if (world) return world;
  if (worlds.some((info) => info.world === name)) {
    throw new ProtocolError(`world "${name}" has no leader now, only standbys (a takeover under way?)`);
  }
  const others = worlds.map((info) => info.world).sort();  // replies come in any order
  throw new ProtocolError(`no world "${name}" answered on ${kWorldsSubject}` +
                          (others.length ? ` (worlds: ${others.join(", ")})` : " (no world answered)"));
}

// A NATS client's error as a ProtocolError; a refused publish is
// PERMISSION_DENIED, as the server itself would answer an observer.
function natsError(error, subject, types) {
  if (error instanceof ProtocolError) return error;
  const cause = error?.cause ?? error;
  if (cause instanceof PermissionViolationError || cause?.name === "PermissionViolationError") {
    return new ProtocolError(`NATS does not permit this user to publish to ${subject}`,
                             types?.ErrorCode.PERMISSION_DENIED ?? 13, "PERMISSION_DENIED");
  }
  if (cause?.name === "NoRespondersError") return new ProtocolError(`nothing answers on ${subject}`);
  if (cause?.name === "TimeoutError") return new ProtocolError(`no reply on ${subject} in time`);
  return new ProtocolError(`${subject}: ${cause?.message ?? cause}`);
}

export class NatsSession {
  // `nc`: a NatsConnection; `world`: its WorldInfo; `streamName`: one of
  // world.streams (empty: the first). Subscribes at once: frames that come
  // before onPoseFrame is set still bring the stream's state up to date.
  constructor(nc, types, world, streamName = "") {
    const stream = streamName ? world.streams.find((s) => s.name === streamName) : world.streams[0];
    if (!stream) {
      const names = world.streams.map((s) => s.name).join(", ") || "none";
      throw new ProtocolError(`world "${world.world}" has no stream "${streamName}" (streams: ${names})`);
    }
    this.nc = nc;
    this.types = types;
    this.world = world;
    this.stream = stream;
    this.querySubject = world.querySubject || `tumble.v1.${world.world}.query`;
    this.keySubject = keySubject(world.world, stream.name);
    this.gate = new SequenceGate();
    this.poses = new PoseStream();
    this.nextRequestId = 1;
    this.closed = false;
    this.controller = false;   // NATS let this user publish to .rpc (set by hello())
    this.refusal = null;       // NATS's refusal of the hello: an observer's requests get it at once
    this.latest = null;        // the newest state shown
    this.lastEventTick = 0;    // of the newest world event
    this.frameWaiters = [];    // {tick, resolve, reject}: listAllBodies of an observer
    this.eventKinds = new Set();  // the WorldEventKinds handed on (subscribePoses)
    // Unsolicited messages; replace to listen (as Session's).
    this.onPoseFrame = (frame) => {};
    this.onWorldEvent = (event) => {};
    this.onError = (error) => {};

    this.subscriptions = [
      nc.subscribe(stream.subject, { callback: (error, message) => this.onStreamMessage(error, message, false) }),
      nc.subscribe(world.eventsSubject, { callback: (error, message) => this.onEventMessage(error, message) }),
    ];
  }

  // Says hello on `.rpc`: resolves with the Welcome of a controller, or,
  // when NATS refuses the publish, one made from the WorldInfo with the
  // observer's role. Rejects when nothing answers.
  async hello(clientName = "tumble-viewer") {
    const { Role, ProtocolVersion } = this.types;
    try {
      const welcome = await this.rpc({
        hello: { protocolVersion: ProtocolVersion.PROTOCOL_VERSION_CURRENT, clientName },
      }, "welcome");
      this.controller = welcome.role === Role.ROLE_CONTROLLER;
      return welcome;
    } catch (error) {
      if (error.codeName !== "PERMISSION_DENIED") throw error;
      this.refusal = error;
      const world = this.world;
      return {
        protocolVersion: ProtocolVersion.PROTOCOL_VERSION_CURRENT,
        serverVersion: world.version,
        tickRateHz: world.tickRateHz,
        tick: Number(world.tick),
        simTime: world.tickRateHz > 0 ? Number(world.tick) / world.tickRateHz : 0,
        bodyCount: world.bodies,
        role: Role.ROLE_OBSERVER,
      };
    }
  }

  // As Session.request: one ClientMessage on `.rpc`, resolved with its
  // reply (Ack, BodyList, Stats) or rejected with a ProtocolError (the
  // server's Error, or NATS's refusal as PERMISSION_DENIED).
  request(kind, payload = {}) {
    if (this.refusal) return Promise.reject(this.refusal);
    return this.rpc({ [kind]: payload });
  }

  // One ClientMessage on `subject` (default `.rpc`), resolved with the reply's content.
  async rpc(fields, expect = null, subject = this.world.rpcSubject) {
    if (this.closed) throw new ProtocolError("the connection is closed");
    const { ClientMessage, ServerMessage } = this.types;
    const requestId = this.nextRequestId++;
    const bytes = ClientMessage.encode(ClientMessage.fromObject({ requestId, ...fields })).finish();
    let reply;
    try {
      reply = await this.nc.request(subject, bytes, { timeout: kRequestTimeoutMs });
    } catch (error) {
      throw natsError(error, subject, this.types);
    }
    const message = ServerMessage.decode(reply.data);
    if (message.kind === "error") {
      throw new ProtocolError(message.error.message, message.error.code, this.types.errorName(message.error.code));
    }
    if (expect && message.kind !== expect) throw new ProtocolError(`${subject} answered ${message.kind}, not ${expect}`);
    return message[message.kind];
  }

  // Every body, as Session.listAllBodies, read on `.query`. Where that
  // fails, a controller lists them on `.rpc`; an observer's bodies are
  // those of the first frame shown at or after the newest world event (a
  // spawn shows from its event's tick on), at that frame's poses, with no
  // shape or name (the view draws a small marker).
  async listAllBodies() {
    try {
      return await listPages((startId) => this.rpc({ listBodies: { startId } }, "bodyList", this.querySubject));
    } catch (error) {
      if (!(error instanceof ProtocolError) || this.closed) throw error;
    }
    if (this.controller) return listPages((startId) => this.request("listBodies", { startId }));
    const frame = await new Promise((resolve, reject) => {
      if (this.closed) reject(new ProtocolError("the connection is closed"));
      else if (this.latest && this.latest.tick >= this.lastEventTick) resolve(this.latest);
      else this.frameWaiters.push({ tick: this.lastEventTick, resolve, reject });
    });
    const { positions: p, orientations: q } = frame;
    return Array.from(frame.ids, (id, i) => ({
      id, name: "", shape: null, mass: 0, motion: 0, asleep: false,
      position: { x: p[3 * i], y: p[3 * i + 1], z: p[3 * i + 2] },
      orientation: { w: q[4 * i], x: q[4 * i + 1], y: q[4 * i + 2], z: q[4 * i + 3] },
    }));
  }

  // One JointList page, as Session.listJointPage, read on `.query`, or on
  // `.rpc` for a controller where that fails.
  async listJointPage(startId, maxJoints = 0) {
    const ask = (subject) => this.rpc({ listJoints: { startId, maxJoints } }, "jointList", subject);
    try {
      return await ask(this.querySubject);
    } catch (error) {
      if (!(error instanceof ProtocolError) || this.closed || !this.controller) throw error;
    }
    return ask(this.world.rpcSubject);
  }

  // Every joint and the listing's tick, as Session.listAllJoints. Where
  // nothing this user may ask answers (an older server), no joints.
  async listAllJoints() {
    try {
      return await listJointPages((startId) => this.listJointPage(startId));
    } catch (error) {
      if (!(error instanceof ProtocolError) || this.closed) throw error;
    }
    return { joints: [], tick: null };
  }

  // The stream's rate, as Subscribed says it: {rateHz, periodTicks}, for
  // a Subscribe of which only `events` counts (the kinds of WorldEvent to
  // hand on): the stream is the one the server publishes, and its frames
  // already flow (the constructor subscribed).
  subscribePoses({ events = [] } = {}) {
    this.eventKinds = new Set(events);
    const rateHz = this.stream.rateHz;
    const periodTicks = rateHz > 0 && this.world.tickRateHz > 0
      ? Math.max(1, Math.round(this.world.tickRateHz / rateHz)) : 1;
    return Promise.resolve({ rateHz, periodTicks, encoding: this.stream.encoding });
  }

  // A message on the stream's subject, or a `.key` reply.
  onStreamMessage(error, message, keyReply) {
    if (this.closed) return;
    if (error) {
      if (keyReply) this.gate.keyRequestFailed();
      return;
    }
    let frame;
    try {
      const decoded = this.types.ServerMessage.decode(message.data);
      if (decoded.kind !== "poseFrame") return;
      frame = decoded.poseFrame;
    } catch (decodeError) {
      this.onError(new ProtocolError(`a message on ${this.stream.subject} is not a ServerMessage: ${decodeError.message}`));
      return;
    }
    const verdict = keyReply ? this.gate.keyReply(frame) : this.gate.published(frame);
    if (verdict.requestKey) this.requestKeyFrame();
    if (!verdict.show) return;
    let state;
    try {
      state = this.poses.decode(frame);
    } catch (decodeError) {
      this.onError(new ProtocolError(`frame ${frame.sequence} on ${this.stream.subject}: ${decodeError.message}`));
      return;
    }
    this.latest = state;
    this.frameWaiters = this.frameWaiters.filter((waiter) => {
      if (state.tick < waiter.tick) return true;
      waiter.resolve(state);
      return false;
    });
    this.onPoseFrame(state);
  }

  // Asks for the stream's latest frame as a key frame; the reply joins the
  // stream through the gate.
  requestKeyFrame() {
    this.nc.request(this.keySubject, new Uint8Array(0), { timeout: kRequestTimeoutMs }).then(
      (reply) => this.onStreamMessage(null, reply, true),
      (error) => this.onStreamMessage(error, null, true));
  }

  onEventMessage(error, message) {
    if (this.closed || error) return;
    let decoded;
    try {
      decoded = this.types.ServerMessage.decode(message.data);
    } catch (decodeError) {
      this.onError(new ProtocolError(`a message on ${this.world.eventsSubject} is not a ServerMessage: ${decodeError.message}`));
      return;
    }
    if (decoded.kind !== "worldEvent" || !this.eventKinds.has(decoded.worldEvent.kind)) return;
    this.lastEventTick = Math.max(this.lastEventTick, Number(decoded.worldEvent.tick));
    this.onWorldEvent(decoded.worldEvent);
  }

  // Ends the session: unsubscribes; requests under way reject.
  close() {
    if (this.closed) return;
    this.closed = true;
    for (const subscription of this.subscriptions) subscription.unsubscribe();
    const error = new ProtocolError("the connection is closed");
    for (const waiter of this.frameWaiters) waiter.reject(error);
    this.frameWaiters = [];
  }
}
