// The browser viewer against the real tumbled, in headless chromium: the
// page draws the bodies where its hook says, follows a push sent from the
// real CLI, shows a selected body, pushes a body dragged with the mouse,
// tells an observer that pushing needs a controller token, and reconnects
// when the server comes back. The same page through NATS's WebSocket
// listener (a real nats-server the server publishes into): it draws the
// bodies where the pose stream puts them and a drag pushes; an observer's
// push is refused by NATS. Saves a screenshot.
//
//   node viewer_test.mjs --tumbled PATH --tumble PATH --scene scenes/playground.json --screenshot OUT.png
//
// Exits 77 (ctest's skip) when chromium or web/node_modules is missing.
import assert from "node:assert/strict";
import { execFile } from "node:child_process";
import { promisify } from "node:util";
import { parseArgs } from "node:util";
import { after, before, test } from "node:test";

import { launchChromium, missingPrerequisite } from "./browser.mjs";
import { kUsers, natsServerPath, startNatsServer } from "./nats_server.mjs";
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
  console.log(`SKIP: the viewer's browser test needs ${missing}`);
  process.exit(77);
}

const kControllerToken = "viewer-test-controller";
const kObserverToken = "viewer-test-observer";
const kWaitMs = 20000;  // generous bound for anything that should take a moment
const kMovedPx = 40;    // a body pushed off its place moves at least this far on screen

let server = null;
let browser = null;
let nats = null;  // the nats-server the world is also published into; null without nats-server
const serverArgs = ["--scene", options.scene, "--tick-rate", "120",
                    "--token", kControllerToken, "--observer-token", kObserverToken];
// The NATS pose stream the page reads: DELTA, so the page's sequence rule is in play.
const kNatsWorld = "demo";
const kNatsArgs = () => ["--nats", nats.url.replace("nats://", `nats://${kUsers.tumbled.user}:${kUsers.tumbled.pass}@`),
                         "--world", kNatsWorld, "--nats-stream", "d60=delta@60"];
const natsFragment = (who) =>
  `#nats=${nats.wsUrl}&world=${kNatsWorld}&user=${kUsers[who].user}&pass=${kUsers[who].pass}`;

// Runs the real CLI against the server; returns its parsed --json output.
async function tumble(...args) {
  const { stdout } = await promisify(execFile)(
    options.tumble, ["--server", `127.0.0.1:${server.port}`, "--token", kControllerToken, "--json", ...args]);
  return JSON.parse(stdout);
}

// The body named `name` as the CLI lists it.
async function bodyFromCli(name) {
  const list = await tumble("bodies");
  const body = list.bodies.find((b) => b.name === name);
  assert.ok(body, `no body named ${name}`);
  return body;
}

const length = (v) => Math.hypot(...v);
const distance = (a, b) => Math.hypot(...a.map((x, i) => x - b[i]));

// Waits until the CLI shows body `name` at rest (it has landed and
// settled); returns the body and the tick the CLI saw it at.
// With { asleep: true }, until the server has put it to sleep: it then
// stays exactly where it is, so a pose drawn from any later frame must be
// that one. Merely slow, it may still creep a few millimetres by then.
async function waitUntilAtRest(name, { asleep = false } = {}) {
  const deadline = Date.now() + 3 * kWaitMs;
  for (;;) {
    const list = await tumble("bodies");
    const body = list.bodies.find((b) => b.name === name);
    assert.ok(body, `no body named ${name}`);
    const resting = asleep ? body.asleep
                           : length(body.linear_velocity) < 0.02 && length(body.angular_velocity) < 0.05;
    if (resting) return { ...body, tick: list.tick };
    assert.ok(Date.now() < deadline, `${name} did not come to rest${asleep ? " asleep" : ""}: ${JSON.stringify(body)}`);
    await new Promise((resolve) => setTimeout(resolve, 200));
  }
}

