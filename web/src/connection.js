// The WebSocket to tumbled's /ws, one protocol Session per socket, and
// reconnection with backoff when the server goes away. The server speaks
// exactly its TCP byte stream over binary messages.
import { Session } from "./protocol.js";

// Reconnection waits this long after the first failure, doubling up to the
// maximum, and starts again from the minimum after a successful handshake.
const kMinBackoffMs = 500;
const kMaxBackoffMs = 8000;

export class Connection {
  // `url`: ws://host/ws; `types`: protocolTypes(); `token`: sent in Hello.
  constructor(url, types, token) {
    this.url = url;
    this.types = types;
    this.token = token;
    this.backoffMs = kMinBackoffMs;
    this.failure = null;  // {attempt, why} while reconnecting
    this.socket = null;
    this.session = null;
    // Shown when an observer tries to push.
    this.pushNote = "Pushing needs a controller token: open the page as /#token=TOKEN.";
    // Listeners; replace to listen.
    // onState(state, detail): "connecting" (the first try), "connected"
    // (detail: the role), "retrying" (waiting; detail: {seconds, why}),
    // "reconnecting" (trying again; detail: {attempt, why}), "refused" (the
    // handshake failed, a wrong token, say; detail: the server's reason; no
    // retry).
    this.onState = (state, detail) => {};
    // onSession(session, welcome): a new session is ready after its Welcome.
    this.onSession = (session, welcome) => {};
    // onClose(): the session ended (before any retry).
    this.onClose = () => {};
  }

  start() {
    this.open();
  }

  open() {
    if (this.failure) this.onState("reconnecting", this.failure);
    else this.onState("connecting", this.url);
    const socket = new WebSocket(this.url);
    socket.binaryType = "arraybuffer";
    const session = new Session(this.types, (bytes) => {
      if (socket.readyState === WebSocket.OPEN) socket.send(bytes);
    });
    this.socket = socket;
    this.session = session;
    let refused = null;  // the handshake's error, when the server said no
    let ready = false;   // Welcome came

    socket.onopen = () => {
      session.hello(this.token).then(
        (welcome) => {
          ready = true;
          this.backoffMs = kMinBackoffMs;
          this.failure = null;
          this.onState("connected", this.types.roleName(welcome.role));
          this.onSession(session, welcome);
        },
        (error) => {
          if (error.code) refused = error;  // an Error from the server, not a closed socket
        });
    };
    socket.onmessage = (event) => {
      session.receive(new Uint8Array(event.data));
      if (session.closed) socket.close();  // the byte stream broke: start afresh
    };
    socket.onerror = () => {};  // onclose follows and says what to do
    socket.onclose = (event) => {
      session.close("the connection closed");
      if (ready) this.onClose();
      if (refused) {
        this.onState("refused", `${refused.codeName}: ${refused.message}`);
        return;
      }
      // A server that was there and went away stays the reason through the
      // tries that follow.
      const why = event.reason || (ready ? "the server went away" : this.failure?.why ?? "cannot reach the server");
      this.failure = { attempt: (this.failure?.attempt ?? 0) + 1, why };
      this.onState("retrying", { seconds: this.backoffMs / 1000, why });
      setTimeout(() => this.open(), this.backoffMs);
      this.backoffMs = Math.min(this.backoffMs * 2, kMaxBackoffMs);
    };
  }
}
