// The joints, drawn over the bodies: a dot at each body's anchor with a
// line to the body's centre, the axis of a hinge, slider or coned ball
// joint as a short line through body A's anchor, and a line between the
// anchors of a distance joint. Each joint
// has its type's colour; the selected one is yellow with larger dots.
// Anchors and axes are kept in their bodies' frames, so they follow the
// meshes as they are drawn.
import * as THREE from "three";

// JointInfo.body_a or body_b when the joint holds a body to the world.
export const kWorldBodyId = 4294967294;

// JointType numbers (proto/tumble/v1/scene.proto) and their names.
export const kJointTypeNames = { 1: "ball", 2: "hinge", 3: "slider", 4: "fixed", 5: "distance" };
const kTypeColors = { 1: 0x4fd1c5, 2: 0xff7a59, 3: 0xb388ff, 4: 0xcfd6df, 5: 0x7ee787 };
const kSelectedColor = 0xffd34d;
// Dots, CSS pixels across, and how near a click must be to pick one.
const kDotPx = 7;
const kSelectedDotPx = 11;
const kPickPx = 8;
// Half the length of a drawn axis, m.
const kAxisHalfLength = 0.3;

const vector = (v) => new THREE.Vector3(v?.x ?? 0, v?.y ?? 0, v?.z ?? 0);

// Whether a joint of this JointInfo has an axis worth drawing.
function drawsAxis(info) {
  return info.type === 2 || info.type === 3 || (info.type === 1 && info.coneLimit != null);
}

export class JointView {
  // `view`: the WorldView whose scene, camera and body meshes are used.
  constructor(view) {
    this.view = view;
    this.joints = new Map();  // id -> {info, localA, localB, localAxis, dots, lines}
    this.selectedId = null;
  }

  // Replaces the joints with those of a JointList (JointInfo[]), whose
  // world-frame anchors and axis are at the poses poseOf(bodyId) gives,
  // {position[3], orientation[4] (w, x, y, z)} or null for the mesh's
  // pose. A joint already drawn keeps its frames, a joint's anchors never
  // moving in its bodies' frames, unless `keepFrames` is false (the first
  // listing of a session: the server may hold another world now).
  setJoints(infos, poseOf, keepFrames = true) {
    const seen = new Set();
    for (const info of infos) {
      seen.add(info.id);
      const old = this.joints.get(info.id);
      if (keepFrames && old && old.info.type === info.type && old.info.bodyA === info.bodyA &&
          old.info.bodyB === info.bodyB) {
        old.info = info;
        continue;
      }
      if (old) this.removeJoint(info.id);
      this.addJoint(info, poseOf);
    }
    for (const id of [...this.joints.keys()]) if (!seen.has(id)) this.removeJoint(id);
    if (!this.joints.has(this.selectedId)) this.select(null);
  }

  // Forgets every joint (a reset: ids may mean other joints now).
  clear() {
    for (const id of [...this.joints.keys()]) this.removeJoint(id);
    this.select(null);
  }

  addJoint(info, poseOf) {
    // The inverse of body `id`'s pose then: world frame -> its frame.
    const toBody = (id) => {
      if (id === kWorldBodyId) return new THREE.Matrix4();
      const pose = poseOf(id);
      const mesh = this.view.bodies.get(id)?.mesh;
      const position = pose ? new THREE.Vector3(...pose.position) : mesh?.position.clone() ?? new THREE.Vector3();
      const [w, x, y, z] = pose ? pose.orientation : [];
      const orientation = pose ? new THREE.Quaternion(x, y, z, w) : mesh?.quaternion.clone() ?? new THREE.Quaternion();
      return new THREE.Matrix4().compose(position, orientation, new THREE.Vector3(1, 1, 1)).invert();
    };
    const fromWorldA = toBody(info.bodyA);
    const color = kTypeColors[info.type] ?? 0xffffff;
    const overlay = (object) => {
      object.renderOrder = 2;  // over the bodies, like the drag line
      object.raycast = () => {};
      return object;
    };
    const dots = overlay(new THREE.Points(
      new THREE.BufferGeometry().setAttribute("position", new THREE.BufferAttribute(new Float32Array(6), 3)),
      new THREE.PointsMaterial({ color, size: kDotPx, sizeAttenuation: false, depthTest: false, transparent: true })));
    // Three segments: the axis or the distance line, and each anchor to its body's centre.
    const lines = overlay(new THREE.LineSegments(
      new THREE.BufferGeometry().setAttribute("position", new THREE.BufferAttribute(new Float32Array(18), 3)),
      new THREE.LineBasicMaterial({ color, depthTest: false, transparent: true, opacity: 0.9 })));
    const joint = {
      info,
      localA: vector(info.anchorA).applyMatrix4(fromWorldA),
      localB: vector(info.anchorB).applyMatrix4(toBody(info.bodyB)),
      localAxis: vector(info.axis).transformDirection(fromWorldA),
      dots,
      lines,
      anchorA: new THREE.Vector3(),
      anchorB: new THREE.Vector3(),
    };
    this.joints.set(info.id, joint);
    this.view.scene.add(dots, lines);
    this.paint(joint);
    this.place(joint);
  }

