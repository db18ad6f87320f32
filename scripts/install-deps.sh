#!/usr/bin/env bash
# Installs the Debian 12 packages tumble needs to build, test and benchmark.
# Idempotent: asks apt only for what dpkg says is missing, and runs
# `apt-get update` only when something is.
#   scripts/install-deps.sh [--fuzz] [extra-package ...]
# --fuzz adds what scripts/fuzz.sh needs besides: clang and its libFuzzer
# and sanitizer runtimes. The default build uses GCC and does not need them.
set -euo pipefail

optional=()
if [[ "${1:-}" == "--fuzz" ]]; then
  optional=(clang-14 libclang-rt-14-dev)
  shift
fi

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libboost-dev libprotobuf-dev protobuf-compiler libspdlog-dev
  nlohmann-json3-dev libcli11-dev
  googletest libgtest-dev libgmock-dev libbenchmark-dev
  libbullet-dev libode-dev
  python3-protobuf
  "${optional[@]}"
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
((${#missing[@]})) || exit 0

echo "installing: ${missing[*]}" >&2
sudo=""
[[ $(id -u) -eq 0 ]] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q >/dev/null
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
