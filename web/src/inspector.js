// The selection panel: the selected body's id, name, shape, mass, state
// (world frame, SI) and whether it sleeps, and a line about pushing it; or
// the selected joint's type, bodies, settings and state.
import { kJointTypeNames, kWorldBodyId } from "./joint_view.js";

const vec3 = (v, digits = 3) => `${v[0].toFixed(digits)}, ${v[1].toFixed(digits)}, ${v[2].toFixed(digits)}`;
const n3 = (value) => Number((value ?? 0).toFixed(3));
const degrees = (rad) => `${(((rad ?? 0) * 180) / Math.PI).toFixed(1)}\u00b0`;
const xyz = (v) => [v?.x ?? 0, v?.y ?? 0, v?.z ?? 0];
// A Vec3's length and components, e.g. "9.810 N (0.000, 9.810, 0.000)".
const magnitude = (v, unit) => `${Math.hypot(...xyz(v)).toFixed(3)} ${unit} (${vec3(xyz(v))})`;

// The rows that describe joint `info` (JointInfo) in `state` (JointStates'
// get(): position, speed and motor impulse of the newest pose frame, force
// and torque of the newest listing, at its `forceTick`; or null):
// [label, value] pairs.
export function jointRows(info, state) {
  const type = kJointTypeNames[info.type] ?? `type ${info.type}`;
  const body = (id, name) => (id === kWorldBodyId ? "world" : `${name || "(unnamed)"} (${id})`);
  const angular = info.type === 1 || info.type === 2;  // the position is an angle
  const rows = [
    ["id", String(info.id)],
    ["name", info.name || "(none)"],
    ["type", type],
    ["bodies", `${body(info.bodyA, info.bodyAName)} \u2013 ${body(info.bodyB, info.bodyBName)}`],
  ];
  const position = state?.position ?? 0;
  const speed = state?.speed ?? 0;
  if (angular) {
    rows.push(["angle", `${position.toFixed(3)} rad (${degrees(position)})`]);
    rows.push(["speed", `${speed.toFixed(3)} rad/s`]);
  } else if (info.type !== 4) {
    rows.push([info.type === 5 ? "length" : "position", `${position.toFixed(3)} m`]);
    rows.push(["speed", `${speed.toFixed(3)} m/s`]);
  }
  // Pose frames carry no forces: these are as the joints were listed.
  const listed = state?.forceTick != null ? `, listed at tick ${state.forceTick}` : "";
  rows.push(["force", magnitude(state?.force, "N") + listed]);
  rows.push(["torque", magnitude(state?.torque, "N m") + listed]);
  if (info.limits) {
    const unit = info.type === 3 ? "m" : "rad";
    rows.push(["limits", `${n3(info.limits.lower)} to ${n3(info.limits.upper)} ${unit}`]);
  }
  if (info.coneLimit != null) rows.push(["cone", `${n3(info.coneLimit)} rad (${degrees(info.coneLimit)})`]);
  if (info.type === 5) rows.push(["range", `${n3(info.minLength)} to ${n3(info.maxLength)} m`]);
  if (info.type === 2 || info.type === 3) {
    rows.push(["motor", describeMotor(info.motor, info.type)]);
    rows.push(["motor impulse", `${(state?.motorImpulse ?? 0).toFixed(3)} ${info.type === 2 ? "N m s" : "N s"}`]);
  }
  if (info.breakForce != null || info.breakTorque != null) {
    const parts = [];
    if (info.breakForce != null) parts.push(`${n3(info.breakForce)} N`);
    if (info.breakTorque != null) parts.push(`${n3(info.breakTorque)} N m`);
    rows.push(["breaks above", parts.join(", ")]);
  }
  return rows;
}

// A hinge's or slider's JointMotorSpec in a few words; "off" when absent.
export function describeMotor(motor, type) {
  if (!motor || motor.target === undefined) return "off";
  const hinge = type === 2;
  const most = hinge ? `${n3(motor.maxTorque)} N m` : `${n3(motor.maxForce)} N`;
  if (motor.target === "speed") return `speed ${n3(motor.speed)} ${hinge ? "rad/s" : "m/s"}, at most ${most}`;
  return `position ${n3(motor.position)} ${hinge ? "rad" : "m"}, at most ${most}`;
}

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
    this.showRows([
      ["id", String(info.id)],
      ["name", info.name || "(none)"],
      ["shape", describeShape(info.shape)],
      ["motion", motion === "dynamic" ? `dynamic, ${Number(info.mass.toFixed(3))} kg` : motion],
      ["position", `${vec3(state.position)} m`],
      ["velocity", `${vec3(state.linearVelocity)} m/s`],
      ["angular velocity", `${vec3(state.angularVelocity)} rad/s`],
      ["state", asleep ? "asleep" : "awake"],
    ]);
  }

  // Shows joint `info` (JointInfo) in `state` (see jointRows).
  showJoint(info, state) {
    this.showRows(jointRows(info, state));
  }

  // The panel as a list of [label, value] rows, and the note under them.
  showRows(rows) {
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
