#!/usr/bin/env bash
# The image test. Builds docker/Dockerfile and runs the image as users do:
# under Debian's Docker engine (docker.io, with Compose v1, docker-compose)
# where a dockerd can run, under podman where none can. No registry is
# needed: the Debian base images are made here by debootstrap. It checks
# from the host with the host's tumble CLI:
#   1. `docker run` with published ports and a named volume: tumbled
#      answers through the published port, runs as uid 10001 as PID 1, and
#      the image's HEALTHCHECK passes (docker: `docker inspect` reports the
#      container healthy); GET / on the published HTTP port returns the
#      viewer's page, byte for byte as in web/dist;
#   2. an impulse moves the crate;
#   3. `docker stop` (SIGTERM) ends the container with exit code 0;
#   4. persistence: a new container on the same volume resumes the world where
#      the first one stopped (the tick goes on, the crate keeps its velocity
#      and is where that velocity has taken it).
# Under Docker, then the two Compose files as their comments run them:
#   5. docker/compose.yaml: `up -d` starts tumbled and the pusher, whose five
#      frames (`logs pusher`) show the crate moving; `down` saves the world
#      to the volume and the next `up` resumes it at the tick it was saved
#      at; `stop` ends tumbled with exit code 0 and the world saved;
#   6. docker/compose.nats.yaml: through each of the three nodes an
#      observer finds world demo with a leader and a standby, lists the
#      bodies and has its force refused; the file's client pushes the crate
#      and its five frames show it moving; the node the leader is connected
#      to is SIGKILLed and the leader reconnects to another, its frames
#      reach the host through the others; the leader is SIGKILLed and the
#      standby leads with a larger epoch, publishes frames and answers on
#      its own TCP port.
# Under podman (no Compose there), parts 5 and 6 are replaced by
# compose.nats.yaml's topology started container by container on a podman
# network: the same roles, frames, node SIGKILL and reconnection, then a
# leader and a standby and the takeover.
# Prints the engine it used, the runtime image size, the build time and the
# time of each part. Every container, volume and network it made is removed
# at the end, whatever happens; so is its own dockerd.
#
#   docker/test-image.sh [PATH/TO/tumble]   (or TUMBLE_CLI; default build/client/cli/tumble)
#
# Environment:
#   ENGINE      docker, podman, or auto (the default): Docker when a daemon
#               answers (DOCKER_HOST, or the default socket) or one can be
#               started here, podman otherwise
#   WORK        the cached base images (debootstrap's trees as tar files),
#               podman's storage and config, logs (default /tmp/tumble-image,
#               or ~/.cache/tumble-image for a user who is not root; reused
#               between runs, so only the first run pays for debootstrap)
#   IMAGE       podman: the tag to build (default localhost/tumble:test);
#               Docker builds tumble:latest, the Compose files' name
#   NATS_IMAGE  podman: the tag of the Dockerfile's nats target (default
#               localhost/tumble-nats:test); Docker: tumble-nats:latest
#   DOCKERFILE  default docker/Dockerfile
#   MIRROR      Debian mirror for debootstrap (default: the one apt uses)
#
# The dockerd this test starts when none answers is its own: its socket,
# pid file and data live in a temporary directory, its containers on a
# bridge of its own (not docker0), and at the end it is stopped (by the pid
# in its pid file), what it left mounted is unmounted, and the directory,
# the bridge and the bridge's iptables rules are removed. A daemon it did not start is used, never stopped: its
# images tumble:latest and tumble-nats:latest are rebuilt, as `docker build`
# would; the rest it makes has this run's names and is removed.
#
# Runs as root (a dockerd of its own, or rootful podman; re-runs itself
# through sudo otherwise, unless a Docker daemon already answers this user)
# and installs docker.io, docker-compose, podman (with runc, netavark and
# aardvark-dns), debootstrap and jq with apt-get when they are missing.
# shellcheck disable=SC2016  # jq programs, in single quotes on purpose
set -Eeuo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
CLI=${1:-${TUMBLE_CLI:-$ROOT/build/client/cli/tumble}}
ENGINE=${ENGINE:-auto}
USER_WORK=${WORK:-}
if [[ $(id -u) -eq 0 ]]; then WORK=${WORK:-/tmp/tumble-image}; else WORK=${WORK:-${XDG_CACHE_HOME:-$HOME/.cache}/tumble-image}; fi
DOCKERFILE=${DOCKERFILE:-$ROOT/docker/Dockerfile}
SUITE=bookworm
RUN_ID=tumble-test-$$
VOLUME=$RUN_ID-data
# Debian's client: a newer docker elsewhere on PATH may speak a newer API
# than Debian's daemon (20.10) accepts.
DOCKER=/usr/bin/docker
COMPOSE=/usr/bin/docker-compose
# The classic builder, the one Debian's 20.10 uses by default; Compose v1
# builds through the API, never through BuildKit.
export DOCKER_BUILDKIT=0 COMPOSE_DOCKER_CLI_BUILD=0
# A token for this run: the container and the host CLI both get it through
# TUMBLE_TOKEN, which checks that the variable reaches tumbled (and the
# HEALTHCHECK's CLI) inside the container.
TOKEN=test-token-$$-$RANDOM

say() { echo "test-image: $*" >&2; }
die() { echo "test-image: FAIL: $*" >&2; exit 1; }
trap 'echo "test-image: FAIL: unexpected error at line $LINENO: $BASH_COMMAND" >&2' ERR

case $ENGINE in auto | docker | podman) ;; *) die "ENGINE is docker, podman or auto, not '$ENGINE'" ;; esac
[[ -x $CLI ]] || die "the tumble CLI '$CLI' is not an executable (build it, or pass its path as \$1 or TUMBLE_CLI)"
CLI=$(cd "$(dirname "$CLI")" && pwd)/$(basename "$CLI")

docker_answers() { [[ -x $DOCKER ]] && timeout 20 "$DOCKER" info >/dev/null 2>&1; }

# Root for a dockerd of its own or rootful podman; a user whom a running
# Docker daemon already answers needs none.
if [[ $(id -u) -ne 0 ]] && ! { [[ $ENGINE != podman ]] && docker_answers; }; then
  command -v sudo >/dev/null || die "needs root for a dockerd of its own or rootful podman (and sudo is not installed)"
  exec sudo ENGINE="$ENGINE" ${USER_WORK:+WORK="$USER_WORK"} DOCKERFILE="$DOCKERFILE" \
    ${IMAGE:+IMAGE="$IMAGE"} ${NATS_IMAGE:+NATS_IMAGE="$NATS_IMAGE"} ${MIRROR:+MIRROR="$MIRROR"} \
    ${DOCKER_HOST:+DOCKER_HOST="$DOCKER_HOST"} ${CI:+CI="$CI"} "${BASH_SOURCE[0]}" "$CLI"
fi

# ---- 1. packages ---------------------------------------------------------
# As scripts/install-deps.sh installs them. For podman: runc, not crun
# (crun 1.8.1, Debian 12's, refuses cgroup-v1/hybrid hosts), and netavark
# and aardvark-dns, whose networks resolve the containers' names.
packages=(docker.io docker-compose podman runc netavark aardvark-dns debootstrap jq)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  if [[ $(id -u) -eq 0 ]]; then
    say "installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q >/dev/null
    apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null \
      || die "apt-get install ${missing[*]} failed"
  else
    for tool in "$COMPOSE" jq; do command -v "$tool" >/dev/null || die "$tool is missing (install ${missing[*]})"; done
  fi
fi

# One run at a time per WORK. Whatever this run leaves running (a dockerd,
# podman's conmon processes, the cache server) is started with the lock's
# descriptor closed, so that nothing but this shell ever holds the lock.
mkdir -p "$WORK"
exec 9>"$WORK/lock"
if ! flock -n 9; then
  say "waiting for $WORK/lock: another image test is running"
  flock -w 3600 9 || die "another image test has held $WORK/lock for an hour"
fi

