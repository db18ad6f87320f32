#!/usr/bin/env bash
# Installs what is missing and builds tumble into build/ (Release, at most 2
# jobs). Used by run.sh and test.sh; safe to run again and again.
#   BUILD_DIR=build BUILD_TYPE=Release scripts/build.sh [extra cmake args]
# TARGETS="a b" builds only those targets (and what they need).
set -euo pipefail
cd "$(dirname "$0")/.."

./scripts/install-deps.sh

BUILD_DIR=${BUILD_DIR:-build}
BUILD_TYPE=${BUILD_TYPE:-Release}
JOBS=${JOBS:-2}
cmake_args=(-S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE="$BUILD_TYPE")
# CI treats warnings as errors.
[[ "${CI:-}" == "true" ]] && cmake_args+=(-DTUMBLE_WERROR=ON)

cmake "${cmake_args[@]}" "$@" >/dev/null
build_args=(--build "$BUILD_DIR" -j "$JOBS")
# shellcheck disable=SC2206  # a space-separated list of target names
[[ -n "${TARGETS:-}" ]] && build_args+=(--target ${TARGETS})
cmake "${build_args[@]}"
