// A real nats-server on ephemeral ports of 127.0.0.1 with a WebSocket
// listener (the `websocket` block the viewer connects through), for the
// viewer's tests; users and permissions from docker/nats/auth.conf itself.
//
//   const nats = await startNatsServer();
//   ... nats.url (nats://127.0.0.1:PORT), nats.wsUrl (ws://127.0.0.1:PORT) ...
//   await nats.stop();
//
// Readiness is the ports file the server writes once it listens. Its log is
// kept in a temporary directory and printed when it fails to start.
import { execFileSync, spawn } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";

const kStartupSeconds = 30;

// Users of the tests, with fixed passwords; roles as docker/nats/auth.conf.
export const kUsers = {
  observer: { user: "observer", pass: "observer-test" },
  controller: { user: "controller", pass: "controller-test" },
  tumbled: { user: "tumbled", pass: "tumbled-test" },
};

// The users and permissions as the docs and the image ship them, read from
// the source tree; nats-server reads their passwords from its environment.
const kAuthConf = new URL("../../docker/nats/auth.conf", import.meta.url);
const kPasswordEnv = {
  TUMBLE_NATS_OBSERVER_PASSWORD: kUsers.observer.pass,
  TUMBLE_NATS_CONTROLLER_PASSWORD: kUsers.controller.pass,
  TUMBLE_NATS_TUMBLED_PASSWORD: kUsers.tumbled.pass,
};

const kConfig = (dir) => `
listen: "127.0.0.1:-1"
ports_file_dir: "${dir}"
websocket { listen: "127.0.0.1:-1", no_tls: true }
${fs.readFileSync(kAuthConf, "utf8")}
`;

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

// Where nats-server is, or "" when it is not installed.
export function natsServerPath() {
  for (const candidate of [process.env.TUMBLE_NATS_SERVER, "/usr/sbin/nats-server", "/usr/bin/nats-server"]) {
    if (candidate && fs.existsSync(candidate)) return candidate;
  }
  try {
    return execFileSync("sh", ["-c", "command -v nats-server"], { encoding: "utf8" }).trim();
  } catch {
    return "";
  }
}

export async function startNatsServer() {
  const binary = natsServerPath();
  if (!binary) throw new Error("nats-server is not installed (scripts/install-deps.sh installs it)");
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "tumble-nats-"));
  const configFile = path.join(dir, "nats.conf");
  fs.writeFileSync(configFile, kConfig(dir));
  const logFile = path.join(dir, "nats.log");
  const log = fs.openSync(logFile, "w");
  const child = spawn(binary, ["-c", configFile],
                      { stdio: ["ignore", log, log], env: { ...process.env, ...kPasswordEnv } });
  fs.closeSync(log);
  let exitCode = null;
  const exited = new Promise((resolve) => child.on("exit", (code, signal) => {
    exitCode = code ?? signal;
    resolve();
  }));
  const portsFile = path.join(dir, `nats-server_${child.pid}.ports`);
  const readLog = () => fs.readFileSync(logFile, "utf8");

  const server = {
    url: "",
    wsUrl: "",
    log: readLog,
    async stop() {
      if (exitCode === null) {
        child.kill("SIGTERM");
        await exited;
      }
      fs.rmSync(dir, { recursive: true, force: true });
    },
  };

  const deadline = Date.now() + kStartupSeconds * 1000;
  while (Date.now() < deadline) {
    if (exitCode !== null) {
      const text = readLog();
      fs.rmSync(dir, { recursive: true, force: true });
      throw new Error(`nats-server exited with ${exitCode} at startup:\n${text}`);
    }
    try {
      const ports = JSON.parse(fs.readFileSync(portsFile, "utf8"));
      if (ports.nats?.length && ports.websocket?.length) {
        server.url = ports.nats[0];
        server.wsUrl = ports.websocket[0];
        return server;
      }
    } catch {
      // not written yet, or not whole
    }
    await sleep(50);
  }
  child.kill("SIGKILL");
  await exited;
  const text = readLog();
  fs.rmSync(dir, { recursive: true, force: true });
  throw new Error(`nats-server did not write its ports within ${kStartupSeconds} s:\n${text}`);
}