# ---- 2. cleanup, whatever happens ----------------------------------------
# Everything this run makes is named after RUN_ID and removed here; the
# functions it calls skip what was never made.
NET=$RUN_ID-net
DOCKERD_DIR=""       # the temporary directory of the dockerd this run started
BRIDGE=""            # that dockerd's bridge
CCACHE_HTTP_PID=""   # the compiler cache server of a docker build
COMPOSE_PROJECTS=()  # Compose projects brought up, as NAME:FILE
E=()                 # the engine's client, once chosen
cleanup() {
  local project
  if [[ -n $CCACHE_HTTP_PID ]]; then
    kill "$CCACHE_HTTP_PID" 2>/dev/null || true
    rm -f "$WORK/ccache-http.port" "$WORK/ccache-http.pid"
  fi
  if ((${#E[@]})); then
    for project in "${COMPOSE_PROJECTS[@]}"; do
      # NAME:FILE; -v: the project's volumes too.
      timeout 120 "$COMPOSE" -p "${project%%:*}" -f "${project#*:}" down -v -t 5 >>"$WORK/compose.log" 2>&1 || true
    done
    # -v: tumbled's anonymous /data volumes too. podman: -t 0, no grace;
    # --ignore, for podman 4.3 removes none of them when one is missing.
    local rm=(rm -f -v)
    [[ $ENGINE == podman ]] && rm+=(-t 0 --ignore)
    e "${rm[@]}" "$RUN_ID-1" "$RUN_ID-2" "$RUN_ID-nats-1" "$RUN_ID-nats-2" "$RUN_ID-nats-3" \
      "$RUN_ID-tumbled" "$RUN_ID-client" "$RUN_ID-leader" "$RUN_ID-standby" >/dev/null 2>&1 || true
    e volume rm -f "$VOLUME" >/dev/null 2>&1 || true
    e network rm "$NET" >/dev/null 2>&1 || true
  fi
  stop_dockerd || true
}
trap cleanup EXIT
# A signal ends the script through exit, so that the EXIT trap still runs.
trap 'die "stopped by SIGTERM"' TERM
trap 'die "stopped by SIGINT"' INT

# ---- 3. the engine: Docker, or podman where no dockerd can run -----------
# E is the engine's client; e runs it, pm runs it with its stderr shown
# only when it fails (podman, where systemd is not running, logs an error
# about the HEALTHCHECK's timer at every run, stop and rm, which is
# harmless: this test runs the check itself with `podman healthcheck run`).
e() { "${E[@]}" "$@" 9>&-; }
pm() {
  local rc=0
  e "$@" 2>"$WORK/engine.err" || rc=$?
  ((rc == 0)) || cat "$WORK/engine.err" >&2
  return "$rc"
}

# A /24 that no route on this host covers or falls inside, for the bridge
# of a dockerd of its own (which must not take docker0, another daemon's).
free_subnet() {
  local n net
  for n in $(seq 0 255); do
    net=10.213.$n.0/24
    if [[ -z $(ip -4 route show root "$net") ]] && ! ip -4 route show match "$net" | grep -qv '^default'; then
      echo "$net"
      return 0
    fi
  done
  return 1
}

# Stops the dockerd that this test started (by the pid in its own pid file)
# and removes what it leaves: mounts under its directory, the iptables rules
# that name its bridge, the bridge, the directory. A no-op when it started
# none.
stop_dockerd() {
  [[ -n $DOCKERD_DIR ]] || return 0
  local dir=$DOCKERD_DIR pid i table line rule
  DOCKERD_DIR=""
  pid=$(cat "$dir/docker.pid" 2>/dev/null || true)
  if [[ $pid =~ ^[0-9]+$ ]] && grep -qF -- "$dir/" "/proc/$pid/cmdline" 2>/dev/null; then
    # SIGTERM: it stops its containers (none are left) and its containerd.
    kill -TERM "$pid" 2>/dev/null || true
    for ((i = 0; i < 120; ++i)); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.25
    done
    if kill -0 "$pid" 2>/dev/null; then
      say "dockerd $pid did not stop within 30 s of SIGTERM: SIGKILL"
      kill -KILL "$pid" 2>/dev/null || true
    fi
  fi
  wait "${DOCKERD_PID:-}" 2>/dev/null || true
  # Overlay layers, network namespaces: deepest first.
  { findmnt -rn -o TARGET | grep -F -- "$dir/" | sort -r | while read -r line; do
      umount "$line" 2>/dev/null || umount -l "$line" 2>/dev/null || true
    done; } || true
  if [[ -n $BRIDGE ]]; then
    for table in nat filter; do
      { iptables -t "$table" -S 2>/dev/null | grep -F -- " $BRIDGE " | grep '^-A ' | while read -r line; do
          read -ra rule <<<"${line#-A }"
          iptables -t "$table" -D "${rule[@]}" 2>/dev/null || true
        done; } || true
    done
    ip link delete "$BRIDGE" 2>/dev/null || true
  fi
  cp "$dir/dockerd.log" "$WORK/dockerd.log" 2>/dev/null || true
  rm -rf "$dir" "$WORK/dockerd.run"
}

# Starts a dockerd of its own: every path of it under a temporary
# directory, its own bridge and containerd namespace, no daemon.json but an
# empty one, so that nothing of another daemon on this machine is shared.
# Returns 1, with the reason in WHY, when it does not answer.
start_dockerd() {
  local subnet i
  command -v dockerd >/dev/null || { WHY="dockerd is not installed"; return 1; }
  command -v iptables >/dev/null || { WHY="iptables is not installed"; return 1; }
  DOCKERD_DIR=$(mktemp -d /tmp/tumble-dockerd.XXXXXX)
  BRIDGE=tumble$$
  # Recorded, so that a run killed before its cleanup is cleaned up by the next.
  echo "$DOCKERD_DIR $BRIDGE" >"$WORK/dockerd.run"
  subnet=$(free_subnet) || { WHY="no free 10.213.x.0/24 for a bridge"; return 1; }
  if ! { ip link add name "$BRIDGE" type bridge && ip address add "${subnet%.0/24}.1/24" dev "$BRIDGE" \
         && ip link set "$BRIDGE" up; } 2>"$DOCKERD_DIR/bridge.err"; then
    WHY="cannot make the bridge $BRIDGE: $(cat "$DOCKERD_DIR/bridge.err")"
    return 1
  fi
  echo '{}' >"$DOCKERD_DIR/daemon.json"
  dockerd --config-file "$DOCKERD_DIR/daemon.json" --host "unix://$DOCKERD_DIR/docker.sock" \
    --data-root "$DOCKERD_DIR/root" --exec-root "$DOCKERD_DIR/exec" --pidfile "$DOCKERD_DIR/docker.pid" \
    --bridge "$BRIDGE" --containerd-namespace "$RUN_ID" --containerd-plugins-namespace "$RUN_ID-plugins" \
    >"$DOCKERD_DIR/dockerd.log" 2>&1 9>&- &
  DOCKERD_PID=$!
  export DOCKER_HOST=unix://$DOCKERD_DIR/docker.sock
  for ((i = 0; i < 120; ++i)); do
    "$DOCKER" version >/dev/null 2>&1 && return 0
    kill -0 "$DOCKERD_PID" 2>/dev/null || break
    sleep 0.5
  done
  WHY="dockerd did not answer: $(grep -E 'level=(error|fatal)|failed' "$DOCKERD_DIR/dockerd.log" | tail -n 3)"
  unset DOCKER_HOST
  return 1
}

# A run killed before its cleanup (ctest's timeout sends SIGKILL) leaves its
# dockerd running, and its cache server if it was building: the lock says
# no other run of this WORK is using them.
if [[ -s $WORK/ccache-http.pid ]]; then
  pid=$(cat "$WORK/ccache-http.pid")
  if [[ $pid =~ ^[0-9]+$ ]] && grep -qF ccache-http.py "/proc/$pid/cmdline" 2>/dev/null; then
    say "stopping the cache server an earlier run left (pid $pid)"
    kill "$pid" 2>/dev/null || true
  fi
  rm -f "$WORK/ccache-http.pid"
fi
if [[ -s $WORK/dockerd.run ]]; then
  read -r DOCKERD_DIR BRIDGE <"$WORK/dockerd.run"
  say "stopping the dockerd an earlier run left in $DOCKERD_DIR"
  stop_dockerd
  BRIDGE=""
fi

WHY=""
if [[ $ENGINE != podman ]]; then
  if docker_answers; then
    ENGINE=docker
    say "engine: docker, the daemon at ${DOCKER_HOST:-the default socket} (not started here: used, never stopped)"
  elif [[ $(id -u) -eq 0 ]] && start_dockerd; then
    ENGINE=docker
    say "engine: docker, a dockerd of its own in $DOCKERD_DIR (bridge $BRIDGE)"
  elif [[ $ENGINE == docker ]]; then
    die "ENGINE=docker, but no Docker daemon answers and none could be started here: $WHY"
  else
    say "no dockerd could be started here ($WHY): podman instead"
    stop_dockerd
    ENGINE=podman
  fi
fi
if [[ $ENGINE == docker ]]; then
  E=("$DOCKER")
  # The names the Compose files use.
  IMAGE=tumble:latest
  NATS_IMAGE=tumble-nats:latest
  say "$("$DOCKER" version -f 'Docker Engine {{.Server.Version}} (API {{.Server.APIVersion}})'), $("$COMPOSE" version --short | sed 's/^/docker-compose /')"
else
  E=(podman)
  IMAGE=${IMAGE:-localhost/tumble:test}
  NATS_IMAGE=${NATS_IMAGE:-localhost/tumble-nats:test}
  say "engine: podman $(podman version -f '{{.Client.Version}}' 2>/dev/null)"
  # A private podman config under $WORK/podman: nothing is written to
  # /var/lib/containers, and no lock is shared with anyone else's podman.
  mkdir -p "$WORK/podman"
  cat > "$WORK/podman/storage.conf" <<EOF
[storage]
driver = "overlay"
runroot = "$WORK/podman/runroot"
graphroot = "$WORK/podman/storage"
EOF
  # podman's default rlimits for root (nofile and nproc 1048576) need
  # CAP_SYS_RESOURCE; cap them at what this process may actually set.
  NOFILE=$(ulimit -Hn); [[ $NOFILE == unlimited ]] && NOFILE=1048576
  NPROC=$(ulimit -Hu);  [[ $NPROC == unlimited ]] && NPROC=1048576
  PIDMAX=$(cat /proc/sys/kernel/pid_max)
  ((NPROC > PIDMAX)) && NPROC=$PIDMAX   # podman lowers its own nproc to pid_max
  cat > "$WORK/podman/containers.conf" <<EOF
[containers]
default_capabilities = ["CHOWN","DAC_OVERRIDE","FOWNER","FSETID","KILL","NET_BIND_SERVICE","SETFCAP","SETGID","SETPCAP","SETUID","SYS_CHROOT"]
default_sysctls = ["net.ipv4.ping_group_range=0 0"]
default_ulimits = ["nofile=$NOFILE:$NOFILE", "nproc=$NPROC:$NPROC"]
[engine]
runtime = "runc"
[network]
network_config_dir = "$WORK/podman/networks"
EOF
  export CONTAINERS_STORAGE_CONF=$WORK/podman/storage.conf CONTAINERS_CONF=$WORK/podman/containers.conf
fi

# ---- 4. base images without a registry -----------------------------------
# debootstrap makes the bookworm tree once; it is kept in $WORK/base as two
# tar files, debian:bookworm and :bookworm-slim, which either engine
# imports when it lacks the image, so that the Dockerfile's unmodified FROM
# lines resolve locally. Both get the apt and dpkg settings of Debian's
# own images: no .debs kept, no translations fetched, and dpkg without an
# fsync for every file it unpacks (force-unsafe-io: a build's apt-get
# would otherwise flush several thousand files to disk, beside tests that
# wait on fsync). The slim one is made the way Debian's slim images are:
# the same minbase tree without docs, man pages and translations, and a
# dpkg config that keeps them out of later installs.
BASE=$WORK/base
# The version of the recipe below: trees made by another are made again.
BASE_RECIPE=2
make_base_tars() {
  local mirror=${MIRROR:-}
  # The mirror apt already uses (deb822 sources first, then sources.list).
  [[ -n $mirror ]] || mirror=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/*.sources 2>/dev/null || true)
  [[ -n $mirror ]] || mirror=$(awk '$1=="deb"{print $2; exit}' /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null || true)
  [[ -n $mirror ]] || die "no Debian mirror found in apt's sources; set MIRROR"

  local rootfs=$WORK/rootfs start=$SECONDS
  rm -rf "$rootfs"
  mkdir -p "$BASE"
  say "making the debian:$SUITE base images with debootstrap (a few minutes, once; log: $WORK/debootstrap.log)"
  debootstrap --variant=minbase "$SUITE" "$rootfs" "$mirror" >"$WORK/debootstrap.log" 2>&1 \
    || { tail -n 20 "$WORK/debootstrap.log" >&2; die "debootstrap failed"; }
  rm -rf "$rootfs"/var/cache/apt/archives/*.deb "$rootfs"/var/lib/apt/lists/*
  : > "$rootfs/etc/hostname"
  # As in Debian's images: apt keeps no downloaded .debs and fetches no translations.
  cat > "$rootfs/etc/apt/apt.conf.d/docker-clean" <<'EOF'
DPkg::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
APT::Update::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
Dir::Cache::pkgcache "";
Dir::Cache::srcpkgcache "";
EOF
  echo 'Acquire::Languages "none";' > "$rootfs/etc/apt/apt.conf.d/docker-no-languages"
  echo 'force-unsafe-io' > "$rootfs/etc/dpkg/dpkg.cfg.d/docker-apt-speedup"
  # Written under another name and renamed: a run stopped halfway leaves no
  # tar file that looks complete.
  tar -C "$rootfs" --numeric-owner --exclude='./dev/*' -cf "$BASE/debian-$SUITE.tar.tmp" .
  mv "$BASE/debian-$SUITE.tar.tmp" "$BASE/debian-$SUITE.tar"

  cat > "$rootfs/etc/dpkg/dpkg.cfg.d/docker" <<'EOF'
path-exclude /usr/share/doc/*
path-include /usr/share/doc/*/copyright
path-exclude /usr/share/man/*
path-exclude /usr/share/info/*
path-exclude /usr/share/locale/*
path-include /usr/share/locale/locale.alias
path-exclude /usr/share/lintian/*
path-exclude /usr/share/linda/*
EOF
  find "$rootfs/usr/share/doc" -mindepth 1 ! -type d ! -name copyright -delete
  find "$rootfs/usr/share/locale" -mindepth 1 ! -type d ! -name locale.alias -delete
  find "$rootfs/usr/share/doc" "$rootfs/usr/share/locale" -mindepth 1 -type d -empty -delete
  rm -rf "$rootfs"/usr/share/man/* "$rootfs"/usr/share/info/* "$rootfs"/usr/share/lintian/* "$rootfs"/usr/share/linda/*
  tar -C "$rootfs" --numeric-owner --exclude='./dev/*' -cf "$BASE/debian-$SUITE-slim.tar.tmp" .
  mv "$BASE/debian-$SUITE-slim.tar.tmp" "$BASE/debian-$SUITE-slim.tar"
  rm -rf "$rootfs"
  echo "$BASE_RECIPE" >"$BASE/recipe"
  say "base image trees made in $((SECONDS - start)) s"
}

# The names FROM debian:TAG resolves to: podman's short-name alias, and
# Docker's own.
base_name() { if [[ $ENGINE == podman ]]; then echo "docker.io/library/debian:$1"; else echo "debian:$1"; fi; }
# Whether the engine has debian:TAG to build on. podman's storage is this
# test's own and kept: the image it imported from this recipe's tree (its
# id recorded at the import). A dockerd of its own starts empty. A Docker
# daemon it did not start: any, Debian's own included.
have_base() {  # TAG
  local id
  id=$(e image inspect -f '{{.Id}}' "$(base_name "$1")" 2>/dev/null) || return 1
  [[ $ENGINE == docker ]] || [[ $(cat "$WORK/podman/debian-$1.imported" 2>/dev/null) == "$BASE_RECIPE $id" ]]
}
base_start=$SECONDS
if [[ -d $BASE && $(cat "$BASE/recipe" 2>/dev/null) != "$BASE_RECIPE" ]]; then
  say "the base image trees in $BASE are of another recipe: making them again"
  rm -f "$BASE"/debian-*.tar
fi
for tag in "$SUITE" "$SUITE-slim"; do
  if have_base "$tag"; then
    continue
  fi
  if [[ ! -s $BASE/debian-$tag.tar ]]; then
    [[ $(id -u) -eq 0 ]] || { say "debian:$tag is missing and debootstrap needs root: the build will pull it"; continue; }
    make_base_tars
  fi
  pm import -c 'CMD ["/bin/bash"]' "$BASE/debian-$tag.tar" "$(base_name "$tag")" >/dev/null \
    || die "importing $BASE/debian-$tag.tar as debian:$tag failed"
  if [[ $ENGINE == podman ]]; then
    e tag "$(base_name "$tag")" "localhost/debian:$tag"
    echo "$BASE_RECIPE $(e image inspect -f '{{.Id}}' "$(base_name "$tag")")" >"$WORK/podman/debian-$tag.imported"
  fi
  say "imported debian:$tag from $BASE/debian-$tag.tar"
done
BASE_SECONDS=$((SECONDS - base_start))

# ---- 5. build ----------------------------------------------------------------
# The build stage compiles through the host's ccache when there is one: a
# host build of the same tree (scripts/test.sh's, before this test in CI)
# has compiled the same files with the same flags, -Werror included when
# CI=true, so the image's compile is mostly cache hits. podman mounts the
# cache at /ccache; `docker build` mounts nothing, so ccache in the build
# reads the host's cache over HTTP instead (docker/ccache-http.py, on the
# address of the bridge that the build's containers are on, read-only).
build_args=(--build-arg "TUMBLE_WERROR=$([[ ${CI:-} == true ]] && echo ON || echo OFF)")
cache_dir=""
if command -v ccache >/dev/null && cache_dir=$(ccache -k cache_dir 2>/dev/null) && [[ -d $cache_dir ]]; then
  if [[ $ENGINE == podman ]]; then
    build_args+=(--volume "$cache_dir:/ccache")
    say "compiling through the host's ccache in $cache_dir"
  else
    gateway=$(e network inspect bridge -f '{{range .IPAM.Config}}{{.Gateway}}{{end}}' 2>/dev/null || true)
    [[ -n $gateway ]] || gateway=$(ip -4 -o address show dev "${BRIDGE:-docker0}" 2>/dev/null | awk '{sub(/\/.*/, "", $4); print $4; exit}')
    rm -f "$WORK/ccache-http.port"
    if [[ -n $gateway ]] && command -v python3 >/dev/null; then
      python3 "$ROOT/docker/ccache-http.py" "$cache_dir" "$gateway" "$WORK/ccache-http.port" \
        2>"$WORK/ccache-http.log" 9>&- &
      CCACHE_HTTP_PID=$!
      echo "$CCACHE_HTTP_PID" >"$WORK/ccache-http.pid"
      for ((i = 0; i < 40; ++i)); do
        [[ -s $WORK/ccache-http.port ]] && break
        kill -0 "$CCACHE_HTTP_PID" 2>/dev/null || break
        sleep 0.25
      done
      if [[ -s $WORK/ccache-http.port ]]; then
        build_args+=(--build-arg "CCACHE_REMOTE_STORAGE=http://$gateway:$(cat "$WORK/ccache-http.port")|read-only")
        say "compiling through the host's ccache in $cache_dir, served on $gateway"
      else
        say "no ccache over HTTP (see $WORK/ccache-http.log): compiling from nothing"
      fi
    fi
  fi
fi
say "building $IMAGE from $DOCKERFILE (log: $WORK/build.log)"
build_start=$SECONDS
if [[ $ENGINE == podman ]]; then
  # --format docker keeps the HEALTHCHECK (the OCI image format has no field for it).
  build=(build --pull=never --format docker)
else
  build=(build)
fi
e "${build[@]}" "${build_args[@]}" -f "$DOCKERFILE" -t "$IMAGE" "$ROOT" >"$WORK/build.log" 2>&1 \
  || { tail -n 40 "$WORK/build.log" >&2; die "$ENGINE build failed (full log: $WORK/build.log)"; }
BUILD_SECONDS=$((SECONDS - build_start))
if [[ -n $CCACHE_HTTP_PID ]]; then
  kill "$CCACHE_HTTP_PID" 2>/dev/null || true
  wait "$CCACHE_HTTP_PID" 2>/dev/null || true
  CCACHE_HTTP_PID=""
  rm -f "$WORK/ccache-http.port" "$WORK/ccache-http.pid"
fi
IMAGE_BYTES=$(e image inspect -f '{{.Size}}' "$IMAGE")
BASE_BYTES=$(e image inspect -f '{{.Size}}' "$(base_name "$SUITE-slim")")
# Housekeeping in podman's cache, never fatal: tag the build stage's last
# image (the line "--> ID" before the first stage on bookworm-slim starts)
# so that its compile stays cached, then prune what earlier builds left
# untagged (about 15 MB each).
if [[ $ENGINE == podman ]]; then
  build_stage=$(awk '/^\[[0-9]+\/[0-9]+\] STEP 1\/[0-9]+: FROM debian:bookworm-slim/{exit} /^--> [0-9a-f]+$/{id=$2} END{print id}' \
    "$WORK/build.log")
  if [[ -n $build_stage ]] && podman tag "$build_stage" "$IMAGE-build" 2>/dev/null; then
    podman image prune -f >/dev/null 2>&1 || true
  fi
fi
say "built in $BUILD_SECONDS s; image size $IMAGE_BYTES bytes"

# The classic builder has built the nats stage already (it builds every
# stage), so this is a cache hit there; with the same build arguments,
# which are part of the build stage's cache key.
say "building $NATS_IMAGE, the Dockerfile's nats target (log: $WORK/build-nats.log)"
nats_build_start=$SECONDS
e "${build[@]}" "${build_args[@]}" --target nats -f "$DOCKERFILE" -t "$NATS_IMAGE" "$ROOT" >"$WORK/build-nats.log" 2>&1 \
  || { tail -n 40 "$WORK/build-nats.log" >&2; die "$ENGINE build --target nats failed (full log: $WORK/build-nats.log)"; }
say "built $NATS_IMAGE in $((SECONDS - nats_build_start)) s"

# ---- 6. run and check --------------------------------------------------------
export TUMBLE_TOKEN=$TOKEN
HOSTPORT=
HTTPPORT=
# The host's CLI against the published port, never waiting forever.
cli() { timeout 30 "$CLI" --server "127.0.0.1:$HOSTPORT" --timeout "${CLI_TIMEOUT:-10}" "$@"; }

# Polls a command until it succeeds: until_ok TRIES COMMAND...; half a second apart.
until_ok() {
  local tries=$1 i
  shift
  for ((i = 0; i < tries; ++i)); do
    "$@" && return 0
    sleep 0.5
  done
  return 1
}

show_logs() {  # NAME
  say "---- logs of $1 ----"
  e logs "$1" 2>&1 | tail -n 40 >&2 || true
}

# The host port an engine published for a container's PORT (podman and
# docker print 127.0.0.1:PORT).
published() {  # NAME PORT
  local port
  port=$(e port "$1" "$2/tcp" | head -n 1 | sed 's/.*://')
  [[ $port =~ ^[0-9]+$ ]] || die "no host port published for $1's $2"
  echo "$port"
}

# Waits until the host CLI lists bodies through 127.0.0.1:HOSTPORT, while
# the container NAME (a name or an ID; LABEL in messages) runs.
wait_answering() {  # NAME [LABEL]
  local name=$1 label=${2:-$1} i
  for ((i = 0; i < 60; ++i)); do
    if [[ $(e inspect -f '{{.State.Running}}' "$name") != true ]]; then
      show_logs "$name"
      die "$label exited before answering (exit code $(e inspect -f '{{.State.ExitCode}}' "$name"))"
    fi
    CLI_TIMEOUT=2 cli bodies >/dev/null 2>&1 && { say "$label answers on 127.0.0.1:$HOSTPORT"; return 0; }
    sleep 0.5
  done
  show_logs "$name"
  die "$label did not answer 'tumble bodies' on 127.0.0.1:$HOSTPORT within 30 s"
}

# Starts a container on the volume with the image's default command (the
# engine picks free host ports) and waits until the host CLI lists bodies.
start_container() {  # NAME
  local name=$1
  pm run -d --name "$name" -p 127.0.0.1::7400 -p 127.0.0.1::8080 -v "$VOLUME:/data" -e TUMBLE_TOKEN \
    "$IMAGE" >/dev/null || die "$ENGINE run $name failed"
  HOSTPORT=$(published "$name" 7400)
  HTTPPORT=$(published "$name" 8080)
  wait_answering "$name"
}

# The image's HEALTHCHECK on a running server. Docker runs it itself (the
# first time `interval`, 10 s, after the start) and reports the state, which
# is polled here; podman runs it only from a systemd timer, so here, once.
check_health() {  # NAME
  local name=$1 status="" i
  if [[ $ENGINE == podman ]]; then
    podman healthcheck run "$name" >/dev/null 2>&1 \
      || { show_logs "$name"; die "the image's HEALTHCHECK fails on a running server"; }
    return 0
  fi
  for ((i = 0; i < 120; ++i)); do
    status=$(e inspect -f '{{if .State.Health}}{{.State.Health.Status}}{{else}}none{{end}}' "$name")
    case $status in
      healthy) return 0 ;;
      none) die "$IMAGE has no HEALTHCHECK (docker inspect shows no health state)" ;;
      unhealthy) break ;;
    esac
    sleep 0.5
  done
  show_logs "$name"
  say "health checks: $(e inspect -f '{{json .State.Health.Log}}' "$name")"
  die "docker inspect reports $name $status, not healthy, within 60 s"
}

