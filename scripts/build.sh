#!/usr/bin/env bash
# Installs what is missing and builds tumble into build/ (Release, at most 2
# jobs). Used by run.sh and test.sh; safe to run again and again.
#   BUILD_DIR=build BUILD_TYPE=Release scripts/build.sh [extra cmake args]
# TARGETS="a b" builds only those targets (and what they need).
# UNITY=0 compiles file by file instead of as a unity build (CMake's
# CMAKE_UNITY_BUILD: each target's files sixteen to a compile, which takes
# about half the time from nothing; docs/development.md "Builds").
set -euo pipefail
cd "$(dirname "$0")/.."

./scripts/install-deps.sh

BUILD_DIR=${BUILD_DIR:-build}
BUILD_TYPE=${BUILD_TYPE:-Release}
JOBS=${JOBS:-2}
UNITY=${UNITY:-1}
cmake_args=(-S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE="$BUILD_TYPE")
if [[ "$UNITY" == 0 ]]; then cmake_args+=(-DCMAKE_UNITY_BUILD=OFF); else cmake_args+=(-DCMAKE_UNITY_BUILD=ON); fi
# CI treats warnings as errors.
[[ "${CI:-}" == "true" ]] && cmake_args+=(-DTUMBLE_WERROR=ON)

cmake "${cmake_args[@]}" "$@" >/dev/null
build_args=(--build "$BUILD_DIR" -j "$JOBS")
# shellcheck disable=SC2206  # a space-separated list of target names
[[ -n "${TARGETS:-}" ]] && build_args+=(--target ${TARGETS})
cmake "${build_args[@]}"