// A page with the viewer, after it is ready and draws every body.
async function openViewer(fragment) {
  const page = await browser.context.newPage();
  const errors = [];
  page.on("pageerror", (error) => errors.push(error));
  page.errors = errors;
  const messages = [];  // the console's, for a failure's report
  page.on("console", (message) => messages.push(`${message.type()}: ${message.text()}`));
  page.messages = messages;
  await page.goto(`http://127.0.0.1:${server.httpPort}/${fragment}`);
  return page;
}

async function waitUntilReady(page) {
  const count = (await tumble("bodies")).bodies.length;
  try {
    await page.waitForFunction((n) => window.tumbleViewer?.ready && window.tumbleViewer.bodyIds().length === n,
                               count, { timeout: kWaitMs });
  } catch (error) {
    const hud = await page.locator("#hud").innerText().catch(() => "(none)");
    throw new Error(`the viewer did not show ${count} bodies: ${error.message}\nHUD:\n${hud}\n` +
                    `page errors: ${page.errors.join("; ")}\nconsole:\n${page.messages.join("\n")}\n` +
                    `tumbled log:\n${server.log()}`);
  }
}

// In the page: a function (x, y) -> the mean colour [r, g, b] of the 5 x 5
// canvas pixels around page point (x, y), of the picture drawn last.
const kPixelReader = `(() => {
  const source = document.querySelector("#scene canvas");
  const copy = document.createElement("canvas");
  copy.width = source.width;
  copy.height = source.height;
  const context = copy.getContext("2d");
  context.drawImage(source, 0, 0);
  const scale = source.width / source.clientWidth;
  return (x, y) => {
    const data = context.getImageData(Math.round(x * scale) - 2, Math.round(y * scale) - 2, 5, 5).data;
    const mean = [0, 0, 0];
    for (let i = 0; i < data.length; i += 4) for (let k = 0; k < 3; ++k) mean[k] += data[i + k] / 25;
    return mean;
  };
})()`;

// The mean colours around each of `points` (page coordinates).
function colorsAt(page, points) {
  return page.evaluate(({ reader, points }) => {
    const colorAt = eval(reader);
    return points.map(({ x, y }) => colorAt(x, y));
  }, { reader: kPixelReader, points });
}

// The colours of a row of points along the bottom of the view and around
// every body's centre, read in one go from the picture the positions were
// drawn in.
function bodyColors(page) {
  return page.evaluate((reader) => {
    const colorAt = eval(reader);
    const bottom = Array.from({ length: 9 }, (_, i) => colorAt(((i + 0.5) / 9) * innerWidth, innerHeight - 4));
    const bodies = window.tumbleViewer.bodyIds()
      .map((id) => ({ id, at: window.tumbleViewer.screenPosition(id) }))
      .filter(({ at }) => at && at.x >= 2 && at.y >= 2 && at.x < innerWidth - 2 && at.y < innerHeight - 2)
      .map((body) => ({ ...body, color: colorAt(body.at.x, body.at.y) }));
    return { bottom, bodies };
  }, kPixelReader);
}

// How many different colours the canvas holds (a blank one holds one).
function distinctColors(page) {
  return page.evaluate(() => {
    const source = document.querySelector("#scene canvas");
    const copy = document.createElement("canvas");
    copy.width = source.width;
    copy.height = source.height;
    const context = copy.getContext("2d");
    context.drawImage(source, 0, 0);
    const data = context.getImageData(0, 0, copy.width, copy.height).data;
    const colors = new Set();
    for (let i = 0; i < data.length; i += 4) colors.add((data[i] << 16) | (data[i + 1] << 8) | data[i + 2]);
    return colors.size;
  });
}

// The page draws the poses about one stream period behind the newest frame
// it has; these many ticks (a quarter second at the server's 120 Hz) cover
// that period and the page's clock estimate.
const kDrawLagTicks = 30;

// Waits until the page holds pose frames kDrawLagTicks past `tick` and has
// drawn two pictures since: what it draws now shows the world at `tick` or
// later.
async function waitUntilDrawnPast(page, tick) {
  await page.waitForFunction((t) => window.tumbleViewer.lastTick >= t, tick + kDrawLagTicks, { timeout: kWaitMs });
  await page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));
}

