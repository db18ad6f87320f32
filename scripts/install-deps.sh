#!/usr/bin/env bash
# Installs the Debian 12 packages tumble needs to build, test and benchmark.
# Idempotent: asks apt only for what dpkg says is missing, and runs
# `apt-get update` only when something is.
#   scripts/install-deps.sh [--fuzz] [--viewer] [extra-package ...]
# --fuzz adds what scripts/fuzz.sh needs besides: clang and its libFuzzer
# and sanitizer runtimes. The default build uses GCC and does not need them.
# --viewer adds what the browser viewer's tests (ctest label viewer) need:
# Debian's chromium, Node.js and npm when `node` is missing, and web/'s npm
# packages, installed by `npm ci` from web/package-lock.json when
# web/node_modules is missing or was installed from another lockfile. The
# build itself needs none of them: web/dist is committed.
set -euo pipefail
cd "$(dirname "$0")/.."

optional=()
viewer=false
while [[ "${1:-}" == --* ]]; do
  case "$1" in
    --fuzz) optional+=(clang-14 libclang-rt-14-dev) ;;
    --viewer)
      viewer=true
      optional+=(chromium)
      command -v node >/dev/null || optional+=(nodejs npm)
      ;;
    *) echo "install-deps.sh: unknown option $1 (--fuzz, --viewer)" >&2; exit 2 ;;
  esac
  shift
done

packages=(
  build-essential cmake ninja-build pkg-config ccache lld clang-format
  libeigen3-dev libboost-dev libprotobuf-dev protobuf-compiler libspdlog-dev
  nlohmann-json3-dev libcli11-dev
  googletest libgtest-dev libgmock-dev libbenchmark-dev
  libbullet-dev libode-dev
  python3-protobuf
  python3-numpy python3-pytest python3-setuptools python3-pip  # the Python client (clients/python) and its tests
  nats-server libnats-dev
  openssl  # the TLS tests make their own certificate authority
  # The container image test (docker/test-image.sh): Debian's Docker engine
  # and Compose v1, podman and runc where dockerd cannot start (with
  # netavark and aardvark-dns, which only podman's recommends would bring:
  # without them podman takes the CNI plugins, whose networks resolve no
  # container names), debootstrap for the base images, jq for the CLI's JSON.
  docker.io docker-compose podman runc netavark aardvark-dns debootstrap jq
  "${optional[@]}"
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}" >&2
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q >/dev/null
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
fi

if $viewer; then
  # The lockfile's hash, kept in node_modules by the last `npm ci`.
  stamp=web/node_modules/.tumble-package-lock.sha256
  want=$(sha256sum web/package-lock.json | cut -d' ' -f1)
  if [[ ! -f $stamp || "$(cat "$stamp")" != "$want" ]]; then
    echo "installing web/node_modules (npm ci)" >&2
    # No install scripts: esbuild finds its binary in its platform package.
    (cd web && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
    echo "$want" >"$stamp"
  fi
fi
