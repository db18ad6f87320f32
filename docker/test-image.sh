#!/usr/bin/env bash
# The image test. Builds docker/Dockerfile with podman (no Docker engine and
# no registry needed: the Debian base images are made here by debootstrap),
# runs the image with a published port and a named volume, and checks it from
# the host with the host's tumble CLI:
#   1. tumbled answers through the published port, runs as uid 10001 as PID 1,
#      and the image's HEALTHCHECK passes; GET / on the published HTTP port
#      returns the viewer's page, byte for byte as in web/dist;
#   2. an impulse moves the crate;
#   3. `podman stop` (SIGTERM) ends the container with exit code 0;
#   4. persistence: a new container on the same volume resumes the world where
#      the first one stopped (the tick goes on, the crate keeps its velocity
#      and is where that velocity has taken it);
#   5. NATS: docker/compose.nats.yaml's topology on a podman network of its
#      own: three nodes of the Dockerfile's `nats` image routed into one
#      cluster (the first with the WebSocket listener), tumbled for world
#      demo publishing into all three with its TCP listener kept. From the
#      host, through each node, an observer's `tumble --nats ... worlds` finds
#      demo, it lists the bodies and its force is refused; a client
#      container, as the controller, pushes the crate and reads it moving in
#      five frames; then the node tumbled is connected to is SIGKILLed and
#      tumbled reconnects to another, whose frames reach the host and a
#      client container;
#   6. JetStream (the nodes run it, as in compose.nats.yaml): that node back,
#      a leader (--nats-state) and a standby (--standby) for world demo;
#      `tumble worlds` shows both; the leader is SIGKILLed and the standby
#      leads with a larger epoch and publishes frames.
# Then prints the runtime image size, the build time and the time of part 5.
# Every container, volume and the network are removed at the end, whatever
# happens.
#
#   docker/test-image.sh [PATH/TO/tumble]   (or TUMBLE_CLI; default build/client/cli/tumble)
#
# Environment:
#   WORK        podman's storage and config, the cached base images, logs
#               (default /tmp/tumble-podman; reused between runs, so only the
#               first run pays for debootstrap and the build packages)
#   IMAGE       tag to build (default localhost/tumble:test)
#   NATS_IMAGE  tag of the Dockerfile's nats target (default localhost/tumble-nats:test)
#   DOCKERFILE  default docker/Dockerfile
#   MIRROR      Debian mirror for debootstrap (default: the one apt uses)
#
# Runs as root (rootful podman; re-runs itself through sudo otherwise) and
# installs podman, runc, debootstrap and jq with apt-get when they are missing.
set -Eeuo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
CLI=${1:-${TUMBLE_CLI:-$ROOT/build/client/cli/tumble}}
WORK=${WORK:-/tmp/tumble-podman}
IMAGE=${IMAGE:-localhost/tumble:test}
NATS_IMAGE=${NATS_IMAGE:-localhost/tumble-nats:test}
DOCKERFILE=${DOCKERFILE:-$ROOT/docker/Dockerfile}
SUITE=bookworm
RUN_ID=tumble-test-$$
VOLUME=$RUN_ID-data
# A token for this run: the container and the host CLI both get it through
# TUMBLE_TOKEN, which checks that the variable reaches tumbled (and the
# HEALTHCHECK's CLI) inside the container.
TOKEN=test-token-$$-$RANDOM

say() { echo "test-image: $*" >&2; }
die() { echo "test-image: FAIL: $*" >&2; exit 1; }
trap 'echo "test-image: FAIL: unexpected error at line $LINENO: $BASH_COMMAND" >&2' ERR

[[ -x $CLI ]] || die "the tumble CLI '$CLI' is not an executable (build it, or pass its path as \$1 or TUMBLE_CLI)"
CLI=$(cd "$(dirname "$CLI")" && pwd)/$(basename "$CLI")

