// The real tumbled on ephemeral ports of 127.0.0.1, for the viewer's tests.
//
//   const server = await startTumbled(tumbledPath, ["--scene", scene], {http: true});
//   ... server.port (TCP), server.httpPort (HTTP and WebSocket) ...
// Ports are picked by the system unless `port` and `httpPort` name them
// (to start a server again where the last one was).
//   await server.stop();  // SIGTERM; throws unless tumbled exits 0
//
// Its log goes to a file in a temporary directory and is printed when
// something fails.
import { spawn } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";

const kStartupSeconds = 30;  // generous: a busy machine or a sanitizer build starts slowly
const kStopSeconds = 30;

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

// The port tumbled wrote to `file`, or 0 while it is missing or not whole.
function readPort(file) {
  try {
    const text = fs.readFileSync(file, "utf8").trim();
    return /^\d+$/.test(text) ? Number(text) : 0;
  } catch {
    return 0;
  }
}

export async function startTumbled(tumbled, args, { http = false, port = 0, httpPort = 0 } = {}) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "tumble-viewer-"));
  const portFile = path.join(dir, "port");
  const httpPortFile = path.join(dir, "http-port");
  const logFile = path.join(dir, "tumbled.log");
  const log = fs.openSync(logFile, "w");
  const argv = ["--listen", `127.0.0.1:${port}`, "--port-file", portFile, ...args];
  if (http) argv.push("--http", `127.0.0.1:${httpPort}`, "--http-port-file", httpPortFile);
  const child = spawn(tumbled, argv, { stdio: ["ignore", log, log] });
  fs.closeSync(log);
  let exitCode = null;
  const exited = new Promise((resolve) => child.on("exit", (code, signal) => {
    exitCode = code ?? signal;
    resolve();
  }));
  const readLog = () => fs.readFileSync(logFile, "utf8");

  const server = {
    port: 0,
    httpPort: 0,
    log: readLog,
    async stop() {
      try {
        if (exitCode === null) {
          child.kill("SIGTERM");
          let timer;
          const stopped = await Promise.race([
            exited.then(() => true),
            new Promise((resolve) => { timer = setTimeout(() => resolve(false), kStopSeconds * 1000); }),
          ]);
          clearTimeout(timer);
          if (!stopped) {
            child.kill("SIGKILL");
            await exited;
            throw new Error(`tumbled did not stop on SIGTERM:\n${readLog()}`);
          }
        }
        if (exitCode !== 0) throw new Error(`tumbled exited with ${exitCode}:\n${readLog()}`);
      } finally {
        fs.rmSync(dir, { recursive: true, force: true });
      }
    },
  };

  const deadline = Date.now() + kStartupSeconds * 1000;
  while (Date.now() < deadline) {
    if (exitCode !== null) {
      const text = readLog();
      fs.rmSync(dir, { recursive: true, force: true });
      throw new Error(`tumbled exited with ${exitCode} at startup:\n${text}`);
    }
    server.port = readPort(portFile);
    server.httpPort = http ? readPort(httpPortFile) : 0;
    if (server.port && (!http || server.httpPort)) return server;
    await sleep(50);
  }
  child.kill("SIGKILL");
  await exited;
  const text = readLog();
  fs.rmSync(dir, { recursive: true, force: true });
  throw new Error(`tumbled did not write its ports within ${kStartupSeconds} s:\n${text}`);
}
