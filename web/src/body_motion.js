// How a body moves, as the viewer names it, from the server's BodyInfo:
// its `motion` (tumble.v1.Motion, decoded as the enum's number).
const kMotionNames = ["dynamic", "static", "kinematic"];  // MOTION_DYNAMIC = 0, MOTION_STATIC = 1, MOTION_KINEMATIC = 2

// "dynamic", "static" or "kinematic"; a value this viewer does not know is
// shown as dynamic, the wire's default.
export function bodyMotion(info) {
  return kMotionNames[info.motion] ?? "dynamic";
}