  removeJoint(id) {
    const joint = this.joints.get(id);
    if (!joint) return;
    for (const object of [joint.dots, joint.lines]) {
      this.view.scene.remove(object);
      object.geometry.dispose();
      object.material.dispose();
    }
    this.joints.delete(id);
  }

  select(id) {
    const previous = this.joints.get(this.selectedId);
    this.selectedId = this.joints.has(id) ? id : null;
    if (previous) this.paint(previous);
    const joint = this.joints.get(this.selectedId);
    if (joint) this.paint(joint);
  }

  paint(joint) {
    const selected = joint.info.id === this.selectedId;
    for (const object of [joint.dots, joint.lines]) {
      object.material.color.set(selected ? kSelectedColor : kTypeColors[joint.info.type] ?? 0xffffff);
    }
    joint.dots.material.size = selected ? kSelectedDotPx : kDotPx;
  }

  // Body `id`'s mesh, or null for the world (or a body not drawn).
  meshOf(id) {
    return id === kWorldBodyId ? null : this.view.bodies.get(id)?.mesh ?? null;
  }

  // Where a point of body `id`'s frame is drawn now, into `out`.
  worldPoint(id, local, out) {
    out.copy(local);
    const mesh = this.meshOf(id);
    return mesh ? out.applyQuaternion(mesh.quaternion).add(mesh.position) : out;
  }

  // Moves the drawing of `joint` to where its bodies are drawn.
  place(joint) {
    const { info, anchorA, anchorB } = joint;
    this.worldPoint(info.bodyA, joint.localA, anchorA);
    this.worldPoint(info.bodyB, joint.localB, anchorB);
    const dots = joint.dots.geometry.attributes.position;
    dots.setXYZ(0, anchorA.x, anchorA.y, anchorA.z);
    dots.setXYZ(1, anchorB.x, anchorB.y, anchorB.z);
    dots.needsUpdate = true;
    joint.dots.geometry.computeBoundingSphere();
    const lines = joint.lines.geometry.attributes.position;
    const meshA = this.meshOf(info.bodyA);
    if (info.type === 5) {
      lines.setXYZ(0, anchorA.x, anchorA.y, anchorA.z);
      lines.setXYZ(1, anchorB.x, anchorB.y, anchorB.z);
    } else if (drawsAxis(info)) {
      const axis = joint.localAxis.clone();
      if (meshA) axis.applyQuaternion(meshA.quaternion);
      axis.multiplyScalar(kAxisHalfLength);
      lines.setXYZ(0, anchorA.x - axis.x, anchorA.y - axis.y, anchorA.z - axis.z);
      lines.setXYZ(1, anchorA.x + axis.x, anchorA.y + axis.y, anchorA.z + axis.z);
    } else {
      lines.setXYZ(0, anchorA.x, anchorA.y, anchorA.z);
      lines.setXYZ(1, anchorA.x, anchorA.y, anchorA.z);
    }
    // The world's anchor has no centre: a segment of no length.
    for (const [k, mesh, anchor] of [[2, meshA, anchorA], [4, this.meshOf(info.bodyB), anchorB]]) {
      const centre = mesh?.position ?? anchor;
      lines.setXYZ(k, anchor.x, anchor.y, anchor.z);
      lines.setXYZ(k + 1, centre.x, centre.y, centre.z);
    }
    lines.needsUpdate = true;
    joint.lines.geometry.computeBoundingSphere();
  }

  // Moves every joint's drawing to its bodies' drawn poses.
  update() {
    for (const joint of this.joints.values()) this.place(joint);
  }

  // How many joints are in the scene with their dots.
  drawnCount() {
    let count = 0;
    for (const joint of this.joints.values()) if (joint.dots.parent === this.view.scene && joint.dots.visible) ++count;
    return count;
  }

  // Where a world point is on the page, {x, y} CSS pixels, or null behind the camera.
  screenPoint(point) {
    const ndc = point.clone().project(this.view.camera);
    if (ndc.z > 1) return null;
    const rect = this.view.renderer.domElement.getBoundingClientRect();
    return { x: rect.left + ((ndc.x + 1) / 2) * rect.width, y: rect.top + ((1 - ndc.y) / 2) * rect.height };
  }

  // The id of the joint with a dot nearest page point (clientX, clientY),
  // within kPickPx, or null.
  pick(clientX, clientY) {
    let best = null;
    let bestPx = kPickPx;
    for (const [id, joint] of this.joints) {
      for (const anchor of [joint.anchorA, joint.anchorB]) {
        const at = this.screenPoint(anchor);
        const px = at ? Math.hypot(at.x - clientX, at.y - clientY) : Infinity;
        if (px <= bestPx) {
          best = id;
          bestPx = px;
        }
      }
    }
    return best;
  }
}
