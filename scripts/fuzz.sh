#!/usr/bin/env bash
# `make fuzz`: run each cargo-fuzz target for FUZZ_SECONDS with one
# libFuzzer job, growing fuzz/corpus/TARGET from fuzz/seeds/TARGET, and
# append one dated line per target to the run log at the end of
# docs/reliability.md: wall-clock and CPU seconds of the fuzzer process
# (measured by /usr/bin/time, the build excluded: on a shared machine the
# two differ), executions (from libFuzzer's -print_final_stats), peak
# memory, and crashes (the files the run left in fuzz/artifacts/TARGET:
# crash-, oom-, timeout- or leak-). A target that crashes or fails to run
# fails the command after its line is written.
#
# Usage: scripts/fuzz.sh TARGET...   (environment: FUZZ_SECONDS, FUZZ_FLAGS,
# CARGO; see the Makefile)
set -euo pipefail

cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-600}
cargo=${CARGO:-cargo}
log=docs/reliability.md
read -r -a flags <<<"${FUZZ_FLAGS:-}"
[ "$#" -gt 0 ] || { echo "usage: scripts/fuzz.sh TARGET..." >&2; exit 2; }
grep -q '^## Fuzz run log' "$log" || { echo "$log has no '## Fuzz run log' section" >&2; exit 2; }

# The value of libFuzzer's final `stat::NAME: VALUE` line in FILE.
stat() {
  sed -n "s/^stat::$1: *\([0-9][0-9]*\).*/\1/p" "$2" | tail -n 1
}

# Build every target first, so the times below are the fuzzers' alone.
(cd fuzz && for target in "$@"; do
  RUSTC_BOOTSTRAP=1 "$cargo" fuzz build -O "${flags[@]}" "$target" || exit 2
done)

status=0
for target in "$@"; do
  mkdir -p "fuzz/corpus/$target" "fuzz/artifacts/$target"
  output=$(mktemp)
  stamp=$(mktemp)
  times=$(mktemp)
  set +e
  (cd fuzz && RAYON_NUM_THREADS=1 RUSTC_BOOTSTRAP=1 /usr/bin/time -f '%e %U %S' -o "$times" \
    "$cargo" fuzz run -O "${flags[@]}" "$target" "corpus/$target" "seeds/$target" -- \
    -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -print_final_stats=1) \
    2>&1 | tee "$output"
  code=${PIPESTATUS[0]}
  set -e
  read -r wall user system <"$times"
  rm -f "$times"
  elapsed=${wall%.*}
  cpu=$(awk -v u="$user" -v s="$system" 'BEGIN { printf "%d", u + s }')
  executions=$(stat number_of_executed_units "$output")
  peak=$(stat peak_rss_mb "$output")
  crashes=$(find "fuzz/artifacts/$target" -type f -newer "$stamp" \
    \( -name 'crash-*' -o -name 'oom-*' -o -name 'timeout-*' -o -name 'leak-*' \) | wc -l)
  rm -f "$stamp"
  if [ -z "$executions" ]; then
    echo "fuzz: $target printed no final statistics (exit $code); nothing logged" >&2
    rm -f "$output"
    status=1
    continue
  fi
  rm -f "$output"
  sanitizer=ASan
  case " ${FUZZ_FLAGS:-} " in *" none "*) sanitizer=none ;; esac
  printf '| %s | `%s` | %s | %s | %s | %s | %s MiB | %s | %s |\n' \
    "$(date -u +%Y-%m-%dT%H:%MZ)" "$target" "$seconds" "$elapsed" "$cpu" "$executions" \
    "${peak:-?}" "$sanitizer" "$crashes" >>"$log"
  if [ "$code" -ne 0 ] || [ "$crashes" -ne 0 ]; then
    echo "fuzz: $target exited $code with $crashes crash file(s) in fuzz/artifacts/$target" >&2
    status=1
  fi
done
exit "$status"
