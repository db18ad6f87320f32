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
  };
  window.tumbleViewer = Object.freeze(hook);
}
