#!/usr/bin/env bash
# `make fuzz`: run each cargo-fuzz target for FUZZ_SECONDS with one
# libFuzzer job, growing fuzz/corpus/TARGET from fuzz/seeds/TARGET, and
# append one dated line per target to the run log at the end of
# docs/reliability.md: wall-clock and CPU seconds of the fuzzer process
# (read from /proc, the build excluded: on a shared machine the two
# differ), executions (from libFuzzer's -print_final_stats), peak
# memory, and crashes (the files the run left in fuzz/artifacts/TARGET:
# crash-, oom-, timeout- or leak-). A target that crashes or fails to run
# fails the command after its line is written.
#
# FUZZ_CPU_SECONDS, when set, bounds each run by the fuzzer's CPU time
# instead of FUZZ_SECONDS of wall clock (a budget of CPU-minutes that a busy
# machine cannot shrink).
#
# Usage: scripts/fuzz.sh TARGET...   (environment: FUZZ_SECONDS,
# FUZZ_CPU_SECONDS, FUZZ_FLAGS, CARGO; see the Makefile)
set -euo pipefail

cd "$(dirname "$0")/.."
. scripts/lib/commit.sh
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

cpu_budget=${FUZZ_CPU_SECONDS:-}
hertz=$(getconf CLK_TCK)
triple=$(rustc -vV | sed -n 's/^host: //p')
[ -z "$cpu_budget" ] || seconds=$((cpu_budget * 20))

# The code fuzzed, read when it is built: the commit, marked `+changes`
# when the sources differ from it.
commit=$(measured_commit +changes fuzz/fuzz_targets)

# Build every target first, so the times below are the fuzzers' alone.
(cd fuzz && for target in "$@"; do
  RUSTC_BOOTSTRAP=1 "$cargo" fuzz build -O "${flags[@]}" "$target" || exit 2
done)

status=0
for target in "$@"; do
  mkdir -p "fuzz/corpus/$target" "fuzz/artifacts/$target"
  output=$(mktemp)
  stamp=$(mktemp)
  start=$(date +%s)
  # The fuzzer runs in the background so its CPU time can be read from
  # /proc: with FUZZ_CPU_SECONDS it is interrupted (SIGINT, after which
  # libFuzzer prints its final statistics and exits 72) once it has used
  # that much CPU, whatever the machine's load.
  (cd fuzz && exec env RAYON_NUM_THREADS=1 "target/$triple/release/$target" \
    -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="artifacts/$target/" "corpus/$target" "seeds/$target") >"$output" 2>&1 &
  pid=$!
  ticks=0
  interrupted=false
  while kill -0 "$pid" 2>/dev/null; do
    ticks=$(awk '{ print $14 + $15 }' "/proc/$pid/stat" 2>/dev/null || echo "$ticks")
    if [ -n "$cpu_budget" ] && [ "$((ticks / hertz))" -ge "$cpu_budget" ] && ! $interrupted; then
      kill -INT "$pid" 2>/dev/null || true
      interrupted=true
    fi
    sleep 1
  done
  set +e
  wait "$pid"
  code=$?
  set -e
  if $interrupted && [ "$code" -eq 72 ]; then code=0; fi
  tail -n 20 "$output"
  elapsed=$(($(date +%s) - start))
  cpu=$((ticks / hertz))
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
  asked="$seconds"
  [ -z "$cpu_budget" ] || asked="$cpu_budget CPU"
  printf '| %s | `%s` | `%s` | %s | %s | %s | %s | %s MiB | %s | %s |\n' \
    "$(date -u +%Y-%m-%dT%H:%MZ)" "$target" "$commit" "$asked" "$elapsed" "$cpu" "$executions" \
    "${peak:-?}" "$sanitizer" "$crashes" >>"$log"
  if [ "$code" -ne 0 ] || [ "$crashes" -ne 0 ]; then
    echo "fuzz: $target exited $code with $crashes crash file(s) in fuzz/artifacts/$target" >&2
    status=1
  fi
done
exit "$status"
