#!/usr/bin/env bash
# `make bench-scaling`: our render time against object count, for the
# plot in docs/performance.md. Sphere grids (examples/grid_scene.rs) of
# 10 to 1,000,000 spheres at 1000², one thread, REPS runs each (default 3),
# the counts interleaved; brute force too where it finishes in seconds.
# Writes the medians to docs/scaling.csv:
#   spheres,accel,render_s,rays,mrays_per_s,peak_mb,parse_check_s,commit
# (commit: the code measured, marked when src/ differs from it), the render
# times as `series,x,y` to docs/scaling_plot.csv, and plots them with
# examples/plot.rs to docs/scaling.png, its title naming the commit.
set -euo pipefail

cd "$(dirname "$0")/.."
. scripts/lib/commit.sh
. scripts/lib/median.sh
REPS=${REPS:-3}
OUT=target/bench
BIN=target/release/raytracer
COUNTS=(10 100 1000 10000 100000 1000000)

commit=$(measured_commit +changes)

cargo build --release --locked --quiet
cargo build --release --locked --quiet --example grid_scene --example plot
mkdir -p "$OUT"
cp scenes/wood_tex.ppm "$OUT/"
for n in "${COUNTS[@]}"; do
  target/release/examples/grid_scene "$n" "$OUT/grid$n.txt" 1000
done

RUNS=()
for n in "${COUNTS[@]}"; do RUNS+=("$n auto"); done
for n in 10 100; do RUNS+=("$n brute"); done

samples="$OUT/scaling-samples.csv"
echo "spheres,accel,render_s,rays,peak_kb,parse_check_s" >"$samples"
for rep in $(seq "$REPS"); do
  for run in "${RUNS[@]}"; do
    read -r n accel <<<"$run"
    echo "rep $rep/$REPS: $n spheres, $accel" >&2
    json="$OUT/scaling.stats.json"
    /usr/bin/time -f "%M" -o "$OUT/scaling.time" \
      "$BIN" render "$OUT/grid$n.txt" "$OUT/scaling.png" --threads 1 --quiet --accel "$accel" --stats-json "$json"
    render=$(sed -n 's/^ *"render": \([0-9.e-]*\),*$/\1/p' "$json")
    front=$(awk -F'[:,]' '/"(parse|check)"/ {s += $2} END {print s}' "$json")
    rays=$(awk -F'[:,]' '/"(primary|shadow|reflection)_rays"/ {s += $2} END {print s}' "$json")
    echo "$n,$accel,$render,$rays,$(cat "$OUT/scaling.time"),$front" >>"$samples"
  done
done

median() {
  awk -F, -v key="$1" -v col="$2" '($1 "," $2) == key {print $col}' "$samples" |
    median_of_lines
}

echo "spheres,accel,render_s,rays,mrays_per_s,peak_mb,parse_check_s,commit" >docs/scaling.csv
echo "series,spheres,seconds" >docs/scaling_plot.csv
for run in "${RUNS[@]}"; do
  read -r n accel <<<"$run"
  r=$(median "$n,$accel" 3)
  rays=$(median "$n,$accel" 4)
  kb=$(median "$n,$accel" 5)
  front=$(median "$n,$accel" 6)
  awk -v n="$n" -v a="$accel" -v r="$r" -v rays="$rays" -v kb="$kb" -v f="$front" -v c="$commit" \
    'BEGIN {printf "%s,%s,%.4f,%d,%.2f,%.1f,%.4f,%s\n", n, a, r, rays, rays / r / 1e6, kb / 1024, f, c}' >>docs/scaling.csv
  series=$([ "$accel" = auto ] && echo "hierarchy (--accel auto)" || echo "brute force")
  echo "$series,$n,$r" >>docs/scaling_plot.csv
done
column -s, -t docs/scaling.csv
target/release/examples/plot docs/scaling_plot.csv docs/scaling.png \
  --title "Render time against sphere count (1000², one thread), commit $commit" \
  --x-label "spheres" --y-label "render time, s (median of $REPS)" --log-x --log-y --lines
