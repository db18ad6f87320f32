// The browser viewer's joints against the real tumbled, in headless
// chromium: a scene with hinges, distance joints and a hanging chain of
// ball joints. The page lists and draws every joint; paused, it draws each
// anchor where the server has it; running, each hinge's two anchors stay
// together as its bodies swing; a click on a joint's dot selects it and the
// panel shows its angle as it changes, from the pose frames the page
// subscribed to with every joint's state (no ListJoints polling); a drag on the chain's last link
// pulls the links above it (through the joints only). Saves a screenshot
// with the selected joint.
//
//   node joints_test.mjs --tumbled PATH --tumble PATH --scene scenes/pendulums.json --screenshot OUT.png
//
// The hanging chain is added to the scene here. Exits 77 (ctest's skip)
// when chromium or web/node_modules is missing.
import assert from "node:assert/strict";
import { execFile } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { promisify } from "node:util";
import { parseArgs } from "node:util";
import { after, before, test } from "node:test";

import { launchChromium, missingPrerequisite } from "./browser.mjs";
import { startTumbled } from "./tumbled.mjs";

const { values: options } = parseArgs({
  options: {
    tumbled: { type: "string" },
    tumble: { type: "string" },
    scene: { type: "string" },
    screenshot: { type: "string" },
  },
});
const missing = missingPrerequisite();
if (missing) {
  console.log(`SKIP: the viewer's joints test needs ${missing}`);
  process.exit(77);
}
// After the check: these import protobufjs from web/node_modules.
const { FrameReader } = await import("../../web/src/framing.js");
const { protocolTypes } = await import("../../web/src/schema.js");
const { loadProtocolRoot } = await import("../../web/proto-schema.mjs");
const types = protocolTypes(loadProtocolRoot());

const kToken = "viewer-joints-test";
const kWaitMs = 20000;  // generous bound for anything that should take a moment

// Three links of 0.5 m hanging straight down from the world at (0, 5, 0),
// ball joints at their ends: at rest until pushed.
const kChainLinks = 3;
function withHangingChain(scene) {
  const links = Array.from({ length: kChainLinks }, (_, i) => ({
    name: `hang${i + 1}`, shape: { box: { half_extents: [0.05, 0.25, 0.05] } }, mass: 1,
    position: [0, 4.75 - 0.5 * i, 0],
  }));
  const joints = links.map((link, i) => ({
    name: `hang-joint${i + 1}`, type: "ball", body_a: i === 0 ? "world" : `hang${i}`, body_b: link.name,
    anchor: [0, 5 - 0.5 * i, 0],
  }));
  return { ...scene, bodies: [...scene.bodies, ...links], joints: [...scene.joints, ...joints] };
}

let server = null;
let browser = null;
let sceneDir = null;

async function tumble(...args) {
  const { stdout } = await promisify(execFile)(
    options.tumble, ["--server", `127.0.0.1:${server.port}`, "--token", kToken, "--json", ...args]);
  return JSON.parse(stdout);
}

const distance = (a, b) => Math.hypot(...a.map((x, i) => x - b[i]));

before(async () => {
  sceneDir = fs.mkdtempSync(path.join(os.tmpdir(), "tumble-joints-"));
  const scene = path.join(sceneDir, "scene.json");
  fs.writeFileSync(scene, JSON.stringify(withHangingChain(JSON.parse(fs.readFileSync(options.scene, "utf8")))));
  server = await startTumbled(options.tumbled, ["--scene", scene, "--tick-rate", "120", "--token", kToken],
                              { http: true });
  browser = await launchChromium();
});

after(async () => {
  await browser?.close();
  await server?.stop();
  if (sceneDir) fs.rmSync(sceneDir, { recursive: true, force: true });
});

