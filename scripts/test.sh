#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite through
# ctest. Extra arguments go to ctest (e.g. -L physics, -R Protocol).
set -euo pipefail
cd "$(dirname "$0")/.."

./scripts/build.sh
ctest --test-dir "${BUILD_DIR:-build}" --output-on-failure -j 2 --timeout 600 "$@"
