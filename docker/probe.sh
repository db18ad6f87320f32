#!/usr/bin/env bash
# Says quickly, installing nothing, whether docker/test-image.sh can run on
# this machine: exit 0 if it can, 1 with the reason on stderr if not. It
# can where a Docker daemon already answers this user, or, as root (or with
# passwordless sudo), where containers can be made: it then starts a
# dockerd of its own, or runs rootful podman where no dockerd can start.
#   docker/probe.sh && ctest -L docker
set -euo pipefail

no() { echo "the container image test cannot run here: $*" >&2; exit 1; }

# A daemon that answers needs nothing else: the test uses it as it is.
if [[ -x /usr/bin/docker ]] && timeout 20 /usr/bin/docker info >/dev/null 2>&1; then
  exit 0
fi

root=()
if [[ $(id -u) -ne 0 ]]; then
  sudo -n true 2>/dev/null || no "no Docker daemon answers, and it needs root or passwordless sudo to start one (or podman)"
  root=(sudo -n)
fi
# It installs docker.io, podman and the rest with apt-get when they are missing.
command -v apt-get >/dev/null || command -v dockerd >/dev/null || command -v podman >/dev/null \
  || no "neither dockerd nor podman is installed, and there is no apt-get to install them"
# Image layers are overlay mounts (both engines); containers need their own namespaces.
grep -qw overlay /proc/filesystems || "${root[@]}" modprobe overlay 2>/dev/null \
  || no "the kernel has no overlay filesystem"
"${root[@]}" unshare --fork --pid --mount --net --uts --ipc true 2>/dev/null \
  || no "new namespaces cannot be made (unshare fails), so no container can start"
exit 0
