#!/usr/bin/env bash
# `make bench`: our tracer against POV-Ray 3.7, side by side in one run.
#
# Scenes (generated into bench/, which git ignores): scenes/sample.txt at
# 400² and 1000², and grids of 10,000 and 100,000 reflective spheres at
# 1000² (examples/grid_scene.rs). Each is exported with
# `raytracer convert --to pov` and rendered REPS times by each tracer,
# alternately (ours, POV-Ray, ours with 2 threads), one thread each, no
# anti-aliasing, no display. Prints a table of medians: our render time
# (`--stats-json` seconds.render) and POV-Ray's trace time (its "Trace
# Time"), their ratio, our rays per second, both peak resident memories,
# our whole-process time and our 2-thread render time. The raw samples go
# to bench/samples.csv, the medians to bench/results.csv.
#
# REPS=7 make bench   (default 5)
set -euo pipefail

cd "$(dirname "$0")/.."
REPS=${REPS:-5}
OUT=bench
BIN=target/release/raytracer

need_apt() {
  # $1 command, $2 Debian package
  if ! command -v "$1" >/dev/null; then
    echo "installing $2" >&2
    apt-get update -qq && apt-get install -y -qq "$2" >/dev/null
  fi
}
need_apt povray povray
[ -x /usr/bin/time ] || { apt-get update -qq && apt-get install -y -qq time >/dev/null; }

cargo build --release --locked --quiet
cargo build --release --locked --quiet --example grid_scene
mkdir -p "$OUT"
cp scenes/wood_tex.ppm "$OUT/"
cp scenes/sample.txt "$OUT/sample400.txt"
sed 's/^camera 400/camera 1000/' scenes/sample.txt >"$OUT/sample1000.txt"
for n in 10000 100000; do
  target/release/examples/grid_scene "$n" "$OUT/grid$n.txt" 1000
done
SCENES=(sample400 sample1000 grid10000 grid100000)
for s in "${SCENES[@]}"; do
  "$BIN" convert "$OUT/$s.txt" --to pov -o "$OUT/$s.pov"
done

# Each run appends: scene,tracer,threads,seconds,wall,peak_kb,rays
echo "scene,tracer,threads,seconds,wall,peak_kb,rays" >"$OUT/samples.csv"

ours() {
  # $1 scene, $2 threads
  local json="$OUT/$1.stats.json" timing="$OUT/$1.time" start end
  start=$EPOCHREALTIME
  /usr/bin/time -f "%e %M" -o "$timing" \
    "$BIN" render "$OUT/$1.txt" "$OUT/$1.ours.png" --threads "$2" --quiet --stats-json "$json"
  end=$EPOCHREALTIME
  local render rays
  render=$(sed -n 's/^ *"render": \([0-9.e-]*\),*$/\1/p' "$json")
  rays=$(awk -F'[:,]' '/"(primary|shadow|reflection)_rays"/ {s += $2} END {print s}' "$json")
  read -r _ peak <"$timing"
  wall=$(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.4f", b - a}')
  echo "$1,ours,$2,$render,$wall,$peak,$rays" >>"$OUT/samples.csv"
}

pov() {
  # $1 scene; POV-Ray resolves the texture against the working folder.
  local size log="$OUT/$1.pov.log"
  size=$(sed -n 's/^camera \([0-9]*\).*/\1/p' "$OUT/$1.txt")
  (cd "$OUT" && /usr/bin/time -f "%e %M" -o "$1.pov.time" \
    povray +I"$1.pov" +O"$1.pov.png" +W"$size" +H"$size" -A -D +WT1 File_Gamma=1 >"$1.pov.log" 2>&1)
  local trace
  trace=$(sed -n 's/.*Trace Time:.*(\([0-9.]*\) seconds).*/\1/p' "$log" | head -1)
  read -r wall peak <"$OUT/$1.pov.time"
  echo "$1,povray,1,$trace,$wall,$peak," >>"$OUT/samples.csv"
}

for rep in $(seq "$REPS"); do
  for s in "${SCENES[@]}"; do
    echo "rep $rep/$REPS: $s" >&2
    ours "$s" 1
    pov "$s"
    ours "$s" 2
  done
done

median() {
  # median of column $3 for scene $1, tracer and threads $2 ("ours,1")
  awk -F, -v key="$1,$2" -v col="$3" '($1 "," $2 "," $3) == key {print $col}' "$OUT/samples.csv" |
    sort -g | awk '{v[NR] = $1} END {if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2}'
}

echo "scene,ours_s,povray_s,ratio,mrays_per_s,ours_peak_mb,povray_peak_mb,ours_wall_s,ours_2threads_s" >"$OUT/results.csv"
printf '\n%s, %s samples each, alternating; one thread unless noted\n' "$(date -u +%F)" "$REPS"
printf '%-11s %9s %10s %7s %8s %9s %9s %9s %10s\n' \
  scene "ours s" "POV-Ray s" ratio "Mrays/s" "ours MB" "POV MB" "ours wall" "ours 2thr"
for s in "${SCENES[@]}"; do
  o=$(median "$s" "ours,1" 4)
  p=$(median "$s" "povray,1" 4)
  w=$(median "$s" "ours,1" 5)
  om=$(median "$s" "ours,1" 6)
  pm=$(median "$s" "povray,1" 6)
  rays=$(median "$s" "ours,1" 7)
  two=$(median "$s" "ours,2" 4)
  awk -v s="$s" -v o="$o" -v p="$p" -v w="$w" -v om="$om" -v pm="$pm" -v r="$rays" -v t="$two" 'BEGIN {
    printf "%-11s %9.3f %10.3f %7.3f %8.2f %9.1f %9.1f %9.3f %10.3f\n", s, o, p, o / p, r / o / 1e6, om / 1024, pm / 1024, w, t
    printf "%s,%.4f,%.4f,%.4f,%.3f,%.1f,%.1f,%.4f,%.4f\n", s, o, p, o / p, r / o / 1e6, om / 1024, pm / 1024, w, t >> "'"$OUT"'/results.csv"
  }'
done
echo
echo "ours s: seconds.render; POV-Ray s: its Trace Time; MB: peak resident set (/usr/bin/time %M);"
echo "ours wall: whole process; ours 2thr: seconds.render with --threads 2. Samples: $OUT/samples.csv"
scripts/bench_lsp.sh
