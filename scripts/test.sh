#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite through
# ctest. Extra arguments go to ctest (e.g. -L physics, -R Protocol).
#
# The container image test (label "docker": docker/test-image.sh, with the
# Docker engine and Compose, or podman where no dockerd can start) runs
# when docker/probe.sh says containers can run on this machine, and is
# left out, with the reason, when they cannot. TUMBLE_DOCKER_TEST=0 leaves it
# out anyway; =1 insists on it.
#
# The browser viewer's tests (label "viewer") need chromium and web/'s npm
# packages; install-deps.sh --viewer installs them first.
#
# SANITIZE picks a sanitizer build of its own instead, at -Og with
# assertions on (CMAKE_BUILD_TYPE=Debug, CMAKE_CXX_FLAGS_DEBUG=-Og), without
# the benchmarks:
#   SANITIZE=address  AddressSanitizer and UndefinedBehaviorSanitizer, in
#                     build-asan/; every test but docker, bench, the slow
#                     one and the pure JavaScript ones (label js).
#   SANITIZE=thread   ThreadSanitizer, in build-tsan/; only the programs
#                     that start threads (labels net, sim, client, e2e,
#                     nats and physics-threads; target threaded_tests),
#                     without the slow ones and the browser's.
# A sanitizer's report, or a failed assertion, fails the test it comes from.
#
# BUILD_ONLY=1 installs and builds what the run would test, and stops there.
set -euo pipefail
cd "$(dirname "$0")/.."

./scripts/install-deps.sh --viewer
ctest_args=(--output-on-failure -j 2 --timeout 600)
# -Og: instrumented code compiles in about two thirds of -O1's time and
# still runs optimized enough for the suite (docs/development.md).
sanitizer_args=(-DCMAKE_CXX_FLAGS_DEBUG=-Og -DTUMBLE_BUILD_BENCH=OFF)
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
    BUILD_DIR=$build_dir BUILD_TYPE=Debug ./scripts/build.sh "${sanitizer_args[@]}" \
      -DTUMBLE_SANITIZE=address,undefined
    # Not the slow never-reader test either: it bounds RSS and the stepping
    # rate, which ASan's shadow memory and quarantine distort. The pure
    # JavaScript tests run no code of ours that a sanitizer could watch.
    ctest_args+=(-LE 'docker|bench|slow|js')
    ;;
  thread)
    build_dir=${BUILD_DIR:-build-tsan}
    BUILD_DIR=$build_dir BUILD_TYPE=Debug TARGETS=threaded_tests \
      ./scripts/build.sh "${sanitizer_args[@]}" -DTUMBLE_SANITIZE=thread
    ctest_args+=(-L '^(net|sim|client|e2e|nats|physics-threads)$' -LE 'slow|viewer')
    ;;
  *)
    echo "test.sh: SANITIZE is address or thread, not '$SANITIZE'" >&2
    exit 2
    ;;
esac
[[ "${BUILD_ONLY:-0}" == 1 ]] && exit 0
ctest --test-dir "$build_dir" "${ctest_args[@]}" "$@"
