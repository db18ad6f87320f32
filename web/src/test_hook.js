// window.tumbleViewer: a small read-only view of the page's state for
// automated tests (and the curious, in the browser's console).
export function installTestHook(viewer) {
  const hook = {
    // The page is connected, has the body list and has drawn a frame.
    get ready() { return viewer.ready; },
    // The role the server gave: "ROLE_CONTROLLER", "ROLE_OBSERVER" or "".
    get role() { return viewer.role; },
    // The tick of the newest pose frame, or null.
    get lastTick() { return viewer.lastTick; },
    // The ids of the bodies drawn.
    bodyIds: () => [...viewer.view.bodies.keys()],
    // The id of the body with this name, or null.
    bodyId: (name) => {
      for (const [id, body] of viewer.view.bodies) if (body.info.name === name) return id;
      return null;
    },
    // Where body `id` is drawn in the world, [x, y, z] m, or null.
    position: (id) => {
      const mesh = viewer.view.bodies.get(id)?.mesh;
      return mesh ? mesh.position.toArray() : null;
    },
    // Where body `id`'s centre is drawn, {x, y} in CSS pixels, or null.
    screenPosition: (id) => viewer.view.screenPosition(id),
    // The id of the selected body, or null.
    get selectedId() { return viewer.view.selectedId; },
    // The ids of the joints listed.
    jointIds: () => [...viewer.joints.joints.keys()],
    // How many joints are drawn in the scene.
    jointsDrawn: () => viewer.joints.drawnCount(),
    // The id of the joint with this name, or null.
    jointId: (name) => {
      for (const [id, joint] of viewer.joints.joints) if (joint.info.name === name) return id;
      return null;
    },
    // Where joint `id`'s anchors are drawn, {a: [x, y, z], b: [x, y, z]} m, or null.
    jointAnchors: (id) => {
      const joint = viewer.joints.joints.get(id);
      return joint ? { a: joint.anchorA.toArray(), b: joint.anchorB.toArray() } : null;
    },
    // Where joint `id`'s anchor on body B is drawn, {x, y} in CSS pixels, or null.
    jointScreenPosition: (id) => {
      const joint = viewer.joints.joints.get(id);
      return joint ? viewer.joints.screenPoint(joint.anchorB) : null;
    },
    // Joint `id`'s newest state, {tick, position, speed, motorImpulse,
    // force, torque, forceTick} (vectors as [x, y, z]; force and torque
    // of the listing of forceTick), or null.
    jointState: (id) => {
      const known = viewer.jointStates.get(id);
      if (!known) return null;
      const v = (vector) => [vector?.x ?? 0, vector?.y ?? 0, vector?.z ?? 0];
      return { tick: known.tick, position: known.position, speed: known.speed, motorImpulse: known.motorImpulse,
               force: v(known.force), torque: v(known.torque), forceTick: known.forceTick };
    },
    // The id of the selected joint, or null.
    get selectedJointId() { return viewer.joints.selectedId; },
  };
  window.tumbleViewer = Object.freeze(hook);
}
