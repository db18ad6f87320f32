#!/usr/bin/env bash
# Installs what is missing, builds, and starts tumbled on the demo scene at
# 127.0.0.1:7400, with the viewer on http://127.0.0.1:8080/. Extra
# arguments go to tumbled (e.g. --tick-rate 120).
# In another shell: build/client/cli/tumble bodies
set -euo pipefail
cd "$(dirname "$0")/.."

./scripts/build.sh
echo "tumbled on 127.0.0.1:7400; the CLI is $(pwd)/build/client/cli/tumble" >&2
echo "the viewer: http://127.0.0.1:8080/ (with a token: http://127.0.0.1:8080/#token=TOKEN)" >&2
exec build/server/tumbled --scene scenes/demo.json --listen 127.0.0.1:7400 --http 127.0.0.1:8080 "$@"
