// Bundles the viewer into dist/: dist/viewer.js (src/main.js with three.js,
// protobufjs and the protocol's JSON descriptor, minified by esbuild) and
// dist/index.html. tumbled embeds dist/ at its build time, so the C++ build
// needs neither Node nor the network; dist/ is committed and this script
// remakes it from the sources and package-lock.json.
//
//   node build.mjs           write dist/
//   node build.mjs --check   build in memory and compare with dist/ byte for
//                            byte; exit 1, naming the files, when they differ,
//                            and 77 (ctest's skip) without node_modules
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const distDir = path.join(here, "dist");
const check = process.argv.includes("--check");

if (!fs.existsSync(path.join(here, "node_modules", "esbuild"))) {
  console.log("SKIP: web/node_modules is missing; `npm ci` in web/ (or scripts/install-deps.sh --viewer) installs it");
  process.exit(check ? 77 : 1);
}
const esbuild = await import("esbuild");
const { loadProtocolRoot } = await import("./proto-schema.mjs");

// The protocol's descriptor as the module "tumble:protocol-descriptor", so
// src/ imports it like any JSON and nothing is fetched at run time.
const descriptorPlugin = {
  name: "protocol-descriptor",
  setup(build) {
    build.onResolve({ filter: /^tumble:protocol-descriptor$/ }, (args) => ({ path: args.path, namespace: "descriptor" }));
    build.onLoad({ filter: /.*/, namespace: "descriptor" }, () => ({
      contents: JSON.stringify(loadProtocolRoot().toJSON()),
      loader: "json",
    }));
  },
};

const result = await esbuild.build({
  entryPoints: [path.join(here, "src", "main.js")],
  bundle: true,
  minify: true,
  format: "esm",
  target: "es2020",
  platform: "browser",
  legalComments: "eof",
  charset: "utf8",
  plugins: [descriptorPlugin],
  write: false,
  outfile: path.join(distDir, "viewer.js"),
  logLevel: "warning",
});

// What dist/ must hold: the bundle and the page.
const outputs = new Map([
  ["viewer.js", Buffer.from(result.outputFiles[0].contents)],
  ["index.html", fs.readFileSync(path.join(here, "index.html"))],
]);

if (check) {
  const stale = [];
  for (const [name, bytes] of outputs) {
    const file = path.join(distDir, name);
    if (!fs.existsSync(file) || !fs.readFileSync(file).equals(bytes)) stale.push(`dist/${name}`);
  }
  const extra = fs.existsSync(distDir) ? fs.readdirSync(distDir).filter((name) => !outputs.has(name)) : [];
  for (const name of extra) stale.push(`dist/${name} (not made by build.mjs)`);
  if (stale.length) {
    console.error(`web: not what the sources make: ${stale.join(", ")}; run \`npm run build\` in web/ and commit dist/`);
    process.exit(1);
  }
  console.log(`web: dist/ matches the sources (${[...outputs.keys()].join(", ")})`);
} else {
  fs.mkdirSync(distDir, { recursive: true });
  for (const [name, bytes] of outputs) fs.writeFileSync(path.join(distDir, name), bytes);
  console.log(`web: wrote ${[...outputs].map(([name, bytes]) => `dist/${name} (${bytes.length} bytes)`).join(", ")}`);
}
