// Debian's chromium, headless, driven by playwright-core from
// web/node_modules, for the viewer's tests. WebGL runs on SwiftShader (the
// CPU), since test machines have no GPU.
import fs from "node:fs";
import { createRequire } from "node:module";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

export const kChromium = process.env.TUMBLE_CHROMIUM || "/usr/bin/chromium";
const kWebDir = path.resolve(path.dirname(fileURLToPath(import.meta.url)), "..", "..", "web");

// What is missing of web/node_modules, or "" when it is installed.
export function missingNodeModules() {
  for (const name of ["playwright-core", "protobufjs", "three", "esbuild", "@nats-io/nats-core", "@nats-io/transport-node"]) {
    if (!fs.existsSync(path.join(kWebDir, "node_modules", name))) {
      return `web/node_modules/${name}, which is missing (scripts/install-deps.sh --viewer runs npm ci in web/)`;
    }
  }
  return "";
}

// Why the browser tests cannot run here, or "" when they can.
export function missingPrerequisite() {
  if (!fs.existsSync(kChromium)) return `${kChromium}, which is missing (scripts/install-deps.sh --viewer installs it)`;
  return missingNodeModules();
}

// A headless chromium with a fresh profile; close() also removes the profile.
export async function launchChromium() {
  const require = createRequire(path.join(kWebDir, "package.json"));
  const { chromium } = require("playwright-core");
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), "tumble-chromium-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: kChromium,
    headless: true,
    viewport: { width: 1000, height: 640 },
    args: [
      "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
      "--disable-component-update", "--disable-sync",
      "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
    ],
  });
  return {
    context,
    async close() {
      await context.close();
      fs.rmSync(profile, { recursive: true, force: true });
    },
  };
}
