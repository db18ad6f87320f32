// The protocol's message types, from a protobufjs Root built from
// proto/tumble/v1/*.proto. The bundle builds that Root from a JSON
// descriptor made at bundle time (build.mjs); the Node tests parse the
// .proto files themselves (proto-schema.mjs). Either way nothing is fetched
// at run time.
import protobuf from "protobufjs/light.js";

// 64-bit integers (ticks, request ids) decode as plain numbers: exact up to
// 2^53, which a tick counter at 10 kHz reaches after 28000 years.
protobuf.util.Long = undefined;
protobuf.configure();

// The types and enums the viewer uses, looked up in `root`.
export function protocolTypes(root) {
  return {
    ClientMessage: root.lookupType("tumble.v1.ClientMessage"),
    ServerMessage: root.lookupType("tumble.v1.ServerMessage"),
    WorldInfo: root.lookupType("tumble.v1.WorldInfo"),
    Role: root.lookupEnum("tumble.v1.Role").values,
    ErrorCode: root.lookupEnum("tumble.v1.ErrorCode").values,
    WorldEventKind: root.lookupEnum("tumble.v1.WorldEventKind").values,
    PoseEncoding: root.lookupEnum("tumble.v1.PoseEncoding").values,
    PoseFields: root.lookupEnum("tumble.v1.PoseFields").values,
    ProtocolVersion: root.lookupEnum("tumble.v1.ProtocolVersion").values,
    Motion: root.lookupEnum("tumble.v1.Motion").values,
    roleName: (value) => root.lookupEnum("tumble.v1.Role").valuesById[value] ?? `ROLE_${value}`,
    errorName: (value) => root.lookupEnum("tumble.v1.ErrorCode").valuesById[value] ?? `ERROR_${value}`,
  };
}

// A Root from the JSON descriptor that protobufjs's Root.toJSON() made.
export function rootFromDescriptor(descriptor) {
  return protobuf.Root.fromJSON(descriptor);
}
