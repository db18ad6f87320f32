// Node only: parses proto/tumble/v1/*.proto with protobufjs into a Root.
// build.mjs turns it into the JSON descriptor the bundle carries; the
// viewer's Node tests use the Root directly.
import path from "node:path";
import { fileURLToPath } from "node:url";
import protobuf from "protobufjs";

const here = path.dirname(fileURLToPath(import.meta.url));

// The repository's proto/ directory, the import root of the .proto files.
export const kProtoDir = path.resolve(here, "..", "proto");

// The protocol's files; protocol.proto imports types and scene, and
// world_info.proto (what a world served over NATS answers) imports protocol.
const kProtoFiles = ["tumble/v1/types.proto", "tumble/v1/scene.proto", "tumble/v1/protocol.proto",
                     "tumble/v1/world_info.proto"];

// A resolved Root of the protocol's messages.
export function loadProtocolRoot(protoDir = kProtoDir) {
  const root = new protobuf.Root();
  root.resolvePath = (origin, target) => path.join(protoDir, target);
  root.loadSync(kProtoFiles);
  root.resolveAll();
  return root;
}
