#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite through
# ctest. Extra arguments go to ctest (e.g. -L physics, -R Protocol).
#
# The container image test (label "docker": docker/test-image.sh, podman)
# runs when docker/probe.sh says containers can run on this machine, and is
# left out, with the reason, when they cannot. TUMBLE_DOCKER_TEST=0 leaves it
# out anyway; =1 insists on it.
#
# The browser viewer's tests (label "viewer") need chromium and web/'s npm
# packages; install-deps.sh --viewer installs them first.
#
# SANITIZE picks a sanitizer build of its own instead (no benchmarks):
#   SANITIZE=address  AddressSanitizer and UndefinedBehaviorSanitizer, in
#                     build-asan/; every test but docker, bench and the slow one.
#   SANITIZE=thread   ThreadSanitizer, in build-tsan/; only the tests that
#                     run threads (labels net, sim, e2e, and physics for the
#                     islands on helper threads), without the slow one.
# A sanitizer's report fails the test it comes from.
set -euo pipefail
cd "$(dirname "$0")/.."

./scripts/install-deps.sh --viewer
ctest_args=(--output-on-failure -j 2 --timeout 600)
case "${SANITIZE:-}" in
  "")
    ./scripts/build.sh
    build_dir=${BUILD_DIR:-build}
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
    ;;
  address)
    build_dir=${BUILD_DIR:-build-asan}
    BUILD_DIR=$build_dir ./scripts/build.sh -DTUMBLE_SANITIZE=address,undefined -DTUMBLE_BUILD_BENCH=OFF
    # Not the slow never-reader test either: it bounds RSS and the stepping
    # rate, which ASan's shadow memory and quarantine distort.
    ctest_args+=(-LE 'docker|bench|slow')
    ;;
  thread)
    build_dir=${BUILD_DIR:-build-tsan}
    BUILD_DIR=$build_dir TARGETS="physics_tests net_tests sim_tests e2e_tests e2e_bad_input_tests" \
      ./scripts/build.sh -DTUMBLE_SANITIZE=thread -DTUMBLE_BUILD_BENCH=OFF
    ctest_args+=(-L 'physics|net|sim|e2e' -LE slow)
    ;;
  *)
    echo "test.sh: SANITIZE is address or thread, not '$SANITIZE'" >&2
    exit 2
    ;;
esac
ctest --test-dir "$build_dir" "${ctest_args[@]}" "$@"
