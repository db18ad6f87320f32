#!/usr/bin/env bash
# Says quickly, installing nothing, whether docker/test-image.sh can run on
# this machine: exit 0 if it can, 1 with the reason on stderr if not.
#   docker/probe.sh && ctest -L docker
set -euo pipefail

no() { echo "the container image test cannot run here: $*" >&2; exit 1; }

# test-image.sh runs rootful podman.
root=()
if [[ $(id -u) -ne 0 ]]; then
  sudo -n true 2>/dev/null || no "it needs root or passwordless sudo"
  root=(sudo -n)
fi
# It installs podman, runc and debootstrap with apt-get when they are missing.
command -v apt-get >/dev/null || command -v podman >/dev/null \
  || no "podman is missing and there is no apt-get to install it"
# Image layers are overlay mounts; containers need their own namespaces.
grep -qw overlay /proc/filesystems || "${root[@]}" modprobe overlay 2>/dev/null \
  || no "the kernel has no overlay filesystem"
"${root[@]}" unshare --fork --pid --mount --net --uts --ipc true 2>/dev/null \
  || no "new namespaces cannot be made (unshare fails), so no container can start"
exit 0
