// Picking and pushing with the pointer. A click on a joint's dot selects
// the joint, a click on a body the body (a click on nothing clears the
// selection). Pressing on a dynamic body and dragging pulls a line from the
// grabbed point across the plane through it that faces the camera;
// releasing sends an impulse at that point, along the line, of the body's
// mass times a speed that grows with the line's length. The camera does not
// orbit while a body is dragged.
import * as THREE from "three";

// Speed change a push aims for per metre dragged, 1/s, and at most, m/s.
export const kPushGainPerSecond = 3;
export const kMaxPushSpeed = 15;
// A press that moves less than this many CSS pixels is a click.
const kClickSlopPx = 4;

// The impulse (N s, world frame, THREE.Vector3) for a drag of `drag`
// metres on a body of `mass` kg.
export function pushImpulse(drag, mass) {
  const speed = Math.min(drag.length() * kPushGainPerSecond, kMaxPushSpeed);
  return drag.lengthSq() > 0 ? drag.clone().normalize().multiplyScalar(speed * mass) : new THREE.Vector3();
}

export class PointerControl {
  // `view`: WorldView. `callbacks`: onSelect(id | null), canPush(id) ->
  // bool, onPush(id, impulse, point) with world-frame THREE.Vector3s,
  // pickJoint(clientX, clientY) -> id | null and onSelectJoint(id).
  constructor(view, callbacks) {
    this.view = view;
    this.callbacks = callbacks;
    this.press = null;  // {x, y, id, grab} while a button is down
    this.line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
                               new THREE.LineBasicMaterial({ color: 0xffd34d, depthTest: false }));
    this.line.renderOrder = 1;
    this.line.visible = false;
    view.scene.add(this.line);

    const canvas = view.renderer.domElement;
    // In the capture phase, so a press on a body turns the orbit controls
    // off before they see it.
    canvas.addEventListener("pointerdown", (event) => this.down(event), { capture: true });
    canvas.addEventListener("pointermove", (event) => this.move(event));
    canvas.addEventListener("pointerup", (event) => this.up(event));
    canvas.addEventListener("pointercancel", () => this.cancel());
  }

  down(event) {
    if (event.button !== 0) return;
    const hit = this.view.pick(event.clientX, event.clientY);
    this.press = { x: event.clientX, y: event.clientY, id: hit?.id ?? null, grab: null };
    if (!hit || !this.callbacks.canPush(hit.id)) return;
    // Grab: the point in the body's frame, so it is pushed where it was
    // taken however the body moved since, and the drag plane.
    const mesh = this.view.bodies.get(hit.id).mesh;
    const normal = this.view.camera.getWorldDirection(new THREE.Vector3());
    this.press.grab = {
      local: mesh.worldToLocal(hit.point.clone()),
      start: hit.point.clone(),
      end: hit.point.clone(),
      plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, hit.point),
    };
    this.view.controls.enabled = false;
    event.target.setPointerCapture?.(event.pointerId);
  }

  move(event) {
    const grab = this.press?.grab;
    if (!grab) return;
    const ray = this.view.rayAt(event.clientX, event.clientY);
    if (ray.intersectPlane(grab.plane, grab.end) === null) return;  // the pointer left the plane's side
    this.line.geometry.setFromPoints([grab.start, grab.end]);
    this.line.visible = true;
  }

  up(event) {
    const press = this.press;
    if (!press) return;
    this.cancel();
    const moved = Math.hypot(event.clientX - press.x, event.clientY - press.y) >= kClickSlopPx;
    if (!moved) {
      const joint = this.callbacks.pickJoint?.(event.clientX, event.clientY) ?? null;
      if (joint !== null) this.callbacks.onSelectJoint(joint);
      else this.callbacks.onSelect(press.id);
      return;
    }
    if (!press.grab) return;  // an orbit of the camera
    const body = this.view.bodies.get(press.id);
    if (!body) return;  // removed meanwhile
    const impulse = pushImpulse(press.grab.end.clone().sub(press.grab.start), body.info.mass);
    const point = body.mesh.localToWorld(press.grab.local.clone());
    this.callbacks.onSelect(press.id);
    if (impulse.lengthSq() > 0) this.callbacks.onPush(press.id, impulse, point);
  }

  cancel() {
    this.press = null;
    this.line.visible = false;
    this.view.controls.enabled = true;
  }
}
