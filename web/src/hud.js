// The corner display: connection state and role, tick, sim time, the
// real-time factor, body and joint counts and stream rate.
const fixed = (value, digits) => (Number.isFinite(value) ? value.toFixed(digits) : "-");

export class Hud {
  // `element`: the HUD's box; its rows are made here.
  constructor(element) {
    this.element = element;
    this.rows = {};
    for (const [key, label] of [["connection", "server"], ["role", "role"], ["tick", "tick"], ["time", "sim time"],
                                ["rtf", "real-time factor"], ["bodies", "bodies"], ["joints", "joints"],
                                ["stream", "stream"]]) {
      const row = document.createElement("div");
      row.className = "hud-row";
      const name = document.createElement("span");
      name.className = "hud-label";
      name.textContent = label;
      const value = document.createElement("span");
      value.className = "hud-value";
      value.dataset.hud = key;
      value.textContent = "-";
      row.append(name, value);
      element.append(row);
      this.rows[key] = value;
    }
    this.setConnection("connecting", "");
  }

  // state and detail as Connection.onState gives them.
  setConnection(state, detail) {
    const text = {
      connecting: "connecting...",
      connected: "connected",
      retrying: `${detail?.why}; retrying in ${fixed(detail?.seconds, 1)} s`,
      reconnecting: `${detail?.why}; reconnecting (try ${detail?.attempt + 1})...`,
      refused: `refused: ${detail}`,
    }[state];
    this.rows.connection.textContent = text;
    this.element.dataset.connection = state;
  }

  setRole(role) {
    this.rows.role.textContent = role ? role.replace(/^ROLE_/, "").toLowerCase() : "-";
  }

  // The latest frame's tick and sim time (s).
  setClock(tick, simTime) {
    this.rows.tick.textContent = String(tick);
    this.rows.time.textContent = `${fixed(simTime, 2)} s`;
  }

  // From a Stats reply.
  setStats(stats) {
    this.rows.rtf.textContent = stats.paused ? "paused" : fixed(stats.realTimeFactor, 2);
    this.rows.bodies.textContent = `${stats.bodies} (${stats.bodiesAsleep} asleep)`;
  }

  // How many joints the world has.
  setJoints(count) {
    this.rows.joints.textContent = String(count);
  }

  setStream(rateHz, periodTicks) {
    this.rows.stream.textContent = `${fixed(rateHz, 1)} Hz (every ${periodTicks} ticks)`;
  }
}
