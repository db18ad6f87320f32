#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite through
# ctest. Extra arguments go to ctest (e.g. -L physics, -R Protocol).
#
# The container image test (label "docker": docker/test-image.sh, podman)
# runs when docker/probe.sh says containers can run on this machine, and is
# left out, with the reason, when they cannot. TUMBLE_DOCKER_TEST=0 leaves it
# out anyway; =1 insists on it.
set -euo pipefail
cd "$(dirname "$0")/.."

./scripts/build.sh

ctest_args=(--test-dir "${BUILD_DIR:-build}" --output-on-failure -j 2 --timeout 600)
case "${TUMBLE_DOCKER_TEST:-auto}" in
  0) ctest_args+=(-LE docker) ;;
  1) ;;
  *)
    if ! reason=$(docker/probe.sh 2>&1); then
      echo "test.sh: leaving out the container image test: ${reason#*: }" >&2
      ctest_args+=(-LE docker)
    fi
    ;;
esac
ctest "${ctest_args[@]}" "$@"