# Sets T, Z and V: the tick, and the crate's position and velocity along
# AXIS (default 2, z), from one ListBodies (one tick's state). The crate is
# pushed along +z, where the demo world has nothing in its way.
read_crate() {  # [AXIS]
  local line
  line=$(cli --json bodies | jq -er --argjson a "${1:-2}" '.tick as $t | .bodies[] | select(.name == "crate")
                                     | "\($t) \(.position[$a]) \(.linear_velocity[$a])"') \
    || die "cannot read the crate from 'tumble --json bodies'"
  read -r T Z V <<<"$line"
}

# GET PATH on the published HTTP port with bash's /dev/tcp (no HTTP client
# in the image or needed on the host); the whole response, headers and
# body, goes to FILE.
http_get() {  # PATH FILE
  local fd
  exec {fd}<>"/dev/tcp/127.0.0.1/$HTTPPORT" || return 1
  printf 'GET %s HTTP/1.1\r\nHost: 127.0.0.1:%s\r\nConnection: close\r\n\r\n' "$1" "$HTTPPORT" >&"$fd"
  timeout 10 cat <&"$fd" >"$2"
  local rc=$?
  exec {fd}<&-
  return "$rc"
}

# Evaluates a jq condition on numbers, e.g. check '$a > $b' a 1 b 2.
check() {
  local expr=$1; shift
  local args=()
  while (($#)); do args+=(--argjson "$1" "$2"); shift 2; done
  jq -ne "${args[@]}" "$expr" >/dev/null
}

stop_container() {  # NAME: SIGTERM, then the exit code must be 0
  local name=$1 start=$SECONDS rc
  pm stop -t 20 "$name" >/dev/null || die "$ENGINE stop $name failed"
  rc=$(e inspect -f '{{.State.ExitCode}}' "$name")
  e logs "$name" >"$WORK/$name.log" 2>&1 || true
  if [[ $rc != 0 ]]; then
    show_logs "$name"
    die "$name exited with $rc after SIGTERM (expected 0; 137 means SIGTERM was ignored and it was killed)"
  fi
  say "$name stopped by SIGTERM with exit code 0 in $((SECONDS - start)) s"
}

# Whether the volume VOLUME holds a saved world, asked of a throwaway
# container (the engine's own view of the volume, wherever it keeps it).
has_state() {  # VOLUME
  e run --rm --no-healthcheck -v "$1:/data" --entrypoint test "$IMAGE" -s /data/world.state 2>/dev/null
}

run_start=$SECONDS
pm volume create "$VOLUME" >/dev/null

# -- first container: the image as shipped, on a new volume
start_container "$RUN_ID-1"

[[ $(e exec "$RUN_ID-1" id -u) == 10001 ]] || die "the server does not run as uid 10001"
[[ $(e exec "$RUN_ID-1" cat /proc/1/comm) == tumbled ]] \
  || die "PID 1 in the container is not tumbled (so it would not get docker stop's SIGTERM)"
check_health "$RUN_ID-1"
say "runs as uid 10001, tumbled is PID 1, $([[ $ENGINE == docker ]] && echo "docker inspect reports it healthy" || echo "healthcheck passes")"

# The viewer's page: the status line, its type, and the body exactly as in
# web/dist (the headers end at the first empty line).
http_get / "$WORK/page.http" || die "GET / on 127.0.0.1:$HTTPPORT failed"
headers=$(sed -n '1,/^\r$/p' "$WORK/page.http")
[[ $headers == "HTTP/1.1 200 OK"* ]] || die "GET / did not answer 200 OK: ${headers%%$'\r'*}"
grep -qi '^content-type: text/html' <<<"$headers" || die "GET / is not served as text/html: $headers"
sed '1,/^\r$/d' "$WORK/page.http" >"$WORK/page.body"
cmp -s "$WORK/page.body" "$ROOT/web/dist/index.html" \
  || die "GET / does not return web/dist/index.html byte for byte"
say "GET / on the HTTP port returns web/dist/index.html"

read_crate; t0=$T z0=$Z v0=$V
check '$v == 0' v "$v0" || die "the crate moves before any command (velocity $v0): not a fresh world"

# The crate weighs 2 kg and the demo world has no gravity: 2 N s along z
# gives it exactly 1 m/s.
cli --json impulse crate --impulse 0 0 2 >/dev/null || die "'tumble impulse' failed"
# Reads the crate once the world has stepped a quarter of a second (60
# ticks at 240 Hz) past tick FROM.
past() { read_crate; check '$t >= $f + 60' t "$T" f "$1"; }
later_than() {  # FROM
  until_ok 20 past "$1" || die "the tick did not advance by 60 within 10 s (tick $T, from $1)"
}
later_than "$t0"; ta=$T za=$Z va=$V
check '($v - 1 | fabs) < 1e-9' v "$va" || die "after an impulse of 2 N s the crate's velocity is $va, not 1 m/s"
check '$a > $b' a "$za" b "$z0" || die "the crate did not move: z=$z0 at tick $t0, $za at tick $ta"
frame=$(cli --json subscribe --bodies crate --rate 10 --count 2 | tail -n 1) || die "'tumble subscribe' failed"
zs=$(jq -er '.bodies[0].position[2]' <<<"$frame") || die "unexpected subscribe frame: $frame"
check '$a > $b' a "$zs" b "$za" || die "the subscribed frame shows the crate at z=$zs, not past $za"
later_than "$ta"; tb=$T zb=$Z vb=$V
say "the crate moves: z=$z0 at tick $t0, z=$za at tick $ta, z=$zb at tick $tb, v=$vb m/s"

stop_container "$RUN_ID-1"
pm rm "$RUN_ID-1" >/dev/null

# ---- 7. persistence: a new container on the same volume ------------------
# tumbled writes the world to /data/world.state on SIGTERM and resumes from it
# when it exists; the crate must go on from where it was, at the same velocity.
has_state "$VOLUME" \
  || die "persistence: no /data/world.state in the volume after '$ENGINE stop' (tumbled --state not saving?)"

start_container "$RUN_ID-2"
read_crate; tc=$T zc=$Z vc=$V
say "after the restart: z=$zc at tick $tc, v=$vc m/s"
check '$c > $b' b "$tb" c "$tc" \
  || die "persistence: the world restarted at tick $tc, not after tick $tb where it was before the stop"
check '($c - $a | fabs) < 1e-9' a "$vb" c "$vc" \
  || die "persistence: the crate's velocity is $vc after the restart, it was $vb"
# Constant velocity, no gravity: z grows by the same amount per tick as it
# did between the two reads before the stop (ta -> tb).
check '($zc - ($zb + ($zb - $za) / ($tb - $ta) * ($tc - $tb)) | fabs) < 1e-5' \
    za "$za" zb "$zb" ta "$ta" tb "$tb" zc "$zc" tc "$tc" \
  || die "persistence: the crate is at z=$zc at tick $tc, not on its track before the stop (z=$zb at tick $tb, $vb m/s)"
say "persistence: the world resumed where it stopped"

stop_container "$RUN_ID-2"
pm rm -v "$RUN_ID-2" >/dev/null
pm volume rm "$VOLUME" >/dev/null
RUN_SECONDS=$((SECONDS - run_start))

# ---- helpers of the NATS parts ----------------------------------------------
# This run's passwords, letters and digits only: they travel in URLs.
export TUMBLE_NATS_OBSERVER_PASSWORD=obs$$x$RANDOM$RANDOM
export TUMBLE_NATS_CONTROLLER_PASSWORD=ctl$$x$RANDOM$RANDOM
export TUMBLE_NATS_TUMBLED_PASSWORD=tbd$$x$RANDOM$RANDOM
INNER_ADDRS=(nats-1:4222 nats-2:4222 nats-3:4222)
declare -A NATS_PORT

# USER PASSWORD HOST:PORT... -> nats://USER:PASSWORD@HOST:PORT,... (the CLI's and tumbled's --nats)
nats_urls() {
  local user=$1 password=$2 urls=() address
  shift 2
  for address in "$@"; do urls+=("nats://$user:$password@$address"); done
  (IFS=,; echo "${urls[*]}")
}
# The host's CLI through NATS, never waiting forever: nats_cli URLS ARGS...
nats_cli() { timeout 30 "$CLI" --nats "$1" --timeout "${CLI_TIMEOUT:-10}" "${@:2}"; }
# The host's URL of node I, as USER.
host_url() { nats_urls "$1" "$(password_of "$1")" "127.0.0.1:${NATS_PORT[$2]}"; }
password_of() {
  case $1 in
    observer) echo "$TUMBLE_NATS_OBSERVER_PASSWORD" ;;
    controller) echo "$TUMBLE_NATS_CONTROLLER_PASSWORD" ;;
  esac
}
# The node tumbled is connected to, asked through all three: sets server
# (its URL as tumbled reports it), node (nats-I), killed (its I) and others
# (the two other I's). WHAT names the run in a failure.
find_connected_node() {
  local what=$1 i
  server=$(nats_cli "$(host_url controller 1),$(host_url controller 2),$(host_url controller 3)" \
    --world demo --json stats | jq -r '.nats.server_url') || die "$what: 'tumble --nats ... stats' failed"
  node=${server#nats://}
  node=${node%%:*}
  [[ $node =~ ^nats-[123]$ ]] || die "$what: tumbled is connected to '$server', not to one of nats-1, nats-2, nats-3"
  killed=${node#nats-}
  others=()
  for i in 1 2 3; do ((i == killed)) || others+=("$i"); done
}
# Whether tumbled, asked through the nodes in $survivors, is connected
# again, to another server than $server (find_connected_node's).
reconnected() {
  CLI_TIMEOUT=2 nats_cli "$survivors" --world demo --json stats 2>/dev/null \
    | jq -e --arg gone "$server" '.nats.connected and .nats.reconnects >= 1 and .nats.server_url != $gone' >/dev/null
}
# World demo's servers through URL, as [{id, standby, epoch}], the leader first.
roles() {  # URL
  nats_cli "$1" --json worlds 2>/dev/null \
    | jq -sc '[.[] | select(.world == "demo") | {id: .server_id, standby, epoch}] | sort_by(.standby)'
}

# An observer reads, and may not command: NATS itself refuses its request
# on .rpc, and lets its ListBodies through to .query.
check_observer() {
  local out
  if out=$(nats_cli "$(host_url observer 2)" --world demo force crate --force 0 0 1 2>&1); then
    die "NATS: an observer's force was accepted"
  fi
  [[ $out == "tumble: not permitted: "*'"tumble.v1.demo.rpc"'* ]] \
    || die "NATS: an observer's force failed, but not as 'not permitted' on tumble.v1.demo.rpc: $out"
  say "NATS: an observer's force is refused: $out"
  nats_cli "$(host_url observer 3)" --world demo --json bodies | jq -e '.bodies[] | select(.name == "crate")' >/dev/null \
    || die "NATS: an observer's 'tumble --nats ... bodies' does not list the crate (.query refused?)"
}

# FRAMES (JSON lines of `tumble --json subscribe`) show the crate moving
# along axis AXIS (0: x, 2: z) in COUNT frames, each further than the one
# before; prints the positions.
crate_moves() {  # FRAMES AXIS COUNT
  local positions
  positions=$(jq -sc --argjson a "$2" '[.[].bodies[] | select(.name == "crate") | .position[$a]]' <<<"$1") \
    || return 1
  echo "$positions"
  jq -e --argjson n "$3" 'length == $n and ([range(1; length) as $i | .[$i] > .[$i - 1]] | all)' <<<"$positions" >/dev/null
}

# nats-1's WebSocket listener (the viewer's) upgrades a connection.
check_websocket() {  # PORT
  local ws status
  exec {ws}<>"/dev/tcp/127.0.0.1/$1" || die "NATS: nothing listens on nats-1's WebSocket port"
  printf 'GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n' >&"$ws"
  status=$(timeout 5 head -n 1 <&"$ws" || true)
  exec {ws}<&-
  [[ $status == "HTTP/1.1 101 Switching Protocols"* ]] \
    || die "NATS: nats-1's WebSocket port did not upgrade the connection: ${status%$'\r'}"
}

# FRAMES (JSON lines): COUNT frames, each after tick TICK.
frames_after() {  # FRAMES TICK COUNT
  jq -se --argjson t "$2" --argjson n "$3" 'length == $n and all(.[]; .tick > $t)' <<<"$1" >/dev/null
}

if [[ $ENGINE == docker ]]; then
# ---- 8. docker/compose.yaml, with Compose v1 as a user runs it -----------
# The project's name is this run's (COMPOSE_PROJECT_NAME); the host ports
# are free ones the engine picks (the variables set and empty), read back
# with `port`.
compose_start=$SECONDS
P=$RUN_ID
COMPOSE_PROJECTS+=("$P:$ROOT/docker/compose.yaml")
dc() { COMPOSE_PROJECT_NAME=$P timeout 300 "$COMPOSE" -f "$ROOT/docker/compose.yaml" "$@"; }
export TUMBLE_HOST_PORT='' TUMBLE_HOST_HTTP_PORT=''
# The output of a service's containers, without Compose's "name_1  | ".
service_output() { dc logs --no-color "$1" | sed -n 's/^[^|]*| //p'; }
compose_port() {  # SERVICE PORT
  local port
  port=$(dc port "$1" "$2" | sed 's/.*://')
  [[ $port =~ ^[0-9]+$ ]] || die "Compose: no host port published for $1's $2"
  echo "$port"
}
# Waits for the container ID to end, then prints its exit code.
exit_code() {  # ID
  [[ -n $1 ]] && timeout 120 "$DOCKER" wait "$1"
}
# `up -d`, then waits for the pusher to end and checks its five frames
# along x (10 N for 1 s on the 2 kg crate, from where it is): sets XS to
# the crate's positions in them.
up_and_push() {
  local rc frames
  dc up -d >>"$WORK/compose.log" 2>&1 || { tail -n 30 "$WORK/compose.log" >&2; die "docker-compose up -d failed"; }
  HOSTPORT=$(compose_port tumbled 7400)
  HTTPPORT=$(compose_port tumbled 8080)
  wait_answering "$(dc ps -q tumbled)" "Compose's tumbled"
  rc=$(exit_code "$(dc ps -q pusher)") || die "Compose: the pusher did not end within 120 s"
  frames=$(service_output pusher | grep '^{' || true)
  [[ $rc == 0 ]] || { service_output pusher >&2; die "Compose: the pusher exited with $rc"; }
  XS=$(crate_moves "$frames" 0 5) || die "Compose: the pusher's five frames do not show the crate moving along x: ${XS:-$frames}"
}

say "Compose: docker/compose.yaml as project $P: docker-compose up -d"
up_and_push
say "Compose: tumbled and the pusher came up; the pusher's frames (docker-compose logs pusher): x = $XS"
# The tumbled container was made by Compose, with the image's health check.
check_health "$(dc ps -q tumbled)"
read_crate 0; td=$T xd=$Z

# down: SIGTERM, the world saved to the volume, the containers removed;
# the next up starts a new tumbled on the same volume.
dc down >>"$WORK/compose.log" 2>&1 || { tail -n 30 "$WORK/compose.log" >&2; die "docker-compose down failed"; }
[[ -z $(dc ps -q) ]] || die "Compose: containers left after docker-compose down"
has_state "${P}_tumble-data" || die "Compose: no /data/world.state in the volume ${P}_tumble-data after down"
say "Compose: down saved the world at tick $td or later (crate at x=$xd)"

up_and_push
loaded=$(service_output tumbled | sed -n 's|.* bodies from /data/world.state, at tick \([0-9]*\)$|\1|p' | head -n 1)
[[ $loaded =~ ^[0-9]+$ ]] || { service_output tumbled >&2; die "Compose: tumbled did not load /data/world.state after up"; }
check '$l >= $d' l "$loaded" d "$td" || die "Compose: the world was loaded at tick $loaded, before tick $td it was at"
# The crate only moves along +x, so the new pusher's first frame finds it
# where it was before down, or further.
check '$x >= $d' x "$(jq '.[0]' <<<"$XS")" d "$xd" \
  || die "Compose: after up, the pusher's frames start at x=$(jq '.[0]' <<<"$XS"), behind x=$xd before down"
say "Compose: the next up resumed at tick $loaded (read at $td before down); the pusher's frames: x = $XS"

# stop: SIGTERM, exit code 0, the save in the log.
tumbled_id=$(dc ps -q tumbled)
dc stop >>"$WORK/compose.log" 2>&1 || die "docker-compose stop failed"
rc=$("$DOCKER" inspect -f '{{.State.ExitCode}}' "$tumbled_id")
[[ $rc == 0 ]] || { service_output tumbled | tail -n 20 >&2; die "Compose: tumbled exited with $rc on docker-compose stop"; }
saved=$(service_output tumbled | grep -c 'saved the world at tick .* to /data/world.state' || true)
[[ $saved == 1 ]] || die "Compose: tumbled's log does not say it saved the world once on stop ($saved lines)"
dc down -v >>"$WORK/compose.log" 2>&1 || die "docker-compose down -v failed"
[[ -z $("$DOCKER" volume ls -q --filter "name=${P}_tumble-data") ]] || die "Compose: down -v left the volume"
unset 'COMPOSE_PROJECTS[-1]'
COMPOSE_SECONDS=$((SECONDS - compose_start))
say "Compose: stop ended tumbled with exit code 0 and the world saved; down -v removed the volume ($COMPOSE_SECONDS s)"

# ---- 9. docker/compose.nats.yaml -------------------------------------------
# What the file is for: world demo served through a cluster of three nodes
# (roles by NATS user), its checkpoints in JetStream, a standby that takes
# the world over when the leader goes, and a client that reads it through
# NATS only. The passwords are this run's, the host ports free ones.
cluster_start=$SECONDS
P2=$RUN_ID-nats
COMPOSE_PROJECTS+=("$P2:$ROOT/docker/compose.nats.yaml")
dn() { COMPOSE_PROJECT_NAME=$P2 timeout 300 "$COMPOSE" -f "$ROOT/docker/compose.nats.yaml" "$@"; }
export TUMBLE_HOST_NATS_PORT_1='' TUMBLE_HOST_NATS_PORT_2='' TUMBLE_HOST_NATS_PORT_3='' TUMBLE_HOST_NATS_WS_PORT=''
export TUMBLE_HOST_STANDBY_PORT='' TUMBLE_HOST_STANDBY_HTTP_PORT=''
nats_port() {  # SERVICE PORT
  local port
  port=$(dn port "$1" "$2" | sed 's/.*://')
  [[ $port =~ ^[0-9]+$ ]] || die "Compose (NATS): no host port published for $1's $2"
  echo "$port"
}
say "Compose: docker/compose.nats.yaml as project $P2: docker-compose up -d"
dn up -d >>"$WORK/compose.log" 2>&1 || { tail -n 30 "$WORK/compose.log" >&2; die "docker-compose up -d (compose.nats.yaml) failed"; }
for i in 1 2 3; do NATS_PORT[$i]=$(nats_port "nats-$i" 4222); done
HOSTPORT=$(nats_port tumbled 7400)
[[ $("$DOCKER" exec "$(dn ps -q nats-1)" id -un) == nats ]] || die "nats-server does not run as the user nats"

# Through each node: world demo, a leader (an epoch) and a standby.
leader_and_standby() {
  roles "$1" | jq -e 'length == 2 and .[0].standby == false and .[0].epoch > 0 and .[1].standby == true' >/dev/null
}
for i in 1 2 3; do
  if ! until_ok 120 leader_and_standby "$(host_url observer "$i")"; then
    dn logs --no-color tumbled tumbled-standby | tail -n 40 >&2
    die "Compose (NATS): through nats-$i, world demo has no leader and standby within 60 s: $(roles "$(host_url observer "$i")")"
  fi
done
before=$(roles "$(host_url observer 1)")
say "Compose (NATS): through each of the three nodes, world demo has a leader and a standby: $before"
check_observer
cli bodies >/dev/null || die "Compose (NATS): tumbled does not answer 'tumble bodies' on its TCP port"
check_websocket "$(nats_port nats-1 9222)"

# The file's client, as the controller through NATS only: 20 N along z for
# 0.1 s, then five frames.
rc=$(exit_code "$(dn ps -q client)") || die "Compose (NATS): the client did not end within 120 s"
frames=$(dn logs --no-color client | sed -n 's/^[^|]*| //p' | grep '^{' || true)
[[ $rc == 0 ]] || { dn logs --no-color client >&2; die "Compose (NATS): the client exited with $rc"; }
zs=$(crate_moves "$frames" 2 5) || die "Compose (NATS): the client's five frames do not show the crate moving along z: ${zs:-$frames}"
say "Compose (NATS): the client pushed the crate as the controller and read it moving: z = $zs"

# A node goes: SIGKILL the one the leader is connected to; it reconnects to
# another by itself and its frames go on through the others.
find_connected_node "Compose (NATS)"
tick_killed=$(cli --json bodies | jq -er .tick) || die "cannot read the tick over TCP"
dn kill "$node" >>"$WORK/compose.log" 2>&1 || die "docker-compose kill $node failed"
survivors="$(host_url controller "${others[0]}"),$(host_url controller "${others[1]}")"
until_ok 60 reconnected \
  || { dn logs --no-color tumbled | tail -n 30 >&2; die "Compose (NATS): tumbled did not reconnect within 30 s of $node's SIGKILL"; }
for i in "${others[@]}"; do
  frames=$(nats_cli "$(host_url observer "$i")" --world demo --json subscribe --count 3) \
    || die "Compose (NATS): no frames through nats-$i after $node's SIGKILL"
  frames_after "$frames" "$tick_killed" 3 || die "Compose (NATS): the frames through nats-$i are not after tick $tick_killed: $frames"
done
say "Compose (NATS): $node SIGKILLed (docker-compose kill); tumbled reconnected to $(nats_cli "$survivors" --world demo --json stats | jq -r .nats.server_url), frames go on through the others"
dn start "$node" >>"$WORK/compose.log" 2>&1 || die "docker-compose start $node failed"

# The leader goes: SIGKILL; the standby takes the world over from the
# checkpoints in JetStream, with a larger epoch, publishes frames and opens
# its TCP port.
epoch_before=$(jq -r '.[0].epoch' <<<"$before")
standby_id=$(jq -r '.[1].id' <<<"$before")
all_observer="$(host_url observer 1),$(host_url observer 2),$(host_url observer 3)"
takeover_start=$SECONDS
dn kill tumbled >>"$WORK/compose.log" 2>&1 || die "docker-compose kill tumbled failed"
taken() {
  roles "$all_observer" | jq -e --arg id "$standby_id" --argjson e "$epoch_before" \
    'any(.[]; .id == $id and .standby == false and .epoch > $e)' >/dev/null
}
until_ok 60 taken \
  || { dn logs --no-color tumbled-standby | tail -n 30 >&2; die "Compose (NATS): the standby did not take world demo over within 30 s: $(roles "$all_observer")"; }
TAKEOVER_SECONDS=$((SECONDS - takeover_start))
frames=$(nats_cli "$all_observer" --world demo --json subscribe --count 3) || die "Compose (NATS): no frames from the new leader"
HOSTPORT=$(nats_port tumbled-standby 7400)
until_ok 20 cli bodies >/dev/null 2>&1 || die "Compose (NATS): the new leader does not answer on its TCP port (the standby's 7400)"
say "Compose (NATS): the leader SIGKILLed, the standby leads (epoch $(roles "$all_observer" | jq -r '.[0].epoch'), was $epoch_before) within $TAKEOVER_SECONDS s; frames: $(jq -sc '[.[].tick]' <<<"$frames"); its TCP port answers"
dn down -v >>"$WORK/compose.log" 2>&1 || die "docker-compose down -v (compose.nats.yaml) failed"
unset 'COMPOSE_PROJECTS[-1]'
CLUSTER_SECONDS=$((SECONDS - cluster_start))
fi

if [[ $ENGINE == podman ]]; then
# ---- 8. NATS under podman: a cluster of three nodes, tumbled and a client --
# No Compose here: docker/compose.nats.yaml's topology container by
# container, with the same names on a network of its own (nats-1, nats-2,
# nats-3) and the same arguments; the host reaches each node through a
# published port.
say "NATS: three nodes of $NATS_IMAGE on the network $NET, tumbled for world demo"
cluster_start=$SECONDS
# A client container on the network, as the controller through all three
# nodes, running a shell command; its stdout is the command's.
client() {  # COMMAND
  e run --rm --name "$RUN_ID-client" --no-healthcheck --network "$NET" \
    -e TUMBLE_NATS="$(nats_urls controller "$TUMBLE_NATS_CONTROLLER_PASSWORD" "${INNER_ADDRS[@]}")" \
    --entrypoint sh "$IMAGE" -c "$1" 2>"$WORK/client.err"
}
pm network create "$NET" >/dev/null || die "podman network create $NET failed"

# Node I routes to the two others; nats-1 has websocket.conf, the viewer's listener.
for i in 1 2 3; do
  routes=()
  for j in 1 2 3; do ((j == i)) || routes+=("nats-route://nats-$j:6222"); done
  conf=/etc/nats/auth.conf
  ports=(-p 127.0.0.1::4222)
  if ((i == 1)); then
    conf=/etc/nats/websocket.conf
    ports+=(-p 127.0.0.1::9222)
  fi
  pm run -d --name "$RUN_ID-nats-$i" --network "$NET" --network-alias "nats-$i" "${ports[@]}" \
      -e TUMBLE_NATS_OBSERVER_PASSWORD -e TUMBLE_NATS_CONTROLLER_PASSWORD -e TUMBLE_NATS_TUMBLED_PASSWORD \
      "$NATS_IMAGE" -c "$conf" --name "nats-$i" --cluster_name tumble -js -sd /data/jetstream \
      --cluster nats://0.0.0.0:6222 --routes "$(IFS=,; echo "${routes[*]}")" >/dev/null \
    || die "podman run nats-$i failed"
  NATS_PORT[$i]=$(podman port "$RUN_ID-nats-$i" 4222/tcp | head -n 1 | sed 's/.*://')
  [[ ${NATS_PORT[$i]} =~ ^[0-9]+$ ]] || die "no host port published for nats-$i"
done
[[ $(podman exec "$RUN_ID-nats-1" id -un) == nats ]] || die "nats-server does not run as the user nats"
[[ $(podman exec "$RUN_ID-nats-1" cat /proc/1/comm) == nats-server ]] || die "PID 1 of nats-1 is not nats-server"
pm run -d --name "$RUN_ID-tumbled" --network "$NET" -p 127.0.0.1::7400 -e TUMBLE_TOKEN "$IMAGE" \
    --scene /usr/share/tumble/scenes/demo.json --world demo \
    --nats "$(nats_urls tumbled "$TUMBLE_NATS_TUMBLED_PASSWORD" "${INNER_ADDRS[@]}")" >/dev/null \
  || die "podman run tumbled (--nats) failed"

# The world is found through each node: the routes carry the request to
# tumbled's node and its reply back.
finds_demo() { nats_cli "$1" --json worlds 2>/dev/null | jq -e 'select(.world == "demo")' >/dev/null; }
for i in 1 2 3; do
  if ! until_ok 60 finds_demo "$(host_url observer "$i")"; then
    show_logs "$RUN_ID-tumbled"; show_logs "$RUN_ID-nats-$i"
    die "NATS: 'tumble --nats ... worlds' through nats-$i did not find world demo within 30 s"
  fi
done
say "NATS: an observer's 'tumble --nats ... worlds' finds demo through each of the three nodes"

# tumbled keeps its TCP listener beside NATS.
HOSTPORT=$(podman port "$RUN_ID-tumbled" 7400/tcp | head -n 1 | sed 's/.*://')
cli bodies >/dev/null || die "NATS: tumbled with --nats does not answer 'tumble bodies' over TCP"

check_websocket "$(podman port "$RUN_ID-nats-1" 9222/tcp | head -n 1 | sed 's/.*://')"

check_observer

# The client container, as the controller: 20 N along z for 0.1 s on the
# 2 kg crate (1 m/s, nothing in the way), then five frames of the stream.
frames=$(client 'tumble --world demo force crate --force 0 0 20 --duration 0.1 >/dev/null &&
                 tumble --world demo --json subscribe --count 5') \
  || { cat "$WORK/client.err" >&2; die "NATS: the client container's force and subscribe failed"; }
zs=$(crate_moves "$frames" 2 5) \
  || die "NATS: the client container's five frames do not show the crate moving along z: ${zs:-$frames}"
say "NATS: the client container pushed the crate as the controller and read it moving: z = $zs"

# SIGKILL the node tumbled is connected to.
find_connected_node NATS
tick_killed=$(cli --json bodies | jq -er .tick) || die "cannot read the tick over TCP"
kill_start=$SECONDS
pm kill "$RUN_ID-$node" >/dev/null || die "podman kill $node failed"
rc=$(timeout 30 podman wait "$RUN_ID-$node" 2>/dev/null) || die "NATS: $node still runs after podman kill"
[[ $rc == 137 ]] || die "NATS: $node exited with $rc after podman kill, not 137 (SIGKILL)"

# tumbled notices and reconnects to one of the others, on its own.
survivors="$(host_url controller "${others[0]}"),$(host_url controller "${others[1]}")"
if ! until_ok 60 reconnected; then
  show_logs "$RUN_ID-tumbled"
  die "NATS: tumbled did not reconnect to another node within 30 s of $node's SIGKILL"
fi
reconnect_seconds=$((SECONDS - kill_start))
now=$(nats_cli "$survivors" --world demo --json stats | jq -r '.nats.server_url')
say "NATS: $node SIGKILLed at tick $tick_killed; tumbled reconnected to $now within $reconnect_seconds s"

# Frames keep coming, later than the kill, through each other node to the
# host, and to a client container given all three (one of them gone).
for i in "${others[@]}"; do
  frames=$(nats_cli "$(host_url observer "$i")" --world demo --json subscribe --count 3) \
    || die "NATS: no frames through nats-$i after $node's SIGKILL"
  frames_after "$frames" "$tick_killed" 3 || die "NATS: the frames through nats-$i are not after tick $tick_killed: $frames"
done
frames=$(client 'tumble --world demo --json subscribe --count 3') \
  || { cat "$WORK/client.err" >&2; die "NATS: the client container read no frames after $node's SIGKILL"; }
frames_after "$frames" "$tick_killed" 3 || die "NATS: the client container's frames are not after tick $tick_killed: $frames"
say "NATS: frames after the SIGKILL reach the host through nats-${others[0]} and nats-${others[1]}, and a client container"

# -- The world kept in JetStream: a leader, a standby, a takeover
# As compose.nats.yaml's tumbled and tumbled-standby: --nats-state (the
# bucket needs all three nodes for its three replicas), then SIGKILL the
# leader and the standby leads from the newest checkpoint.
pm stop -t 20 "$RUN_ID-tumbled" >/dev/null || die "podman stop tumbled failed"
pm start "$RUN_ID-$node" >/dev/null || die "podman start $node failed"
NATS_PORT[$killed]=$(podman port "$RUN_ID-$node" 4222/tcp | head -n 1 | sed 's/.*://')
all_nodes=$(nats_urls observer "$TUMBLE_NATS_OBSERVER_PASSWORD" "127.0.0.1:${NATS_PORT[1]}" \
  "127.0.0.1:${NATS_PORT[2]}" "127.0.0.1:${NATS_PORT[3]}")
for role in leader standby; do
  args=(--nats-state)
  [[ $role == standby ]] && args=(--standby)
  pm run -d --name "$RUN_ID-$role" --network "$NET" --no-healthcheck --entrypoint tumbled "$IMAGE" \
      --listen 0.0.0.0:7400 --scene /usr/share/tumble/scenes/demo.json --world demo "${args[@]}" \
      --nats "$(nats_urls tumbled "$TUMBLE_NATS_TUMBLED_PASSWORD" "${INNER_ADDRS[@]}")" >/dev/null \
    || die "podman run tumbled ($role) failed"
  # The leader first: the standby defers to a lease somebody holds.
  if [[ $role == leader ]]; then
    led() {
      nats_cli "$all_nodes" --json worlds 2>/dev/null \
        | jq -se 'map(select(.world == "demo" and .epoch > 0 and (.standby | not))) | length == 1' >/dev/null
    }
    until_ok 120 led || { show_logs "$RUN_ID-leader"; die "JetStream: the leader did not lead world demo within 60 s"; }
  fi
done
has_standby() { roles "$all_nodes" | jq -e 'length == 2 and .[0].standby == false and .[1].standby == true' >/dev/null; }
until_ok 60 has_standby || { show_logs "$RUN_ID-standby"; die "JetStream: no standby answered for world demo: $(roles "$all_nodes")"; }
before=$(roles "$all_nodes")
epoch_before=$(jq -r '.[0].epoch' <<<"$before")
standby_id=$(jq -r '.[1].id' <<<"$before")
say "JetStream: world demo has a leader (epoch $epoch_before) and a standby: $before"
takeover_start=$SECONDS
pm kill "$RUN_ID-leader" >/dev/null || die "podman kill of the leader failed"
taken() {
  roles "$all_nodes" | jq -e --arg id "$standby_id" --argjson e "$epoch_before" \
    'length == 1 and .[0].id == $id and .[0].standby == false and .[0].epoch > $e' >/dev/null
}
until_ok 60 taken || { show_logs "$RUN_ID-standby"; die "JetStream: the standby did not take world demo over within 30 s: $(roles "$all_nodes")"; }
TAKEOVER_SECONDS=$((SECONDS - takeover_start))
frames=$(nats_cli "$all_nodes" --world demo --json subscribe --count 3) || die "JetStream: no frames from the new leader"
say "JetStream: the leader SIGKILLed, the standby leads (epoch $(roles "$all_nodes" | jq -r '.[0].epoch')) within $TAKEOVER_SECONDS s; frames: $(jq -sc '[.[].tick]' <<<"$frames")"
CLUSTER_SECONDS=$((SECONDS - cluster_start))
fi

cleanup
trap - EXIT ERR
echo "test-image: PASS (engine: $ENGINE)"
echo "runtime image: $IMAGE, $IMAGE_BYTES bytes ($((IMAGE_BYTES / 1000000)) MB) as $ENGINE reports it, on debian:$SUITE-slim's $BASE_BYTES"
echo "base images: $BASE_SECONDS s; build: $BUILD_SECONDS s; run, stop and resume: $RUN_SECONDS s"
if [[ $ENGINE == docker ]]; then
  echo "compose.yaml: $COMPOSE_SECONDS s; compose.nats.yaml: $CLUSTER_SECONDS s (the standby's takeover: $TAKEOVER_SECONDS s)"
else
  echo "NATS cluster part: $CLUSTER_SECONDS s (the standby's takeover: $TAKEOVER_SECONDS s)"
fi
echo "total: $SECONDS s"
