#!/usr/bin/env bash
# Generates the protocol modules of the Python client, src/tumble/v1/*_pb2.py
# and their type stubs (*_pb2.pyi), from proto/tumble/v1 with Debian's
# protoc, and writes them over the committed ones. Run it after any change
# to proto/; the test test_generated.py fails while they differ.
#   clients/python/generate.sh [OUT_DIR]
# OUT_DIR (default: clients/python/src) receives tumble/v1/*_pb2.py(i).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${1:-$here/src}"
protoc="${PROTOC:-protoc}"
mkdir -p "$out/tumble/v1"
"$protoc" -I "$root/proto" --python_out="$out" --pyi_out="$out" \
  "$root"/proto/tumble/v1/{types,scene,protocol}.proto
