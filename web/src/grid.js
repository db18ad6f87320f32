// The ground grid: lines every metre on y = 0, brighter every five, within
// ±half metres of the origin. Each line is drawn as short segments rather
// than one long one: some renderers (SwiftShader, the CPU renderer of
// headless browsers) drop a whole line when one end is behind the camera,
// which would leave the grid blank around the viewer.
import * as THREE from "three";

// half: extent, m; segment: length of one piece, m.
export function makeGrid(half = 50, segment = 2) {
  const minor = new THREE.Color(0x646d7b);
  const major = new THREE.Color(0x8d97a6);
  const positions = [];
  const colors = [];
  for (let i = -half; i <= half; ++i) {
    const color = i % 5 === 0 ? major : minor;
    for (let s = -half; s < half; s += segment) {
      positions.push(i, 0, s, i, 0, s + segment, s, 0, i, s + segment, 0, i);  // along z, then along x
      for (let k = 0; k < 4; ++k) colors.push(color.r, color.g, color.b);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.Float32BufferAttribute(positions, 3));
  geometry.setAttribute("color", new THREE.Float32BufferAttribute(colors, 3));
  return new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ vertexColors: true, transparent: true, opacity: 0.65 }));
}
