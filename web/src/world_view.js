// The 3D scene: renderer, camera with orbit controls, lights, ground grid,
// and one mesh per body, drawn by its shape. Dynamic bodies get a colour of
// their own, static ones grey and kinematic ones amber; a sleeping body is
// dimmer, the selected one glows. Poses are world frame, +Y up, metres, as
// the server sends them.
import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { bodyMotion } from "./body_motion.js";
import { makeGrid } from "./grid.js";
import { shapeGeometry } from "./shapes.js";

const kStaticColor = new THREE.Color(0x8d939c);
const kKinematicColor = new THREE.Color(0xd9a63a);
const kGroundColor = new THREE.Color(0x3b4350);
const kBackground = new THREE.Color(0x1d2127);
const kSelectedGlow = new THREE.Color(0x2f6bff);
const kAsleepDimming = 0.55;  // colour factor of a sleeping body

// A dynamic body's own colour, spread over hues by its id.
function dynamicColor(id) {
  return new THREE.Color().setHSL(((id * 0.618034) % 1 + 1) % 1, 0.55, 0.55);
}

export class WorldView {
  // `container`: the element the canvas fills.
  constructor(container) {
    this.container = container;
    // preserveDrawingBuffer keeps the last picture readable (drawImage of the
    // canvas), which the browser test uses to check what was drawn.
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.setClearColor(kBackground);
    container.appendChild(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.scene.fog = new THREE.Fog(kBackground, 60, 160);
    this.camera = new THREE.PerspectiveCamera(50, 1, 0.05, 500);
    this.camera.position.set(8, 6, 12);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;
    this.controls.target.set(0, 1, 0);

    this.scene.add(new THREE.HemisphereLight(0xdde6ff, 0x30302a, 1.4));
    const sun = new THREE.DirectionalLight(0xffffff, 2.0);
    sun.position.set(6, 12, 8);
    this.scene.add(sun);
    this.scene.add(makeGrid());

    this.bodies = new Map();  // id -> {info, motion, mesh, material, asleep, inWorld}
    this.selectedId = null;
    this.framed = false;  // the camera was aimed at the bodies once
    this.raycaster = new THREE.Raycaster();
    // A box drawn around the selected body, a little larger than it so its
    // lines are not hidden in the body's faces.
    this.selectionBox = new THREE.Box3Helper(new THREE.Box3(), 0xffd34d);
    this.selectionBox.visible = false;
    this.scene.add(this.selectionBox);

    this.resize();
    window.addEventListener("resize", () => this.resize());
  }

  resize() {
    const width = this.container.clientWidth || window.innerWidth;
    const height = this.container.clientHeight || window.innerHeight;
    this.renderer.setSize(width, height);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
  }

  // Replaces the bodies with those of a BodyList (BodyInfo[]), keeping the
  // meshes of bodies that are still there with the same shape.
  setBodies(infos) {
    const seen = new Set();
    for (const info of infos) {
      seen.add(info.id);
      const old = this.bodies.get(info.id);
      if (old && JSON.stringify(old.info.shape) === JSON.stringify(info.shape)) {
        old.info = info;
        old.asleep = info.asleep;
        this.applyColor(old);
        continue;
      }
      if (old) this.removeBody(info.id);
      this.addBody(info);
    }
    for (const id of [...this.bodies.keys()]) if (!seen.has(id)) this.removeBody(id);
    if (this.selectedId !== null && !this.bodies.has(this.selectedId)) this.select(null);
    if (!this.framed && infos.length) {
      this.frameBodies();
      this.framed = true;
    }
  }

  addBody(info) {
    const { geometry, inWorld, edges } = shapeGeometry(info.shape);
    const motion = bodyMotion(info);
    const material = new THREE.MeshStandardMaterial({
      roughness: inWorld ? 0.95 : 0.55,
      metalness: 0.05,
      flatShading: info.shape?.kind === "convex",
      // The ground sits a hair behind the grid so the grid always shows.
      polygonOffset: inWorld,
      polygonOffsetFactor: 1,
      polygonOffsetUnits: 1,
    });
    const mesh = new THREE.Mesh(geometry, material);
    mesh.userData.bodyId = info.id;
    if (edges) {
      const lines = new THREE.LineSegments(new THREE.EdgesGeometry(geometry, 25),
                                           new THREE.LineBasicMaterial({ color: 0x14171c, transparent: true, opacity: 0.5 }));
      lines.raycast = () => {};  // picking hits the faces
      mesh.add(lines);
    }
    const body = { info, motion, mesh, material, asleep: info.asleep, inWorld, baseColor: null };
    body.baseColor = inWorld ? kGroundColor : motion === "static" ? kStaticColor
                   : motion === "kinematic" ? kKinematicColor : dynamicColor(info.id);
    if (!inWorld) this.placeMesh(mesh, info.position, info.orientation);
    this.bodies.set(info.id, body);
    this.applyColor(body);
    this.scene.add(mesh);
  }

  removeBody(id) {
    const body = this.bodies.get(id);
    if (!body) return;
    this.scene.remove(body.mesh);
    body.mesh.traverse((object) => {
      object.geometry?.dispose();
      object.material?.dispose();
    });
    this.bodies.delete(id);
  }

  placeMesh(mesh, p, q) {
    mesh.position.set(p?.x ?? 0, p?.y ?? 0, p?.z ?? 0);
    mesh.quaternion.set(q?.x ?? 0, q?.y ?? 0, q?.z ?? 0, q?.w ?? 1);
  }

  // Moves body `id` to position p[3] and orientation q[4] (w, x, y, z).
  setPose(id, p, q) {
    const body = this.bodies.get(id);
    if (!body || body.inWorld) return;
    body.mesh.position.set(p[0], p[1], p[2]);
    body.mesh.quaternion.set(q[1], q[2], q[3], q[0]);
  }

  setAsleep(id, asleep) {
    const body = this.bodies.get(id);
    if (!body) return;
    body.asleep = asleep;
    this.applyColor(body);
  }

  select(id) {
    const previous = this.bodies.get(this.selectedId);
    this.selectedId = this.bodies.has(id) ? id : null;
    if (previous) this.applyColor(previous);
    const body = this.bodies.get(this.selectedId);
    if (body) this.applyColor(body);
    this.selectionBox.visible = body !== undefined && !body.inWorld;
  }

  applyColor(body) {
    body.material.color.copy(body.baseColor).multiplyScalar(body.asleep ? kAsleepDimming : 1);
    body.material.emissive.copy(body.info.id === this.selectedId ? kSelectedGlow : new THREE.Color(0));
    body.material.emissiveIntensity = body.info.id === this.selectedId ? 0.6 : 0;
  }

  // Aims the camera at the bodies that are not the ground.
  frameBodies() {
    const box = new THREE.Box3();
    for (const body of this.bodies.values()) if (!body.inWorld) box.expandByObject(body.mesh);
    if (box.isEmpty()) return;
    const centre = box.getCenter(new THREE.Vector3());
    const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1);
    const distance = radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2)) * 0.8;
    this.controls.target.copy(centre);
    this.camera.position.copy(centre).add(new THREE.Vector3(0.45, 0.45, 0.77).normalize().multiplyScalar(distance));
    this.camera.far = Math.max(500, distance * 10);
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  // The ray from the camera through page point (clientX, clientY).
  rayAt(clientX, clientY) {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1,
                                  -((clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    return this.raycaster.ray;
  }

  // The body under page point (clientX, clientY), not counting the ground:
  // {id, point (world, THREE.Vector3)} or null.
  pick(clientX, clientY) {
    this.rayAt(clientX, clientY);
    const meshes = [...this.bodies.values()].filter((body) => !body.inWorld).map((body) => body.mesh);
    const hit = this.raycaster.intersectObjects(meshes, false)[0];
    return hit ? { id: hit.object.userData.bodyId, point: hit.point.clone() } : null;
  }

  // Where body `id`'s centre is drawn, in CSS pixels of the page, or null.
  screenPosition(id) {
    const body = this.bodies.get(id);
    if (!body || body.inWorld) return null;
    const ndc = body.mesh.position.clone().project(this.camera);
    const rect = this.renderer.domElement.getBoundingClientRect();
    return { x: rect.left + ((ndc.x + 1) / 2) * rect.width, y: rect.top + ((1 - ndc.y) / 2) * rect.height };
  }

  render() {
    this.controls.update();
    if (this.selectionBox.visible) {
      this.selectionBox.box.setFromObject(this.bodies.get(this.selectedId).mesh).expandByScalar(0.04);
    }
    this.renderer.render(this.scene, this.camera);
  }
}