if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || die "needs root for rootful podman (and sudo is not installed)"
  exec sudo WORK="$WORK" IMAGE="$IMAGE" NATS_IMAGE="$NATS_IMAGE" DOCKERFILE="$DOCKERFILE" ${MIRROR:+MIRROR="$MIRROR"} \
    "${BASH_SOURCE[0]}" "$CLI"
fi

# ---- 1. packages ---------------------------------------------------------
# runc, not crun: crun 1.8.1 (Debian 12) refuses cgroup-v1/hybrid hosts.
packages=(podman runc debootstrap jq)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  say "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q >/dev/null
  apt-get install -y -q "${missing[@]}" >/dev/null || die "apt-get install ${missing[*]} failed"
fi

# ---- 2. private podman config under $WORK --------------------------------
# Nothing is written to /var/lib/containers, and two runs never share a lock
# with anyone else's podman.
mkdir -p "$WORK"
exec 9>"$WORK/lock"
flock -w 3600 9 || die "another image test has held $WORK/lock for an hour"

cat > "$WORK/storage.conf" <<EOF
[storage]
driver = "overlay"
runroot = "$WORK/runroot"
graphroot = "$WORK/storage"
EOF
# podman's default rlimits for root (nofile and nproc 1048576) need
# CAP_SYS_RESOURCE; cap them at what this process may actually set.
NOFILE=$(ulimit -Hn); [[ $NOFILE == unlimited ]] && NOFILE=1048576
NPROC=$(ulimit -Hu);  [[ $NPROC == unlimited ]] && NPROC=1048576
PIDMAX=$(cat /proc/sys/kernel/pid_max)
((NPROC > PIDMAX)) && NPROC=$PIDMAX   # podman lowers its own nproc to pid_max
cat > "$WORK/containers.conf" <<EOF
[containers]
default_capabilities = ["CHOWN","DAC_OVERRIDE","FOWNER","FSETID","KILL","NET_BIND_SERVICE","SETFCAP","SETGID","SETPCAP","SETUID","SYS_CHROOT"]
default_sysctls = ["net.ipv4.ping_group_range=0 0"]
default_ulimits = ["nofile=$NOFILE:$NOFILE", "nproc=$NPROC:$NPROC"]
[engine]
runtime = "runc"
[network]
network_config_dir = "$WORK/networks"
EOF
export CONTAINERS_STORAGE_CONF=$WORK/storage.conf CONTAINERS_CONF=$WORK/containers.conf

# ---- 3. base images without a registry -----------------------------------
# debootstrap -> podman import, tagged docker.io/library/debian:bookworm and
# :bookworm-slim so the Dockerfile's unmodified FROM lines resolve locally.
# The slim one is made the way Debian's slim images are: the same minbase
# tree without docs, man pages and translations, and a dpkg config that
# keeps them out of later installs.
import_rootfs() {  # DIR TAG
  tar -C "$1" --numeric-owner --exclude='./dev/*' -c . \
    | podman import -q --change 'CMD ["/bin/bash"]' - "docker.io/library/debian:$2" >/dev/null
  podman tag "docker.io/library/debian:$2" "localhost/debian:$2"
}

