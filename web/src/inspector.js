// The selection panel: the selected body's id, name, shape, mass, state
// (world frame, SI) and whether it sleeps, and a line about pushing it.
const vec3 = (v, digits = 3) => `${v[0].toFixed(digits)}, ${v[1].toFixed(digits)}, ${v[2].toFixed(digits)}`;

// A short description of a tumble.v1.Shape.
export function describeShape(shape) {
  const n = (value) => Number(value.toFixed(3));
  switch (shape?.kind) {
    case "box": {
      const h = shape.box.halfExtents;
      return `box, half extents ${n(h.x)} x ${n(h.y)} x ${n(h.z)} m`;
    }
    case "sphere": return `sphere, radius ${n(shape.sphere.radius)} m`;
    case "capsule": return `capsule, radius ${n(shape.capsule.radius)} m, half height ${n(shape.capsule.halfHeight)} m`;
    case "convex": return `convex hull of ${shape.convex.points.length} points`;
    case "points": return `${shape.points.masses.length} point masses`;
    case "plane": return "plane";
    default: return "unknown shape";
  }
}

export class Inspector {
  constructor(element) {
    this.element = element;
    this.element.hidden = true;
    this.note = "";
  }

  // Hides the panel.
  clear() {
    this.element.hidden = true;
    this.element.replaceChildren();
  }

  // Shows body `info` (BodyInfo) with `motion` ("dynamic", "static",
  // "kinematic"), `state` {position, linearVelocity, angularVelocity}
  // arrays from the latest frame, and whether it sleeps.
  show(info, motion, state, asleep) {
    const rows = [
      ["id", String(info.id)],
      ["name", info.name || "(none)"],
      ["shape", describeShape(info.shape)],
      ["motion", motion === "dynamic" ? `dynamic, ${Number(info.mass.toFixed(3))} kg` : motion],
      ["position", `${vec3(state.position)} m`],
      ["velocity", `${vec3(state.linearVelocity)} m/s`],
      ["angular velocity", `${vec3(state.angularVelocity)} rad/s`],
      ["state", asleep ? "asleep" : "awake"],
    ];
    const table = document.createElement("dl");
    for (const [label, value] of rows) {
      const term = document.createElement("dt");
      term.textContent = label;
      const detail = document.createElement("dd");
      detail.textContent = value;
      detail.dataset.field = label;
      table.append(term, detail);
    }
    const parts = [table];
    if (this.note) {
      const note = document.createElement("p");
      note.className = "inspector-note";
      note.textContent = this.note;
      parts.push(note);
    }
    this.element.replaceChildren(...parts);
    this.element.hidden = false;
  }

  // A line shown under the state, e.g. why a push was not sent; "" for none.
  setNote(text) {
    this.note = text;
  }
}