// Every ClientMessage `page` sends on its WebSockets goes to page.sent,
// decoded, in order (the socket's bytes are the TCP protocol's stream).
function recordRequests(page) {
  page.sent = [];
  page.on("websocket", (socket) => {
    const reader = new FrameReader();
    socket.on("framesent", ({ payload }) => {
      if (typeof payload === "string") return;
      reader.push(new Uint8Array(payload.buffer, payload.byteOffset, payload.length));
      for (let body = reader.next(); body !== null; body = reader.next()) page.sent.push(types.ClientMessage.decode(body));
    });
  });
}

// How many ListJoints `page` has sent.
const listJointsSent = (page) => page.sent.filter((message) => message.kind === "listJoints").length;

// A page with the viewer, once it draws every body and every joint.
async function openViewer() {
  const page = await browser.context.newPage();
  page.errors = [];
  page.on("pageerror", (error) => page.errors.push(error));
  page.messages = [];
  page.on("console", (message) => page.messages.push(`${message.type()}: ${message.text()}`));
  recordRequests(page);
  await page.goto(`http://127.0.0.1:${server.httpPort}/#token=${kToken}`);
  const bodies = (await tumble("bodies")).bodies.length;
  const joints = (await tumble("joints")).joints.length;
  try {
    await page.waitForFunction(({ bodies, joints }) => {
      const hook = window.tumbleViewer;
      return hook?.ready && hook.bodyIds().length === bodies && hook.jointIds().length === joints &&
             hook.jointsDrawn() === joints;
    }, { bodies, joints }, { timeout: kWaitMs });
  } catch (error) {
    const hud = await page.locator("#hud").innerText().catch(() => "(none)");
    throw new Error(`the viewer did not show ${bodies} bodies and ${joints} joints: ${error.message}\nHUD:\n${hud}\n` +
                    `page errors: ${page.errors.join("; ")}\nconsole:\n${page.messages.join("\n")}\n` +
                    `tumbled log:\n${server.log()}`);
  }
  return page;
}

// Every joint's drawn anchors, {name: {a, b}}, read from one picture.
function drawnAnchors(page) {
  return page.evaluate(() => {
    const hook = window.tumbleViewer;
    return { tick: hook.lastTick, anchors: Object.fromEntries(hook.jointIds().map((id) => [id, hook.jointAnchors(id)])) };
  });
}

// Waits until the page has drawn two pictures since now.
const twoPictures = (page) =>
  page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));