make_base_images() {
  local mirror=${MIRROR:-}
  # The mirror apt already uses (deb822 sources first, then sources.list).
  [[ -n $mirror ]] || mirror=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/*.sources 2>/dev/null || true)
  [[ -n $mirror ]] || mirror=$(awk '$1=="deb"{print $2; exit}' /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null || true)
  [[ -n $mirror ]] || die "no Debian mirror found in apt's sources; set MIRROR"

  local rootfs=$WORK/rootfs start=$SECONDS
  rm -rf "$rootfs"
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
  import_rootfs "$rootfs" "$SUITE"

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
  import_rootfs "$rootfs" "$SUITE-slim"
  rm -rf "$rootfs"
  say "base images made in $((SECONDS - start)) s"
}

if podman image exists "docker.io/library/debian:$SUITE" \
   && podman image exists "docker.io/library/debian:$SUITE-slim"; then
  say "base images debian:$SUITE and :$SUITE-slim already in $WORK"
else
  make_base_images
fi

# ---- 4. build --------------------------------------------------------------
# --format docker keeps the HEALTHCHECK (the OCI image format has no field for it).
# The build stage compiles through the host's ccache when there is one: a
# host build of the same tree (scripts/test.sh's, before this test in CI)
# has compiled the same files with the same flags, -Werror included when
# CI=true, so the image's compile is mostly cache hits.
build_args=(--build-arg "TUMBLE_WERROR=$([[ ${CI:-} == true ]] && echo ON || echo OFF)")
if command -v ccache >/dev/null && cache_dir=$(ccache -k cache_dir 2>/dev/null) && [[ -d $cache_dir ]]; then
  build_args+=(--volume "$cache_dir:/ccache")
  say "compiling through the host's ccache in $cache_dir"
fi
say "building $IMAGE from $DOCKERFILE (log: $WORK/build.log)"
build_start=$SECONDS
podman build --pull=never --format docker "${build_args[@]}" -f "$DOCKERFILE" -t "$IMAGE" "$ROOT" \
    >"$WORK/build.log" 2>&1 \
  || { tail -n 40 "$WORK/build.log" >&2; die "podman build failed (full log: $WORK/build.log)"; }
BUILD_SECONDS=$((SECONDS - build_start))
IMAGE_BYTES=$(podman image inspect --format '{{.Size}}' "$IMAGE")
# Housekeeping, never fatal: tag the build stage's last image (the line
# "--> ID" before the first stage on bookworm-slim starts) so that its
# compile stays cached, then prune what earlier builds left untagged (about
# 15 MB each).
build_stage=$(awk '/^\[[0-9]+\/[0-9]+\] STEP 1\/[0-9]+: FROM debian:bookworm-slim/{exit} /^--> [0-9a-f]+$/{id=$2} END{print id}' \
  "$WORK/build.log")
if [[ -n $build_stage ]] && podman tag "$build_stage" "$IMAGE-build" 2>/dev/null; then
  podman image prune -f >/dev/null 2>&1 || true
fi
say "built in $BUILD_SECONDS s; image size $IMAGE_BYTES bytes"

say "building $NATS_IMAGE, the Dockerfile's nats target (log: $WORK/build-nats.log)"
nats_build_start=$SECONDS
podman build --pull=never --format docker --target nats -f "$DOCKERFILE" -t "$NATS_IMAGE" "$ROOT" \
    >"$WORK/build-nats.log" 2>&1 \
  || { tail -n 40 "$WORK/build-nats.log" >&2; die "podman build --target nats failed (full log: $WORK/build-nats.log)"; }
say "built $NATS_IMAGE in $((SECONDS - nats_build_start)) s"

# ---- 5. run and check --------------------------------------------------------
NET=$RUN_ID-net
cleanup() {
  # -v: tumbled's anonymous /data volumes too.
  podman rm -f -v -t 0 "$RUN_ID-1" "$RUN_ID-2" "$RUN_ID-nats-1" "$RUN_ID-nats-2" "$RUN_ID-nats-3" \
    "$RUN_ID-tumbled" "$RUN_ID-client" "$RUN_ID-leader" "$RUN_ID-standby" >/dev/null 2>&1 || true
  podman volume rm -f "$VOLUME" >/dev/null 2>&1 || true
  podman network rm -f "$NET" >/dev/null 2>&1 || true
}
trap cleanup EXIT
# A signal ends the script through exit, so that the EXIT trap still runs.
trap 'die "stopped by SIGTERM"' TERM
trap 'die "stopped by SIGINT"' INT
podman volume create "$VOLUME" >/dev/null

export TUMBLE_TOKEN=$TOKEN
HOSTPORT=
HTTPPORT=
# The host's CLI against the published port, never waiting forever.
cli() { timeout 30 "$CLI" --server "127.0.0.1:$HOSTPORT" --timeout "${CLI_TIMEOUT:-10}" "$@"; }

# podman with its stderr shown only when it fails: where systemd is not
# running, podman logs an error about the HEALTHCHECK's timer at every run,
# stop and rm, which is harmless (this test runs the check itself with
# `podman healthcheck run`).
pm() {
  local rc=0
  podman "$@" 2>"$WORK/podman.err" || rc=$?
  ((rc == 0)) || cat "$WORK/podman.err" >&2
  return "$rc"
}

show_logs() {  # NAME
  say "---- logs of $1 ----"
  podman logs "$1" 2>&1 | tail -n 40 >&2 || true
}

# Starts a container on the volume with the image's default command (a free
# host port is picked by podman) and waits until the host CLI lists bodies.
start_container() {  # NAME
  local name=$1 i
  pm run -d --name "$name" -p 127.0.0.1::7400 -p 127.0.0.1::8080 -v "$VOLUME:/data" -e TUMBLE_TOKEN \
    "$IMAGE" >/dev/null || die "podman run $name failed"
  HOSTPORT=$(podman port "$name" 7400/tcp | head -n 1 | sed 's/.*://')
  [[ $HOSTPORT =~ ^[0-9]+$ ]] || die "no host port published for $name"
  HTTPPORT=$(podman port "$name" 8080/tcp | head -n 1 | sed 's/.*://')
  [[ $HTTPPORT =~ ^[0-9]+$ ]] || die "no host port published for $name's HTTP (8080)"
  for i in $(seq 60); do
    if [[ $(podman inspect -f '{{.State.Running}}' "$name") != true ]]; then
      show_logs "$name"
      die "$name exited before answering (exit code $(podman inspect -f '{{.State.ExitCode}}' "$name"))"
    fi
    CLI_TIMEOUT=2 cli bodies >/dev/null 2>&1 && { say "$name answers on 127.0.0.1:$HOSTPORT"; return 0; }
    sleep 0.5
  done
  show_logs "$name"
  die "$name did not answer 'tumble bodies' on 127.0.0.1:$HOSTPORT within 30 s"
}

# Sets T, Z and V: the tick, and the crate's z position and z velocity, from
# one ListBodies (one tick's state). The crate is pushed along +z, where the
# demo world has nothing in its way.
read_crate() {
  local line
  line=$(cli --json bodies | jq -er '.tick as $t | .bodies[] | select(.name == "crate")
                                     | "\($t) \(.position[2]) \(.linear_velocity[2])"') \
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
  pm stop -t 20 "$name" >/dev/null || die "podman stop $name failed"
  rc=$(podman inspect -f '{{.State.ExitCode}}' "$name")
  podman logs "$name" >"$WORK/$name.log" 2>&1 || true
  if [[ $rc != 0 ]]; then
    show_logs "$name"
    die "$name exited with $rc after SIGTERM (expected 0; 137 means SIGTERM was ignored and it was killed)"
  fi
  say "$name stopped by SIGTERM with exit code 0 in $((SECONDS - start)) s"
}

# -- first container: the image as shipped, on a new volume
start_container "$RUN_ID-1"

[[ $(podman exec "$RUN_ID-1" id -u) == 10001 ]] || die "the server does not run as uid 10001"
[[ $(podman exec "$RUN_ID-1" cat /proc/1/comm) == tumbled ]] \
  || die "PID 1 in the container is not tumbled (so it would not get docker stop's SIGTERM)"
podman healthcheck run "$RUN_ID-1" >/dev/null 2>&1 \
  || { show_logs "$RUN_ID-1"; die "the image's HEALTHCHECK fails on a running server"; }
say "runs as uid 10001, tumbled is PID 1, healthcheck passes"

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
sleep 1
read_crate; ta=$T za=$Z va=$V
check '($v - 1 | fabs) < 1e-9' v "$va" || die "after an impulse of 2 N s the crate's velocity is $va, not 1 m/s"
check '$a > $b' a "$za" b "$z0" || die "the crate did not move: z=$z0 at tick $t0, $za at tick $ta"
frame=$(cli --json subscribe --bodies crate --rate 10 --count 2 | tail -n 1) || die "'tumble subscribe' failed"
zs=$(jq -er '.bodies[0].position[2]' <<<"$frame") || die "unexpected subscribe frame: $frame"
check '$a > $b' a "$zs" b "$za" || die "the subscribed frame shows the crate at z=$zs, not past $za"
sleep 0.5
read_crate; tb=$T zb=$Z vb=$V
check '$b > $a' a "$ta" b "$tb" || die "the tick did not advance ($ta, then $tb)"
say "the crate moves: z=$z0 at tick $t0, z=$za at tick $ta, z=$zb at tick $tb, v=$vb m/s"

stop_container "$RUN_ID-1"
pm rm "$RUN_ID-1" >/dev/null

# ---- 6. persistence: a new container on the same volume ------------------
# tumbled writes the world to /data/world.state on SIGTERM and resumes from it
# when it exists; the crate must go on from where it was, at the same velocity.
mountpoint=$(podman volume inspect --format '{{.Mountpoint}}' "$VOLUME")
[[ -s $mountpoint/world.state ]] \
  || die "persistence: no /data/world.state in the volume after 'podman stop' (tumbled --state not saving?)"

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

# ---- 7. NATS: a cluster of three nodes, tumbled and a client -------------
# As docker/compose.nats.yaml runs them, with the same names on the network
# (nats-1, nats-2, nats-3) and the same arguments; the host reaches each
# node through a published port.
say "NATS: three nodes of $NATS_IMAGE on the network $NET, tumbled for world demo"
cluster_start=$SECONDS
# This run's passwords, letters and digits only: they travel in URLs.
export TUMBLE_NATS_OBSERVER_PASSWORD=obs$$x$RANDOM$RANDOM
export TUMBLE_NATS_CONTROLLER_PASSWORD=ctl$$x$RANDOM$RANDOM
export TUMBLE_NATS_TUMBLED_PASSWORD=tbd$$x$RANDOM$RANDOM
INNER_ADDRS=(nats-1:4222 nats-2:4222 nats-3:4222)

# USER PASSWORD HOST:PORT... -> nats://USER:PASSWORD@HOST:PORT,... (the CLI's and tumbled's --nats)
nats_urls() {
  local user=$1 password=$2 urls=() address
  shift 2
  for address in "$@"; do urls+=("nats://$user:$password@$address"); done
  (IFS=,; echo "${urls[*]}")
}
# The host's CLI through NATS, never waiting forever: nats_cli URLS ARGS...
nats_cli() { timeout 30 "$CLI" --nats "$1" --timeout "${CLI_TIMEOUT:-10}" "${@:2}"; }
# A client container on the network, as the controller through all three
# nodes, running a shell command; its stdout is the command's.
client() {  # COMMAND
  podman run --rm --name "$RUN_ID-client" --no-healthcheck --network "$NET" \
    -e TUMBLE_NATS="$(nats_urls controller "$TUMBLE_NATS_CONTROLLER_PASSWORD" "${INNER_ADDRS[@]}")" \
    --entrypoint sh "$IMAGE" -c "$1" 2>"$WORK/client.err"
}
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

pm network create "$NET" >/dev/null || die "podman network create $NET failed"

# Node I routes to the two others; nats-1 has websocket.conf, the viewer's listener.
declare -A NATS_PORT
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
# The host's URL of node I, as USER.
host_url() { nats_urls "$1" "$(password_of "$1")" "127.0.0.1:${NATS_PORT[$2]}"; }
password_of() {
  case $1 in
    observer) echo "$TUMBLE_NATS_OBSERVER_PASSWORD" ;;
    controller) echo "$TUMBLE_NATS_CONTROLLER_PASSWORD" ;;
  esac
}

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

# nats-1's WebSocket listener (the viewer's) upgrades a connection.
ws_port=$(podman port "$RUN_ID-nats-1" 9222/tcp | head -n 1 | sed 's/.*://')
exec {ws}<>"/dev/tcp/127.0.0.1/$ws_port" || die "NATS: nothing listens on nats-1's WebSocket port"
printf 'GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n' >&"$ws"
status=$(timeout 5 head -n 1 <&"$ws" || true)
exec {ws}<&-
[[ $status == "HTTP/1.1 101 Switching Protocols"* ]] \
  || die "NATS: nats-1's WebSocket port did not upgrade the connection: ${status%$'\r'}"

# An observer may not command: NATS itself refuses its request on .rpc.
if out=$(nats_cli "$(host_url observer 2)" --world demo force crate --force 0 0 1 2>&1); then
  die "NATS: an observer's force was accepted"
fi
[[ $out == "tumble: not permitted: "*'"tumble.v1.demo.rpc"'* ]] \
  || die "NATS: an observer's force failed, but not as 'not permitted' on tumble.v1.demo.rpc: $out"
say "NATS: an observer's force is refused: $out"
# It reads, though: its ListBodies goes to .query, which auth.conf lets it ask.
nats_cli "$(host_url observer 3)" --world demo --json bodies | jq -e '.bodies[] | select(.name == "crate")' >/dev/null \
  || die "NATS: an observer's 'tumble --nats ... bodies' does not list the crate (.query refused?)"

# The client container, as the controller: 20 N along z for 0.1 s on the
# 2 kg crate (1 m/s, nothing in the way), then five frames of the stream.
frames=$(client 'tumble --world demo force crate --force 0 0 20 --duration 0.1 >/dev/null &&
                 tumble --world demo --json subscribe --count 5') \
  || { cat "$WORK/client.err" >&2; die "NATS: the client container's force and subscribe failed"; }
zs=$(jq -sc '[.[].bodies[] | select(.name == "crate") | .position[2]]' <<<"$frames") \
  || die "NATS: the client's frames are not JSON: $frames"
jq -e 'length == 5 and ([range(1; length) as $i | .[$i] > .[$i - 1]] | all)' <<<"$zs" >/dev/null \
  || die "NATS: the client container's five frames do not show the crate moving along z: $zs"
say "NATS: the client container pushed the crate as the controller and read it moving: z = $zs"

# SIGKILL the node tumbled is connected to.
stats=$(nats_cli "$(host_url controller 1),$(host_url controller 2),$(host_url controller 3)" --world demo --json stats) \
  || die "NATS: 'tumble --nats ... stats' failed"
server=$(jq -r '.nats.server_url' <<<"$stats")
node=${server#nats://}
node=${node%%:*}
[[ $node =~ ^nats-[123]$ ]] || die "NATS: tumbled is connected to '$server', not to one of nats-1, nats-2, nats-3"
killed=${node#nats-}
others=()
for i in 1 2 3; do ((i == killed)) || others+=("$i"); done
tick_killed=$(cli --json bodies | jq -er .tick) || die "cannot read the tick over TCP"
kill_start=$SECONDS
pm kill "$RUN_ID-$node" >/dev/null || die "podman kill $node failed"
rc=$(timeout 30 podman wait "$RUN_ID-$node" 2>/dev/null) || die "NATS: $node still runs after podman kill"
[[ $rc == 137 ]] || die "NATS: $node exited with $rc after podman kill, not 137 (SIGKILL)"

# tumbled notices and reconnects to one of the others, on its own.
survivors="$(host_url controller "${others[0]}"),$(host_url controller "${others[1]}")"
reconnected() {
  CLI_TIMEOUT=2 nats_cli "$survivors" --world demo --json stats 2>/dev/null \
    | jq -e --arg gone "$server" '.nats.connected and .nats.reconnects >= 1 and .nats.server_url != $gone' >/dev/null
}
if ! until_ok 60 reconnected; then
  show_logs "$RUN_ID-tumbled"
  die "NATS: tumbled did not reconnect to another node within 30 s of $node's SIGKILL"
fi
reconnect_seconds=$((SECONDS - kill_start))
now=$(nats_cli "$survivors" --world demo --json stats | jq -r '.nats.server_url')
say "NATS: $node SIGKILLed at tick $tick_killed; tumbled reconnected to $now within $reconnect_seconds s"

# Frames keep coming, later than the kill, through each other node to the
# host, and to a client container given all three (one of them gone).
later() {  # FRAMES (JSON lines): COUNT frames, each after tick_killed
  jq -se --argjson t "$tick_killed" --argjson n "$2" 'length == $n and all(.[]; .tick > $t)' <<<"$1" >/dev/null
}
for i in "${others[@]}"; do
  frames=$(nats_cli "$(host_url observer "$i")" --world demo --json subscribe --count 3) \
    || die "NATS: no frames through nats-$i after $node's SIGKILL"
  later "$frames" 3 || die "NATS: the frames through nats-$i are not after tick $tick_killed: $frames"
done
frames=$(client 'tumble --world demo --json subscribe --count 3') \
  || { cat "$WORK/client.err" >&2; die "NATS: the client container read no frames after $node's SIGKILL"; }
later "$frames" 3 || die "NATS: the client container's frames are not after tick $tick_killed: $frames"
say "NATS: frames after the SIGKILL reach the host through nats-${others[0]} and nats-${others[1]}, and a client container"

# ---- 8. The world kept in JetStream: a leader, a standby, a takeover -----
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
roles() {
  nats_cli "$all_nodes" --json worlds 2>/dev/null \
    | jq -sc '[.[] | select(.world == "demo") | {id: .server_id, standby, epoch}] | sort_by(.standby)'
}
has_standby() { roles | jq -e 'length == 2 and .[0].standby == false and .[1].standby == true' >/dev/null; }
until_ok 60 has_standby || { show_logs "$RUN_ID-standby"; die "JetStream: no standby answered for world demo: $(roles)"; }
before=$(roles)
epoch_before=$(jq -r '.[0].epoch' <<<"$before")
standby_id=$(jq -r '.[1].id' <<<"$before")
say "JetStream: world demo has a leader (epoch $epoch_before) and a standby: $before"
takeover_start=$SECONDS
pm kill "$RUN_ID-leader" >/dev/null || die "podman kill of the leader failed"
taken() {
  roles | jq -e --arg id "$standby_id" --argjson e "$epoch_before" \
    'length == 1 and .[0].id == $id and .[0].standby == false and .[0].epoch > $e' >/dev/null
}
until_ok 60 taken || { show_logs "$RUN_ID-standby"; die "JetStream: the standby did not take world demo over within 30 s: $(roles)"; }
TAKEOVER_SECONDS=$((SECONDS - takeover_start))
frames=$(nats_cli "$all_nodes" --world demo --json subscribe --count 3) || die "JetStream: no frames from the new leader"
say "JetStream: the leader SIGKILLed, the standby leads (epoch $(roles | jq -r '.[0].epoch')) within $TAKEOVER_SECONDS s; frames: $(jq -sc '[.[].tick]' <<<"$frames")"
CLUSTER_SECONDS=$((SECONDS - cluster_start))
cleanup

trap - ERR
echo "test-image: PASS"
echo "runtime image: $IMAGE, $IMAGE_BYTES bytes ($((IMAGE_BYTES / 1000000)) MB)"
echo "build time: $BUILD_SECONDS s"
echo "NATS cluster part: $CLUSTER_SECONDS s (the standby's takeover: $TAKEOVER_SECONDS s)"