const screenPosition = (page, id) => page.evaluate((id) => window.tumbleViewer.screenPosition(id), id);

// Waits until body `id` is drawn more than `px` CSS pixels from `from`.
async function waitUntilMovedOnScreen(page, id, from, px) {
  await page.waitForFunction(({ id, from, px }) => {
    const at = window.tumbleViewer.screenPosition(id);
    return at && Math.hypot(at.x - from.x, at.y - from.y) > px;
  }, { id, from, px }, { timeout: kWaitMs });
}

const colorDistance = (a, b) => Math.hypot(...a.map((x, i) => x - b[i]));

before(async () => {
  if (natsServerPath()) {
    nats = await startNatsServer();
    serverArgs.push(...kNatsArgs());
  }
  server = await startTumbled(options.tumbled, serverArgs, { http: true });
  browser = await launchChromium();
});

after(async () => {
  await browser?.close();
  await server?.stop();
  await nats?.stop();
});

test("the page draws the bodies, follows a push from the CLI and shows a selected body", async () => {
  const page = await openViewer(`#token=${kControllerToken}`);
  await waitUntilReady(page);
  assert.equal(await page.evaluate(() => window.tumbleViewer.role), "ROLE_CONTROLLER");
  const cliIds = (await tumble("bodies")).bodies.map((b) => b.id).sort((a, b) => a - b);
  assert.deepEqual(await page.evaluate(() => window.tumbleViewer.bodyIds().sort((a, b) => a - b)), cliIds);
  assert.ok(await distinctColors(page) > 200, "the canvas is blank");

  // Where the page says each body is, the canvas shows something other than
  // the ground, which fills the bottom of the view: its colour is the median
  // of a row of samples there (a few may fall on grid lines).
  const { bottom, bodies } = await bodyColors(page);
  const ground = [0, 1, 2].map((k) => bottom.map((color) => color[k]).sort((a, b) => a - b)[bottom.length >> 1]);
  assert.ok(bottom.filter((color) => colorDistance(color, ground) < 10).length > bottom.length / 2,
            `the bottom of the view is not ground: ${JSON.stringify(bottom)}`);
  assert.ok(bodies.length > 0, "no body is drawn inside the view");
  for (const body of bodies) {
    assert.ok(colorDistance(body.color, ground) > 25,
              `body ${body.id} at ${JSON.stringify(body.at)} looks like the ground ${ground}: ${body.color}`);
  }

  // The top crate of the stack, at rest: where the page draws it, the
  // canvas shows it; once a push from the CLI has thrown it off, the same
  // pixels show what was behind it.
  const resting = await waitUntilAtRest("crate4");
  const crate = await page.evaluate(() => window.tumbleViewer.bodyId("crate4"));
  // Rendering lags a frame period behind the stream: wait until it draws the crate at rest.
  await waitUntilDrawnPast(page, resting.tick);
  const before = await screenPosition(page, crate);
  const [there] = await colorsAt(page, [before]);
  const ack = await tumble("impulse", "crate4", "--impulse", "-8", "0", "0");
  assert.ok(ack.applied_tick > 0);
  await waitUntilMovedOnScreen(page, crate, before, kMovedPx);
  await page.waitForFunction((tick) => window.tumbleViewer.lastTick >= tick, ack.applied_tick, { timeout: kWaitMs });
  const [behind] = await colorsAt(page, [before]);
  assert.ok(colorDistance(there, behind) > 20,
            `the pixels where crate4 was drawn did not change when it left: ${there} then ${behind}`);

  // Selecting crate1 (at the bottom of the stack, where the page puts it).
  const target = await page.evaluate(() => window.tumbleViewer.bodyId("crate1"));
  const at = await screenPosition(page, target);
  await page.mouse.click(at.x, at.y);
  await page.waitForFunction((id) => window.tumbleViewer.selectedId === id, target, { timeout: kWaitMs });
  const panel = page.locator("#inspector");
  await panel.waitFor({ state: "visible", timeout: kWaitMs });
  assert.equal(await panel.locator('[data-field="name"]').textContent(), "crate1");
  assert.equal(await panel.locator('[data-field="id"]').textContent(), String(target));
  assert.match(await panel.locator('[data-field="shape"]').textContent(), /^box, half extents 0.5 x 0.5 x 0.5 m$/);

  // For the screenshot: crate4 has landed and is drawn there, and the HUD has the server's stats.
  await waitUntilDrawnPast(page, (await waitUntilAtRest("crate4")).tick);
  await page.waitForFunction(() => /^\d+ \(\d+ asleep\)$/.test(
    document.querySelector('[data-hud="bodies"]')?.textContent ?? ""), null, { timeout: kWaitMs });
  if (options.screenshot) await page.screenshot({ path: options.screenshot });
  assert.deepEqual(page.errors, []);
  await page.close();
});