test("the page draws every joint, at the server's anchors when paused and with its anchors together as it swings", async () => {
  // Opened on a paused world, the page's first frame and its joint listing
  // are of the tick the world stays at: every anchor is drawn where the
  // server has it.
  const listed = (await tumble("joints")).joints;
  await tumble("pause");
  let page;
  try {
    page = await openViewer();
    const atPause = (await tumble("joints")).joints;
    await twoPictures(page);
    const { anchors } = await drawnAnchors(page);
    for (const joint of atPause) {
      const drawn = anchors[joint.id];
      assert.ok(distance(drawn.a, joint.anchor_a) < 1e-4 && distance(drawn.b, joint.anchor_b) < 1e-4,
                `joint ${joint.name} is drawn at ${JSON.stringify(drawn)}, the server has ${joint.anchor_a} and ${joint.anchor_b}`);
    }
  } finally {
    await tumble("resume");
  }
  assert.equal(await page.locator('[data-hud="joints"]').textContent(), String(listed.length));
  assert.deepEqual(await page.evaluate(() => window.tumbleViewer.jointIds().sort((a, b) => a - b)),
                   listed.map((j) => j.id).sort((a, b) => a - b));

  // Running, the anchors follow the bodies: lower-pivot's (between the two
  // swinging rods) moves, and its two anchors stay together.
  const lower = await page.evaluate(() => window.tumbleViewer.jointId("lower-pivot"));
  const first = (await drawnAnchors(page)).anchors[lower];
  await page.waitForFunction(({ id, from }) => {
    const now = window.tumbleViewer.jointAnchors(id);
    return Math.hypot(...now.b.map((x, i) => x - from[i])) > 0.3;
  }, { id: lower, from: first.b }, { timeout: kWaitMs });
  for (let i = 0; i < 5; ++i) {
    const { anchors: now } = await drawnAnchors(page);
    for (const joint of listed.filter((j) => j.type === "hinge" || j.type === "ball")) {
      const { a, b } = now[joint.id];
      assert.ok(distance(a, b) < 0.02, `joint ${joint.name}'s anchors are drawn ${distance(a, b)} m apart: ${a} and ${b}`);
    }
    await twoPictures(page);
  }
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("a click on a joint selects it, and the panel shows its angle from the pose frames as the pendulum swings", async () => {
  const page = await openViewer();
  // The page's subscription asks for the joints' states in its frames.
  const subscribes = page.sent.filter((message) => message.kind === "subscribe");
  assert.equal(subscribes.length, 1);
  assert.equal(subscribes[0].subscribe.joints, true);
  const listingsBefore = listJointsSent(page);
  const selectedAt = Date.now();
  const pivot = await page.evaluate(() => window.tumbleViewer.jointId("pivot"));
  const at = await page.evaluate((id) => window.tumbleViewer.jointScreenPosition(id), pivot);
  await page.mouse.click(at.x, at.y);
  await page.waitForFunction((id) => window.tumbleViewer.selectedJointId === id, pivot, { timeout: kWaitMs });
  assert.equal(await page.evaluate(() => window.tumbleViewer.selectedId), null);
  const panel = page.locator("#inspector");
  await panel.waitFor({ state: "visible", timeout: kWaitMs });
  assert.equal(await panel.locator('[data-field="name"]').textContent(), "pivot");
  assert.equal(await panel.locator('[data-field="type"]').textContent(), "hinge");
  assert.match(await panel.locator('[data-field="bodies"]').textContent(), /^world \u2013 bob \(\d+\)$/);
  assert.match(await panel.locator('[data-field="motor"]').textContent(), /^off$/);

  // The bob swings: the joint's angle, as the page has it and shows it, changes.
  const state = () => page.evaluate((id) => window.tumbleViewer.jointState(id), pivot);
  const angle = () => panel.locator('[data-field="angle"]').textContent();
  const before = await state();
  const shownBefore = await angle();
  assert.match(shownBefore, /^-?\d+\.\d{3} rad \(-?\d+\.\d\u00b0\)$/);
  // Taken low in the swing (|sin| of the angle from level above 0.5),
  // where the hinge pulls with 3 m g |sin| and more: near the top of the
  // swing the pull falls to nothing.
  const low = await page.waitForFunction(({ id, tick, position }) => {
    const now = window.tumbleViewer.jointState(id);
    const moved = now.tick > tick && Math.abs(now.position - position) > 0.2;
    return moved && Math.abs(Math.sin(now.position)) > 0.5 ? now : false;
  }, { id: pivot, tick: before.tick, position: before.position }, { timeout: kWaitMs });
  const after = await low.jsonValue();
  // Within the swing's range: the bob starts level with the pivot and
  // swings down and up to level on the other side, half a turn.
  assert.ok(Math.abs(after.position) <= Math.PI + 0.1, `the pivot's angle is ${after.position}`);
  await page.waitForFunction(({ shown }) =>
    document.querySelector('#inspector [data-field="angle"]')?.textContent !== shown, { shown: shownBefore },
  { timeout: kWaitMs });
  assert.ok(Number.isFinite(after.speed) && after.force.every(Number.isFinite));
  // The state is the newest frame's, every frame: its tick is the page's
  // last frame's, read in one go.
  for (let i = 0; i < 5; ++i) {
    const { state, lastTick } = await page.evaluate((id) => {
      const hook = window.tumbleViewer;
      return { state: hook.jointState(id), lastTick: hook.lastTick };
    }, pivot);
    assert.equal(state.tick, lastTick, "the pivot's state is not the last frame's");
    assert.ok(state.forceTick !== null && state.forceTick <= state.tick, `force of tick ${state.forceTick}`);
    await twoPictures(page);
  }
  // Pose frames carry no forces: the panel says which listing's they are.
  assert.match(await panel.locator('[data-field="force"]').textContent(), /^\d+\.\d{3} N \(.*\), listed at tick \d+$/);
  // And nothing asked for the joint's state meanwhile: no ListJoints since
  // the page listed the joints (polling at 10 Hz would have sent several).
  const waited = Date.now() - selectedAt;
  if (waited < 1000) await new Promise((resolve) => setTimeout(resolve, 1000 - waited));
  assert.equal(listJointsSent(page), listingsBefore,
               `the page sent ListJoints while a joint was selected: ${listJointsSent(page) - listingsBefore} of them`);
  if (options.screenshot) await page.screenshot({ path: options.screenshot });
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("dragging the last link of a hanging chain pulls the links above it", async () => {
  const page = await openViewer();
  const bodies = async () => Object.fromEntries((await tumble("bodies")).bodies.map((b) => [b.name, b]));
  const rest = await bodies();
  const last = `hang${kChainLinks}`;
  const id = await page.evaluate((name) => window.tumbleViewer.bodyId(name), last);
  const from = await page.evaluate((id) => window.tumbleViewer.screenPosition(id), id);
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  await page.mouse.move(from.x + 60, from.y, { steps: 5 });
  await page.mouse.move(from.x + 120, from.y, { steps: 5 });
  await page.mouse.up();
  assert.equal(await page.evaluate(() => window.tumbleViewer.selectedId), id);

  // The top link, which nothing touched, swings away from where it hung.
  const deadline = Date.now() + kWaitMs;
  let moved = 0;
  while ((moved = distance((await bodies()).hang1.position, rest.hang1.position)) < 0.05 && Date.now() < deadline) {
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
  assert.ok(moved >= 0.05, `the chain's top link moved ${moved} m`);
  // And the joints hold: the chain is still joined end to end.
  const now = await bodies();
  for (let i = 1; i < kChainLinks; ++i) {
    const gap = distance(now[`hang${i}`].position, now[`hang${i + 1}`].position);
    assert.ok(Math.abs(gap - 0.5) < 0.05, `links ${i} and ${i + 1} are ${gap} m apart`);
  }
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("after the server comes back the page lists the joints again, and the selected joint's state is the new server's", async () => {
  const page = await openViewer();
  const pivot = await page.evaluate(() => window.tumbleViewer.jointId("pivot"));
  const at = await page.evaluate((id) => window.tumbleViewer.jointScreenPosition(id), pivot);
  await page.mouse.click(at.x, at.y);
  await page.waitForFunction((id) => window.tumbleViewer.jointState(id) !== null && window.tumbleViewer.selectedJointId === id,
                             pivot, { timeout: kWaitMs });
  const old = await page.evaluate((id) => window.tumbleViewer.jointState(id), pivot);

  const { port, httpPort } = server;
  await server.stop();
  server = null;
  await page.waitForFunction(() => window.tumbleViewer.ready === false, null, { timeout: kWaitMs });
  server = await startTumbled(options.tumbled, ["--scene", path.join(sceneDir, "scene.json"), "--tick-rate", "120",
                                                "--token", kToken], { http: true, port, httpPort });
  // The new server counts ticks from 0: its states are older by the tick,
  // and still the ones to show.
  await page.waitForFunction(({ id, tick }) => {
    const hook = window.tumbleViewer;
    const state = hook.jointState(id);
    return hook.ready && hook.jointsDrawn() === hook.jointIds().length && state !== null && state.tick < tick;
  }, { id: pivot, tick: old.tick }, { timeout: kWaitMs });
  assert.equal(await page.evaluate(() => window.tumbleViewer.selectedJointId), pivot);
  assert.deepEqual(page.errors, []);
  await page.close();
});
