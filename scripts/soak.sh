#!/usr/bin/env bash
# Soak test: a long run of tumbled under steady load, watching for leaks,
# overruns and errors. Not part of ./scripts/test.sh.
#
#   ./scripts/soak.sh                 # 10 minutes
#   DURATION=120 ./scripts/soak.sh    # shorter
#   BUILD=0 ./scripts/soak.sh         # with the binaries already in $BUILD_DIR
#
# Builds tumbled, tumble and net_load (Release, into $BUILD_DIR, default
# build/), starts tumbled (an empty world with gravity) on a free port of
# 127.0.0.1, and runs bench/net's net_load against it for DURATION seconds
# (default 600): its field world of 1000 spheres on the ground (a tenth
# spinning, the rest asleep until pushed), 50 subscribers at 30 Hz in
# full, quantized and delta encodings in turn, 100 requests a second
# (forces, impulses and sets, in turn), and the latency probe. Every 10 s it
# samples tumbled's resident set size (VmRSS); at the end it reads the
# overruns and ticks from `tumble stats`.
#
# Prints a summary, and exits 1 when
#   - RSS grew more than 5% from the first sample after the warm-up (60 s,
#     or half of DURATION when that is shorter) to the last sample,
#   - overruns are 0.1% of the ticks or more,
#   - any error: a request answered by an Error, a stream that broke or a
#     disconnect (net_load's errors), or tumbled gone before the end.
set -euo pipefail
cd "$(dirname "$0")/.."

DURATION=${DURATION:-600}
BUILD_DIR=${BUILD_DIR:-build}
SAMPLE_SECONDS=10
WARMUP=$((DURATION / 2 < 60 ? DURATION / 2 : 60))

if [[ "${BUILD:-1}" != 0 ]]; then
  BUILD_DIR=$BUILD_DIR TARGETS="tumbled tumble net_load" nice ./scripts/build.sh >/dev/null
fi

work=$(mktemp -d)
tumbled_pid=""
cleanup() {
  [[ -n "$tumbled_pid" ]] && kill "$tumbled_pid" 2>/dev/null && wait "$tumbled_pid" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT

"$BUILD_DIR/server/tumbled" --listen 127.0.0.1:0 --port-file "$work/port" \
  --log-level warn 2>"$work/tumbled.log" &
tumbled_pid=$!
for _ in $(seq 600); do [[ -s "$work/port" ]] && break; sleep 0.1; done
[[ -s "$work/port" ]] || { echo "soak: tumbled did not start:" >&2; cat "$work/tumbled.log" >&2; exit 1; }
server=127.0.0.1:$(cat "$work/port")

rss_kib() { awk '/^VmRSS:/ { print $2 }' "/proc/$tumbled_pid/status" 2>/dev/null; }

echo "soak: ${DURATION} s against tumbled (pid $tumbled_pid) at $server; RSS every ${SAMPLE_SECONDS} s, warm-up ${WARMUP} s"
"$BUILD_DIR/bench/net_load" --server "$server" --server-pid "$tumbled_pid" --world field --bodies 1000 \
  --subscribers 50 --rate 30 --encoding mixed --commands-per-second 100 --seconds "$DURATION" \
  >"$work/net_load.out" 2>"$work/net_load.err" &
load_pid=$!

# RSS samples "seconds KiB", every SAMPLE_SECONDS from when the load starts until it ends.
start=$SECONDS
next=0
: >"$work/rss"
while kill -0 "$load_pid" 2>/dev/null; do
  if ((SECONDS - start >= next)); then
    rss=$(rss_kib) || true
    [[ -n "$rss" ]] && echo "$((SECONDS - start)) $rss" >>"$work/rss"
    next=$((next + SAMPLE_SECONDS))
  fi
  sleep 0.2
done
load_status=0
wait "$load_pid" || load_status=$?

failures=()
if ! kill -0 "$tumbled_pid" 2>/dev/null; then
  failures+=("tumbled exited before the end of the run")
fi
report=$(cat "$work/net_load.out")
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<<" $report"; }
errors=$(field errors)
if [[ $load_status -ne 0 || -z "$errors" ]]; then
  failures+=("net_load exited with status $load_status: $(tail -n 3 "$work/net_load.err" | tr '\n' ' ')")
fi
[[ -n "$errors" && "$errors" != 0 ]] && failures+=("$errors errors (see net_load's stderr below)")

stats=$("$BUILD_DIR/client/cli/tumble" --server "$server" --json stats 2>&1) || failures+=("tumble stats: $stats")
overruns=$(sed -n 's/.*"overruns": *\([0-9]*\).*/\1/p' <<<"$stats")
ticks=$(sed -n 's/.*"tick": *\([0-9]*\).*/\1/p' <<<"$stats")
if [[ -n "$overruns" && -n "$ticks" ]] && ((overruns * 1000 >= ticks)); then
  failures+=("overruns $overruns are 0.1% of the $ticks ticks or more")
fi

# RSS: the first sample at or after the warm-up, against the last.
read -r base_t base_rss < <(awk -v w="$WARMUP" '$1 >= w { print; exit }' "$work/rss") || true
read -r last_t last_rss < <(tail -n 1 "$work/rss") || true
read -r min_rss max_rss < <(awk 'NR == 1 { lo = hi = $2 } { if ($2 < lo) lo = $2; if ($2 > hi) hi = $2 } END { print lo, hi }' "$work/rss")
growth="-"
if [[ -n "${base_rss:-}" && -n "${last_rss:-}" ]]; then
  growth=$(awk -v a="$base_rss" -v b="$last_rss" 'BEGIN { printf "%.2f", 100 * (b - a) / a }')
  if awk -v g="$growth" 'BEGIN { exit !(g > 5) }'; then
    failures+=("RSS grew ${growth}% from ${base_rss} KiB at ${base_t} s to ${last_rss} KiB at ${last_t} s")
  fi
else
  failures+=("no RSS sample after the ${WARMUP} s warm-up")
fi

echo "soak: net_load: $report"
echo "soak: RSS samples (s KiB): $(tr '\n' ' ' <"$work/rss" | sed 's/ $//' | awk '{ for (i = 1; i <= NF; i += 2) printf "%s%s:%s", (i > 1 ? ", " : ""), $i, $(i + 1) }')"
echo "soak: RSS min ${min_rss:-?} KiB, max ${max_rss:-?} KiB; after warm-up ${base_rss:-?} KiB at ${base_t:-?} s -> ${last_rss:-?} KiB at ${last_t:-?} s: ${growth}%"
echo "soak: overruns ${overruns:-?} of ${ticks:-?} ticks; errors ${errors:-?}"
if [[ -s "$work/net_load.err" ]]; then
  echo "soak: net_load's stderr (last lines):"
  tail -n 20 "$work/net_load.err"
fi
if ((${#failures[@]} > 0)); then
  printf 'soak: FAIL: %s\n' "${failures[@]}"
  echo "soak: tumbled's warnings (last lines):"
  tail -n 20 "$work/tumbled.log"
  exit 1
fi
echo "soak: PASS"