// Drags the pill, resting and drawn, to the left on the screen and waits
// until the page shows it moving and the server has it 0.3 m or more from
// where it rested; returns its id.
async function dragThePill(page) {
  const rest = await waitUntilAtRest("pill");
  await waitUntilDrawnPast(page, rest.tick);
  const pill = await page.evaluate(() => window.tumbleViewer.bodyId("pill"));
  const from = await screenPosition(page, pill);
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  await page.mouse.move(from.x - 60, from.y - 10, { steps: 5 });
  await page.mouse.move(from.x - 120, from.y - 20, { steps: 5 });
  await page.mouse.up();
  await waitUntilMovedOnScreen(page, pill, from, kMovedPx);
  const deadline = Date.now() + kWaitMs;
  let moved = 0;
  while ((moved = distance((await bodyFromCli("pill")).position, rest.position)) < 0.3 && Date.now() < deadline) {
    await new Promise((resolve) => setTimeout(resolve, 200));
  }
  assert.ok(moved >= 0.3, `the dragged pill moved ${moved} m on the server`);
  return pill;
}

test("dragging a body pushes it", async () => {
  const page = await openViewer(`#token=${kControllerToken}`);
  await waitUntilReady(page);
  const pill = await dragThePill(page);
  assert.equal(await page.evaluate(() => window.tumbleViewer.selectedId), pill);
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("an observer is told that pushing needs a controller token; a wrong token is refused", async () => {
  const page = await openViewer(`#token=${kObserverToken}`);
  await waitUntilReady(page);
  assert.equal(await page.evaluate(() => window.tumbleViewer.role), "ROLE_OBSERVER");
  const id = await page.evaluate(() => window.tumbleViewer.bodyId("crate2"));
  const at = await screenPosition(page, id);
  await page.mouse.move(at.x, at.y);
  await page.mouse.down();
  await page.mouse.move(at.x + 80, at.y, { steps: 5 });
  await page.mouse.up();
  await page.locator("#inspector .inspector-note").waitFor({ state: "visible", timeout: kWaitMs });
  assert.match(await page.locator("#inspector .inspector-note").textContent(), /controller token/);
  await page.close();

  const stranger = await openViewer("#token=wrong");
  await stranger.waitForFunction(() => document.querySelector("#hud")?.dataset.connection === "refused",
                                 null, { timeout: kWaitMs });
  assert.match(await stranger.locator('[data-hud="connection"]').textContent(), /UNAUTHENTICATED/);
  await stranger.close();
});

test("the page says when the server went away and reconnects when it is back", async () => {
  const page = await openViewer(`#token=${kControllerToken}`);
  await waitUntilReady(page);
  const { port, httpPort } = server;
  await server.stop();
  server = null;
  // While it waits and while it tries again, the HUD says why.
  await page.waitForFunction(() => ["retrying", "reconnecting"].includes(document.querySelector("#hud")?.dataset.connection),
                             null, { timeout: kWaitMs });
  assert.match(await page.locator('[data-hud="connection"]').textContent(), /^the server went away; re/);
  assert.equal(await page.evaluate(() => window.tumbleViewer.ready), false);

  server = await startTumbled(options.tumbled, serverArgs, { http: true, port, httpPort });
  await waitUntilReady(page);
  assert.equal(await page.locator('[data-hud="connection"]').textContent(), "connected");
  assert.deepEqual(page.errors, []);
  await page.close();
});

const kNatsSkip = () => (natsServerPath() ? false : "nats-server is missing");

test("through NATS the page draws the bodies where the pose stream puts them, and a drag pushes", { skip: kNatsSkip() }, async () => {
  const page = await openViewer(natsFragment("controller"));
  await waitUntilReady(page);
  assert.equal(await page.evaluate(() => window.tumbleViewer.role), "ROLE_CONTROLLER");
  const cliIds = (await tumble("bodies")).bodies.map((b) => b.id).sort((a, b) => a - b);
  assert.deepEqual(await page.evaluate(() => window.tumbleViewer.bodyIds().sort((a, b) => a - b)), cliIds);

  // Asleep, crate4 is drawn where the server has it, within the DELTA stream's grid (1/1024 m).
  const resting = await waitUntilAtRest("crate4", { asleep: true });
  await waitUntilDrawnPast(page, resting.tick);
  const crate = await page.evaluate(() => window.tumbleViewer.bodyId("crate4"));
  const drawn = await page.evaluate((id) => window.tumbleViewer.position(id), crate);
  assert.ok(distance(drawn, resting.position) < 2e-3,
            `crate4 is drawn at ${drawn}, the server has it at ${resting.position}`);

  // A drag sends ApplyImpulse over .rpc: the server moves the pill, and the page shows it moving.
  await dragThePill(page);
  assert.equal(await page.locator("#inspector .inspector-note").count(), 0);
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("through NATS an observer sees every body, and NATS refuses its push", { skip: kNatsSkip() }, async () => {
  const page = await openViewer(natsFragment("observer"));
  await waitUntilReady(page);
  assert.equal(await page.evaluate(() => window.tumbleViewer.role), "ROLE_OBSERVER");
  assert.equal(await page.locator('[data-hud="role"]').textContent(), "observer");
  const resting = await waitUntilAtRest("crate2", { asleep: true });
  await waitUntilDrawnPast(page, resting.tick);
  // The observer lists the bodies on .query: it knows crate2 by name, as a controller does.
  const id = resting.id;
  assert.equal(await page.evaluate(() => window.tumbleViewer.bodyId("crate2")), id);
  const drawn = await page.evaluate((id) => window.tumbleViewer.position(id), id);
  assert.ok(distance(drawn, resting.position) < 2e-3, `crate2 is drawn at ${drawn}, the server has it at ${resting.position}`);
  const at = await screenPosition(page, id);
  await page.mouse.move(at.x, at.y);
  await page.mouse.down();
  await page.mouse.move(at.x + 80, at.y, { steps: 5 });
  await page.mouse.up();
  const note = page.locator("#inspector .inspector-note");
  await note.waitFor({ state: "visible", timeout: kWaitMs });
  assert.match(await note.textContent(), /NATS does not let this user publish to tumble\.v1\.demo\.rpc/);
  assert.ok(length((await bodyFromCli("crate2")).linear_velocity) < 0.02, "the observer's drag moved crate2");
  assert.deepEqual(page.errors, []);
  await page.close();
});

test("through NATS a wrong password is refused", { skip: kNatsSkip() }, async () => {
  const page = await openViewer(`#nats=${nats.wsUrl}&world=${kNatsWorld}&user=controller&pass=wrong`);
  await page.waitForFunction(() => document.querySelector("#hud")?.dataset.connection === "refused", null, { timeout: kWaitMs });
  assert.match(await page.locator('[data-hud="connection"]').textContent(), /[Aa]uthorization/);
  await page.close();
});
