// three.js geometry for each kind of tumble.v1.Shape, in the body frame
// (origin at the centre of mass, as the server's poses are), except the
// plane, which is infinite and given in world coordinates: it becomes a
// large square already placed in the world.
import * as THREE from "three";
import { ConvexGeometry } from "three/examples/jsm/geometries/ConvexGeometry.js";
import { mergeGeometries } from "three/examples/jsm/utils/BufferGeometryUtils.js";

// Side of the square that stands for an infinite plane, m.
const kGroundSize = 400;

const vec = (v) => new THREE.Vector3(v?.x ?? 0, v?.y ?? 0, v?.z ?? 0);

// {geometry, inWorld, edges}: inWorld when the geometry is in world
// coordinates (a plane) and the body's pose must not move it; edges when
// outlining the creases helps to read it (flat faces).
export function shapeGeometry(shape) {
  switch (shape?.kind) {
    case "box": {
      const h = vec(shape.box.halfExtents);
      return { geometry: new THREE.BoxGeometry(2 * h.x, 2 * h.y, 2 * h.z), inWorld: false, edges: true };
    }
    case "sphere":
      return { geometry: new THREE.SphereGeometry(shape.sphere.radius, 32, 16), inWorld: false, edges: false };
    case "capsule":  // three's capsule also lies along y, length = the cylinder part
      return {
        geometry: new THREE.CapsuleGeometry(shape.capsule.radius, 2 * shape.capsule.halfHeight, 8, 24),
        inWorld: false,
        edges: false,
      };
    case "convex":
      return { geometry: convexGeometry(shape.convex.points.map(vec)), inWorld: false, edges: true };
    case "points":
      return { geometry: pointMassesGeometry(shape.points), inWorld: false, edges: false };
    case "plane":
      return { geometry: planeGeometry(shape.plane), inWorld: true, edges: false };
    default:  // a shape this viewer does not know: a small marker
      return { geometry: new THREE.OctahedronGeometry(0.2), inWorld: false, edges: true };
  }
}

// The hull of `points`, re-centred on its centre of mass (uniform density),
// as the server re-centres it: the body's position is that centre.
function convexGeometry(points) {
  const geometry = new ConvexGeometry(points);
  const position = geometry.getAttribute("position");
  const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
  const centre = new THREE.Vector3();
  let volume = 0;
  // Sum of the tetrahedra (origin, a, b, c): volume det/6, centroid (a+b+c)/4.
  for (let i = 0; i < position.count; i += 3) {
    a.fromBufferAttribute(position, i);
    b.fromBufferAttribute(position, i + 1);
    c.fromBufferAttribute(position, i + 2);
    const v = a.dot(b.clone().cross(c)) / 6;
    volume += v;
    centre.addScaledVector(a.clone().add(b).add(c), v / 4);
  }
  if (volume > 0) geometry.translate(-centre.x / volume, -centre.y / volume, -centre.z / volume);
  return geometry;
}

// A small sphere per point mass (radius growing with the cube root of the
// mass) joined by thin rods to their centre of mass, the body's origin.
function pointMassesGeometry(points) {
  const masses = points.masses;
  const positions = points.positions.map(vec);
  const total = masses.reduce((sum, m) => sum + m, 0);
  const centre = new THREE.Vector3();
  positions.forEach((p, i) => centre.addScaledVector(p, masses[i] / total));
  const parts = [];
  positions.forEach((p, i) => {
    const local = p.clone().sub(centre);
    const ball = new THREE.SphereGeometry(0.08 * Math.cbrt(masses[i]), 16, 8);
    ball.translate(local.x, local.y, local.z);
    parts.push(ball);
    const length = local.length();
    if (length > 1e-6) {
      const rod = new THREE.CylinderGeometry(0.015, 0.015, length, 6);
      rod.translate(0, length / 2, 0);
      rod.applyQuaternion(new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 1, 0), local.normalize()));
      parts.push(rod.toNonIndexed());
    }
  });
  return mergeGeometries(parts.map((part) => (part.index ? part.toNonIndexed() : part)));
}

// A large square on the plane normal . p = offset, facing along the normal.
function planeGeometry(plane) {
  const normal = plane.normal ? vec(plane.normal) : new THREE.Vector3(0, 1, 0);
  if (normal.lengthSq() === 0) normal.set(0, 1, 0);
  normal.normalize();
  const geometry = new THREE.PlaneGeometry(kGroundSize, kGroundSize);
  geometry.applyQuaternion(new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 0, 1), normal));
  const at = normal.clone().multiplyScalar(plane.offset ?? 0);
  geometry.translate(at.x, at.y, at.z);
  return geometry;
}
