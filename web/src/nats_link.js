// The page's link to a world through NATS's own WebSocket listener, in
// place of Connection's WebSocket to tumbled: the same listeners (onState,
// onSession, onClose), a NatsSession per session. The NATS client reconnects
// by itself (to any server of the cluster it learnt of); each time it is
// connected again, the world is looked up afresh and a new session begins,
// since the server that answers may have restarted meanwhile.
import { NatsSession, findWorld } from "./nats_session.js";

// While the world cannot be found or the first connection fails, the page
// tries again after this long, doubling up to the maximum, ms.
const kMinBackoffMs = 500;
const kMaxBackoffMs = 8000;

// What NATS says of a user it does not know (nats-server's -ERR text).
const isAuthorizationError = (error) =>
  error?.name === "AuthorizationError" || /authorization violation/i.test(error?.message ?? "");

export class NatsLink {
  // `connect`: @nats-io/nats-core's wsconnect (or another transport's
  // connect); `options`: {servers (ws:// URLs, comma separated), world,
  // stream (empty: the world's first), user, pass, token}; `types`:
  // protocolTypes().
  constructor(connect, options, types) {
    this.connect = connect;
    this.options = options;
    this.types = types;
    this.nc = null;
    this.session = null;
    this.backoffMs = kMinBackoffMs;
    this.failure = null;  // {attempt, why} while retrying
    this.generation = 0;  // counts sessions begun, so a late one is dropped
    // Shown when an observer tries to push.
    this.pushNote = `NATS does not let this user publish to tumble.v1.${options.world}.rpc: ` +
                    "pushing needs a controller user (#nats=...&user=USER&pass=PASSWORD).";
    // Listeners, as Connection's.
    this.onState = (state, detail) => {};
    this.onSession = (session, welcome) => {};
    this.onClose = () => {};
  }

  start() {
    this.dial();
  }

  // The first connection; failures are retried here, later ones by the client.
  async dial() {
    const servers = this.options.servers.split(",").map((url) => url.trim()).filter(Boolean);
    if (this.failure) this.onState("reconnecting", this.failure);
    else this.onState("connecting", servers.join(", "));
    const { user, pass, token } = this.options;
    try {
      this.nc = await this.connect({
        servers,
        name: "tumble-viewer",
        ...(user ? { user, pass } : {}),
        ...(token ? { token } : {}),
        maxReconnectAttempts: -1,  // reconnect for as long as the page is open
        reconnectTimeWait: 1000,
      });
    } catch (error) {
      if (isAuthorizationError(error)) {
        this.onState("refused", `NATS: ${error.message}`);
        return;
      }
      this.retry(() => this.dial(), `cannot reach NATS at ${servers.join(", ")}`);
      return;
    }
    this.watch(this.nc);
    this.begin();
  }

  // Follows the client's own reconnection.
  async watch(nc) {
    nc.closed().then((error) => {
      this.end();
      this.onState("refused", `the NATS connection closed${error ? `: ${error.message}` : ""}`);
    });
    let attempt = 0;
    for await (const status of nc.status()) {
      if (status.type === "disconnect") {
        this.end();
        attempt = 0;
        this.onState("reconnecting", { attempt, why: "the NATS server went away" });
      } else if (status.type === "reconnecting") {
        this.onState("reconnecting", { attempt: attempt++, why: "the NATS server went away" });
      } else if (status.type === "reconnect") {
        this.failure = null;
        this.backoffMs = kMinBackoffMs;
        this.begin();
      }
    }
  }

  // Finds the world and says hello; a new session once both answered.
  async begin() {
    const generation = ++this.generation;
    let session = null;
    try {
      const world = await findWorld(this.nc, this.types, this.options.world);
      if (generation !== this.generation) return;
      session = new NatsSession(this.nc, this.types, world, this.options.stream);
      const welcome = await session.hello();
      if (generation !== this.generation) {
        session.close();
        return;
      }
      this.session = session;
      this.failure = null;
      this.backoffMs = kMinBackoffMs;
      this.onState("connected", this.types.roleName(welcome.role));
      this.onSession(session, welcome);
    } catch (error) {
      session?.close();
      if (generation !== this.generation || this.nc.isClosed()) return;
      this.retry(() => this.begin(), error.message);
    }
  }

  // The session ends (the NATS link went down).
  end() {
    ++this.generation;
    if (!this.session) return;
    this.session.close();
    this.session = null;
    this.onClose();
  }

  retry(again, why) {
    this.failure = { attempt: (this.failure?.attempt ?? 0) + 1, why };
    this.onState("retrying", { seconds: this.backoffMs / 1000, why });
    const generation = this.generation;
    setTimeout(() => {
      if (generation === this.generation) again();
    }, this.backoffMs);
    this.backoffMs = Math.min(this.backoffMs * 2, kMaxBackoffMs);
  }
}
