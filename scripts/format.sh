#!/usr/bin/env bash
# Formats the C++ sources git tracks with clang-format and the root
# .clang-format (Debian's clang-format 14, which install-deps.sh installs).
#   scripts/format.sh           rewrites the files in place
#   scripts/format.sh --check   changes nothing; lists the files that are not
#                               formatted and exits 1 when there are any
set -euo pipefail
cd "$(dirname "$0")/.."

mode=fix
case "${1:-}" in
  "") ;;
  --check) mode=check ;;
  *) echo "format.sh: unknown option $1 (--check)" >&2; exit 2 ;;
esac

command -v clang-format >/dev/null || ./scripts/install-deps.sh
mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.hpp' | grep -v '^web/')
if [[ $mode == fix ]]; then
  clang-format -i "${files[@]}"
  exit 0
fi
# clang-format on batches of 64 files, two batches at a time (one process
# a file took 40 s); each file it would change is named in an error line.
report=$(printf '%s\0' "${files[@]}" | xargs -0 -n 64 -P 2 clang-format --dry-run --Werror 2>&1 >/dev/null) && rc=0 || rc=$?
mapfile -t unformatted < <(sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: code should be clang-formatted.*/\1/p' <<<"$report" | sort -u)
if ((rc != 0 && ${#unformatted[@]} == 0)); then
  echo "format.sh: clang-format failed:" >&2
  echo "$report" >&2
  exit 2
fi
if ((${#unformatted[@]})); then
  echo "format.sh: ${#unformatted[@]} of ${#files[@]} files are not formatted (run scripts/format.sh):" >&2
  printf '  %s\n' "${unformatted[@]}" >&2
  exit 1
fi
echo "format.sh: ${#files[@]} files formatted"
