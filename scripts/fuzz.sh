#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang into build-fuzz/
# (installing clang and its runtimes when missing) and runs each for
# SECONDS (default 60), starting from its seed corpus. New inputs are kept
# in build-fuzz/tests/fuzz/corpus/<target>/ and grow from run to run; a
# crash leaves its input in build-fuzz/tests/fuzz/ and fails the script.
#   scripts/fuzz.sh [SECONDS]        (JOBS=2, BUILD_DIR=build-fuzz, TARGETS="frame scene state protocol")
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

seconds=${1:-60}
BUILD_DIR=${BUILD_DIR:-build-fuzz}
JOBS=${JOBS:-2}
read -r -a targets <<<"${TARGETS:-frame scene state protocol}"

./scripts/install-deps.sh --fuzz

cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER=clang++-14 \
  -DTUMBLE_FUZZ=ON -DTUMBLE_BUILD_TESTS=OFF -DTUMBLE_BUILD_BENCH=OFF >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS" --target "${targets[@]/%/_fuzz}"

dir="$BUILD_DIR/tests/fuzz"
status=0
for target in "${targets[@]}"; do
  mkdir -p "$dir/corpus/$target"
  log="$dir/$target.log"
  args=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1)
  [[ -f "tests/fuzz/$target.dict" ]] && args+=(-dict="$root/tests/fuzz/$target.dict")
  echo "== ${target}_fuzz for ${seconds}s" >&2
  # libFuzzer logs to stderr; the summary below is read from that log.
  if (cd "$dir" && "./${target}_fuzz" "${args[@]}" "corpus/$target" "$root/tests/fuzz/corpus/$target") \
       >"$log" 2>&1; then
    result=ok
  else
    result="FAILED: a crash, leak or timeout, see $log"
    status=1
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  last=$(grep -E "^#[0-9]+" "$log" | tail -n 1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corpus=$(sed -n 's/.* corp: \([0-9]*\/[0-9a-zA-Z]*\).*/\1/p' <<<"$last")
  printf '%-12s %s: %s executions (%s/s), coverage %s edges, %s features, corpus %s\n' \
    "${target}_fuzz" "$result" "${execs:-?}" "${speed:-?}" "${cov:-?}" "${ft:-?}" "${corpus:-?}"
done
exit "$status"
