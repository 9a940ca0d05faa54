#!/usr/bin/env bash
# Part of `make bench`: how reporting scales with the number of problems.
# `raytracer check` on scenes of 1,000, 10,000 and 100,000 spheres that
# each have one error (`dimension 0`), in the human format showing every
# diagnostic (`--max-errors 0`), the short and JSON formats, and the human
# format at its default cap; then 50 MB of random bytes and a scene on one
# line of 1 MB with an error at its end. Each time is the median of REPS
# runs (wall, `/usr/bin/time`, 10 ms steps). The slope is a least-squares
# fit of time against the number of diagnostics (µs per diagnostic); the
# exponent is the fit of log time against log count (1 is linear, 2
# quadratic). Targets (issue 29): 100,000 diagnostics in the human format
# under 2 s, 50 MB of random bytes under 5 s.
#
# Writes its table into docs/performance.md between the
# `diagnostics:begin` and `diagnostics:end` markers.
#
# REPS=5 scripts/bench_diagnostics.sh   (default 3)
set -euo pipefail

cd "$(dirname "$0")/.."
. scripts/lib/splice.sh
. scripts/lib/commit.sh
. scripts/lib/median.sh
REPS=${REPS:-3}
OUT=target/bench/diagnostics
BIN=target/release/raytracer
DOC=docs/performance.md
STARTED=$(date -u '+%F %H:%M UTC')
cargo build --release --locked --quiet
mkdir -p "$OUT"

COUNTS=(1000 10000 100000)
for n in "${COUNTS[@]}"; do
  awk -v n="$n" 'BEGIN {
    print "camera 4"
    for (i = 0; i < n; i++) printf "sphere\n  dimension 0\n  center %d 0 -5\n", i
  }' >"$OUT/errors$n.txt"
done
head -c 50000000 /dev/urandom >"$OUT/random.txt"
awk 'BEGIN {
  printf "camera 4 "
  for (i = 0; i < 30000; i++) printf "sphere dimension 1 center 0 0 -5 "
  printf "sphere dimension 0 center 0 0 -5\n"
}' >"$OUT/longline.txt"

median_time() {
  # the median wall time of REPS runs of `raytracer check "$@"`
  for _ in $(seq "$REPS"); do
    /usr/bin/time -f "%e" -o "$OUT/time" "$BIN" check "$@" >/dev/null 2>&1 || true
    cat "$OUT/time"
  done | median_of_lines
}

diagnostics() {
  "$BIN" check --format json "$1" 2>/dev/null | grep -c '"code"' || true
}

echo "format,count,diagnostics,seconds" >"$OUT/samples.csv"
FORMATS=("human-all:--max-errors 0" "short-all:--format short --max-errors 0" "json:--format json" "human-capped:")
for entry in "${FORMATS[@]}"; do
  name=${entry%%:*}
  read -r -a flags <<<"${entry#*:}"
  for n in "${COUNTS[@]}"; do
    echo "diagnostics: $name $n" >&2
    d=$(diagnostics "$OUT/errors$n.txt")
    echo "$name,$n,$d,$(median_time "${flags[@]}" "$OUT/errors$n.txt")" >>"$OUT/samples.csv"
  done
done
random_s=$(median_time "$OUT/random.txt")
random_d=$(diagnostics "$OUT/random.txt")
long_s=$(median_time --max-errors 0 "$OUT/longline.txt")
long_d=$(diagnostics "$OUT/longline.txt")

GEN="$OUT/generated.md"
{
  echo "<!-- diagnostics:begin: written by \`make bench\` (scripts/bench_diagnostics.sh); edit the script, not this section -->"
  echo
  echo "### Reporting against the number of problems"
  echo
  echo "\`raytracer check\` on scenes of spheres with one error each (\`dimension 0\`), medians of $REPS"
  echo "runs (wall seconds), started $STARTED on commit $(measured_commit ' plus uncommitted changes'),"
  echo "load average $(cut -d' ' -f1-3 /proc/loadavg) at the end. Slope: least-squares µs per"
  echo "diagnostic; exponent: the fit of log time against log count (1 is linear, 2 quadratic)."
  echo
  echo "| format | 1k s | 10k s | 100k s | diagnostics at 100k | slope µs/diagnostic | exponent |"
  echo "|---|---|---|---|---|---|---|"
  for entry in "${FORMATS[@]}"; do
    name=${entry%%:*}
    awk -F, -v f="$name" -v label="\`${entry#*:}\`" '$1 == f {n++; x[n] = $3; y[n] = $4}
      END {
        sx = sy = sxx = sxy = lx = ly = lxx = lxy = 0
        for (i = 1; i <= n; i++) {
          sx += x[i]; sy += y[i]; sxx += x[i] * x[i]; sxy += x[i] * y[i]
          a = log(x[i]); b = log(y[i] > 0.005 ? y[i] : 0.005)
          lx += a; ly += b; lxx += a * a; lxy += a * b
        }
        slope = (n * sxy - sx * sy) / (n * sxx - sx * sx)
        exponent = (n * lxy - lx * ly) / (n * lxx - lx * lx)
        if (label == "``") label = "default (`--max-errors 50`)"
        printf "| %s %s | %.2f | %.2f | %.2f | %d | %.1f | %.2f |\n", f, label, y[1], y[2], y[3], x[3], slope * 1e6, exponent
      }' "$OUT/samples.csv"
  done
  echo
  human100k=$(awk -F, '$1 == "human-all" && $2 == 100000 {print $4}' "$OUT/samples.csv")
  echo "| input | diagnostics | seconds | target | |"
  echo "|---|---|---|---|---|"
  awk -v s="$human100k" 'BEGIN {printf "| 100,000 spheres, human, every diagnostic shown | 100000 | %.2f | < 2 s | %s |\n", s, s < 2 ? "met" : "not met"}'
  awk -v s="$random_s" -v d="$random_d" 'BEGIN {printf "| 50 MB of random bytes | %d | %.2f | < 5 s | %s |\n", d, s, s < 5 ? "met" : "not met"}'
  awk -v s="$long_s" -v d="$long_d" -v size="$(stat -c %s "$OUT/longline.txt")" 'BEGIN {printf "| one line of %.1f MB, error at its end | %d | %.2f | — | |\n", size / 1e6, d, s}'
  echo
  echo "<!-- diagnostics:end -->"
} >"$GEN"

splice_section "$DOC" diagnostics "$GEN"
cat "$GEN"
