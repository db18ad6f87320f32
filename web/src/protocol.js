// One protocol session over any byte transport: the Hello/Welcome
// handshake, requests matched to their replies by request_id, and the
// unsolicited PoseFrames and WorldEvents. The transport is a function that
// sends bytes; whatever arrives is handed to receive(). See
// proto/tumble/v1/protocol.proto for the messages.
import { FrameReader, encodeFrame } from "./framing.js";

// The server answered a request with an Error, or the session ended first.
export class ProtocolError extends Error {
  constructor(message, code = 0, codeName = "") {
    super(message);
    this.code = code;          // tumble.v1.ErrorCode, 0 when the session ended
    this.codeName = codeName;  // e.g. "PERMISSION_DENIED"
  }
}

// Every body, page after page: `listPage(startId)` resolves with a
// BodyList, asked for from each BodyList's nextStartId until it is 0.
// Resolves with their BodyInfo in ascending id order; rejects as the pages
// do, or when the pages do not advance. With `field` "joints", the same for
// JointLists.
export async function listPages(listPage, field = "bodies") {
  const items = [];
  let startId = 0;
  for (;;) {
    const page = await listPage(startId);
    for (const item of page[field]) items.push(item);
    if (!page.nextStartId) return items;
    // Ids only grow from page to page; anything else would never end.
    if (page.nextStartId <= startId) {
      throw new ProtocolError(`the server's ${field} pages do not advance: nextStartId ${page.nextStartId}`);
    }
    startId = page.nextStartId;
  }
}

// Every joint with the tick of the listing: {joints: JointInfo[], tick},
// `listPage(startId)` resolving with a JointList. The tick is the first
// page's (a later page's joints may be of a later one).
export async function listJointPages(listPage) {
  let tick = null;
  const joints = await listPages(async (startId) => {
    const page = await listPage(startId);
    tick ??= Number(page.tick);
    return page;
  }, "joints");
  return { joints, tick };
}

// The ServerMessage fields that answer a request, by the oneof's name.
const kReplies = new Set(["ack", "error", "bodyList", "jointList", "subscribed", "stats"]);

export class Session {
  // `types`: protocolTypes(); `send`: (Uint8Array) => void.
  constructor(types, send) {
    this.types = types;
    this.send = send;
    this.reader = new FrameReader();
    this.nextRequestId = 1;
    this.pending = new Map();  // request_id -> {resolve, reject}
    this.helloWaiter = null;   // the Hello's {resolve, reject} until Welcome
    this.closed = false;
    // Unsolicited messages; replace to listen.
    this.onPoseFrame = (frame) => {};
    this.onWorldEvent = (event) => {};
    this.onError = (error) => {};  // an Error that answers no request, or a broken stream
  }

  // Sends Hello with `token` (may be empty); resolves with the Welcome.
  hello(token, clientName = "tumble-viewer") {
    return new Promise((resolve, reject) => {
      this.helloWaiter = { resolve, reject };
      this.write({
        requestId: this.nextRequestId++,
        hello: { protocolVersion: this.types.ProtocolVersion.PROTOCOL_VERSION_CURRENT, clientName, token },
      });
    });
  }

  // Starts the pose stream the viewer draws (a Subscribe) and resolves
  // with its Subscribed.
  subscribePoses(subscribe) {
    return this.request("subscribe", subscribe);
  }

  // Sends one request, e.g. request("applyImpulse", {body: {id: 3}, impulse: {...}}),
  // and resolves with its reply (Ack, BodyList, JointList, Subscribed or Stats), or
  // rejects with a ProtocolError.
  request(kind, payload = {}) {
    if (this.closed) return Promise.reject(new ProtocolError("the connection is closed"));
    const requestId = this.nextRequestId++;
    return new Promise((resolve, reject) => {
      this.pending.set(requestId, { resolve, reject });
      this.write({ requestId, [kind]: payload });
    });
  }

  // Every body, page after page; see listPages().
  listAllBodies() {
    return listPages((startId) => this.request("listBodies", { startId }));
  }

  // One JointList page: at most `maxJoints` (0: as many as fit) from `startId` on.
  listJointPage(startId, maxJoints = 0) {
    return this.request("listJoints", { startId, maxJoints });
  }

  // Every joint and the listing's tick; see listJointPages().
  listAllJoints() {
    return listJointPages((startId) => this.listJointPage(startId));
  }

  write(fields) {
    const { ClientMessage } = this.types;
    this.send(encodeFrame(ClientMessage.encode(ClientMessage.fromObject(fields)).finish()));
  }

  // Feeds bytes that arrived (a Uint8Array) and dispatches every whole
  // message among them.
  receive(chunk) {
    if (this.closed) return;
    this.reader.push(chunk);
    try {
      for (let body = this.reader.next(); body !== null; body = this.reader.next()) {
        this.dispatch(this.types.ServerMessage.decode(body));
      }
    } catch (error) {
      this.close(`the server's byte stream is broken: ${error.message}`);
      this.onError(error);
    }
  }

  dispatch(message) {
    const kind = message.kind;
    if (kind === "welcome") {
      const waiter = this.helloWaiter;
      this.helloWaiter = null;
      if (waiter) waiter.resolve(message.welcome);
    } else if (kind === "poseFrame") {
      this.onPoseFrame(message.poseFrame);
    } else if (kind === "worldEvent") {
      this.onWorldEvent(message.worldEvent);
    } else if (kReplies.has(kind)) {
      const reply = message[kind];
      const requestId = Number(reply.requestId);
      const waiter = this.pending.get(requestId);
      if (kind === "error") {
        const error = new ProtocolError(reply.message, reply.code, this.types.errorName(reply.code));
        if (waiter) {
          this.pending.delete(requestId);
          waiter.reject(error);
        } else if (this.helloWaiter) {
          // The handshake failed (wrong token, wrong version): the server
          // closes the connection after this.
          const hello = this.helloWaiter;
          this.helloWaiter = null;
          hello.reject(error);
        } else {
          this.onError(error);
        }
      } else if (waiter) {
        this.pending.delete(requestId);
        waiter.resolve(reply);
      }
    }
  }

  // Ends the session: every request still waiting is rejected with `reason`.
  close(reason) {
    if (this.closed) return;
    this.closed = true;
    const error = new ProtocolError(reason);
    if (this.helloWaiter) this.helloWaiter.reject(error);
    this.helloWaiter = null;
    for (const waiter of this.pending.values()) waiter.reject(error);
    this.pending.clear();
  }
}
