#!/usr/bin/env bash
# `make bench-scaling`: our render time against object count, for the
# plot in docs/performance.md. Sphere grids (examples/grid_scene.rs) of
# 10 to 1,000,000 spheres at 1000², one thread, REPS runs each (default 3),
# the counts interleaved; brute force too where it finishes in seconds.
# Writes the medians to docs/scaling.csv:
#   spheres,accel,render_s,rays,mrays_per_s,peak_mb,parse_check_s,load1,commit
# (load1: the machine's 1-minute load average as each render started, the
# median over the repetitions, as the machine is shared; commit: the code
# measured, marked when src/ differs from it), the render
# times as `series,x,y` to docs/scaling_plot.csv, and plots them with
# examples/plot.rs to docs/scaling.png, its title naming the commit and the
# range of the load averages.
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
echo "spheres,accel,render_s,rays,peak_kb,parse_check_s,load1" >"$samples"
for rep in $(seq "$REPS"); do
  for run in "${RUNS[@]}"; do
    read -r n accel <<<"$run"
    echo "rep $rep/$REPS: $n spheres, $accel" >&2
    json="$OUT/scaling.stats.json"
    load=$(cut -d' ' -f1 /proc/loadavg)
    /usr/bin/time -f "%M" -o "$OUT/scaling.time" \
      "$BIN" render "$OUT/grid$n.txt" "$OUT/scaling.png" --threads 1 --quiet --accel "$accel" --stats-json "$json"
    render=$(sed -n 's/^ *"render": \([0-9.e-]*\),*$/\1/p' "$json")
    front=$(awk -F'[:,]' '/"(parse|check)"/ {s += $2} END {print s}' "$json")
    rays=$(awk -F'[:,]' '/"(primary|shadow|reflection)_rays"/ {s += $2} END {print s}' "$json")
    echo "$n,$accel,$render,$rays,$(cat "$OUT/scaling.time"),$front,$load" >>"$samples"
  done
done

median() {
  awk -F, -v key="$1" -v col="$2" '($1 "," $2) == key {print $col}' "$samples" |
    median_of_lines
}

echo "spheres,accel,render_s,rays,mrays_per_s,peak_mb,parse_check_s,load1,commit" >docs/scaling.csv
echo "series,spheres,seconds" >docs/scaling_plot.csv
for run in "${RUNS[@]}"; do
  read -r n accel <<<"$run"
  r=$(median "$n,$accel" 3)
  rays=$(median "$n,$accel" 4)
  kb=$(median "$n,$accel" 5)
  front=$(median "$n,$accel" 6)
  load=$(median "$n,$accel" 7)
  awk -v n="$n" -v a="$accel" -v r="$r" -v rays="$rays" -v kb="$kb" -v f="$front" -v l="$load" -v c="$commit" \
    'BEGIN {printf "%s,%s,%.4f,%d,%.2f,%.1f,%.4f,%.2f,%s\n", n, a, r, rays, rays / r / 1e6, kb / 1024, f, l, c}' >>docs/scaling.csv
  series=$([ "$accel" = auto ] && echo "hierarchy (--accel auto)" || echo "brute force")
  echo "$series,$n,$r" >>docs/scaling_plot.csv
done
column -s, -t docs/scaling.csv
# The least and the greatest load average a render started at.
loads=$(awk -F, 'NR > 1 {print $7}' "$samples" | sort -g | sed -n '1p;$p' | paste -sd '-')
target/release/examples/plot docs/scaling_plot.csv docs/scaling.png \
  --title "Render time against sphere count (1000², one thread), commit $commit, load $loads" \
  --x-label "spheres" --y-label "render time, s (median of $REPS)" --log-x --log-y --lines
