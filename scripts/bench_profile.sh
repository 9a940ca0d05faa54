#!/usr/bin/env bash
# `make bench-profile BASE=path/to/an/older/raytracer`: where a render of
# the 100,000-sphere grid spends its work, and how two builds compare on
# the sphere grids, written into docs/performance.md.
#
# The split counts instructions (valgrind's cachegrind, which also
# simulates a 32 KiB first-level and a 1 MiB last-level data cache), not
# time: on the shared 2-core machine the counts do not move with the other
# tenants' load. Each function's count goes to one of: closest hits
# (camera and reflection rays, traversal and primitive tests; the tests
# apart where the build has them in a function of their own), shadow rays
# (traversal and tests), shading (the tracer's path loop), building the
# hierarchy, and the rest (reading and checking the scene, writing the
# image). Both binaries are profiled, and must write the same image.
#
# Then the A/B: each grid (10,000, 100,000 and 1,000,000 spheres, at
# 1000²) rendered with one thread by the two binaries in turn, RUNS rounds
# (default 7), the median of each one's CPU time (user + system, which
# other tenants' load inflates less than wall time) and their ratio; the
# images must be the same bytes.
#
# The tables replace the part of docs/performance.md between its
# `profile:begin` and `profile:end` markers.
set -euo pipefail

cd "$(dirname "$0")/.."
. scripts/lib/splice.sh
. scripts/lib/commit.sh
. scripts/lib/median.sh
BASE=${BASE:?set BASE to the binary to compare with, e.g. a copy of an older target/release/raytracer}
# How the tables name BASE (say, the commit it was built from).
BASE_LABEL=${BASE_LABEL:-$(basename "$BASE")}
RUNS=${RUNS:-7}
NEW=target/release/raytracer
OUT=target/bench-profile
DOC=docs/performance.md
STARTED=$(date -u '+%F %H:%M UTC')
command -v valgrind >/dev/null || { echo "installing valgrind" >&2; apt-get install -y -qq valgrind >/dev/null; }

cargo build --release --locked --quiet
cargo build --release --locked --quiet --example grid_scene
mkdir -p "$OUT"
cp scenes/wood_tex.ppm "$OUT/"
for n in 10000 100000 1000000; do
  [ -f "$OUT/grid$n.txt" ] || target/release/examples/grid_scene "$n" "$OUT/grid$n.txt" 1000
done

# Cachegrind both builds at once (one core each).
profile() {
  valgrind --tool=cachegrind --cache-sim=yes --D1=32768,8,64 --LL=1048576,16,64 \
    --cachegrind-out-file="$OUT/$1.cg" "$2" render "$OUT/grid100000.txt" "$OUT/$1.cg.ppm" \
    --threads 1 --quiet 2>"$OUT/$1.cg.log"
}
profile base "$BASE" &
profile new "$NEW" &
wait
cmp -s "$OUT/base.cg.ppm" "$OUT/new.cg.ppm" || { echo "bench-profile: the two builds' images differ" >&2; exit 1; }

# Per group: instructions, first-level and last-level read misses.
split() {
  cg_annotate --show=Ir,D1mr,DLmr --threshold=0 "$OUT/$1.cg" 2>/dev/null | awk '
    {gsub(/\([^)]*\)/, ""); gsub(",", "")}
    / PROGRAM TOTALS/ {ti = $1; td = $2; tl = $3; next}
    $1 ~ /^[0-9]+$/ && NF == 4 {
      fn = $4
      g = "rest"
      if (fn ~ /closest::\{\{closure\}\}/) g = "leaf"
      else if (fn ~ /closest_in|::closest|closest_fan|first_hits/) g = "closest"
      else if (fn ~ /occluded/) g = "shadow"
      else if (fn ~ /render::trace::/) g = "shading"
      else if (fn ~ /render::bvh::/) g = "build"
      ir[g] += $1; d1[g] += $2; ll[g] += $3
    }
    END {
      split("closest leaf shadow shading build rest", gs, " ")
      for (k = 1; k <= 6; k++) printf "%s %.0f %.0f %.0f\n", gs[k], ir[gs[k]], d1[gs[k]], ll[gs[k]]
      printf "total %.0f %.0f %.0f\n", ti, td, tl
    }'
}
split base >"$OUT/base.split"
split new >"$OUT/new.split"

# The A/B, alternating.
echo "scene,build,cpu_s" >"$OUT/ab.csv"
for s in grid10000 grid100000 grid1000000; do
  for _ in $(seq "$RUNS"); do
    for b in base new; do
      bin=$NEW
      [ $b = base ] && bin=$BASE
      /usr/bin/time -f "%U %S" -o "$OUT/time" "$bin" render "$OUT/$s.txt" "$OUT/$s.$b.ppm" --threads 1 --quiet
      echo "$s,$b,$(awk '{print $1 + $2}' "$OUT/time")" >>"$OUT/ab.csv"
    done
  done
  cmp -s "$OUT/$s.base.ppm" "$OUT/$s.new.ppm" || { echo "bench-profile: $s differs between the builds" >&2; exit 1; }
done
median() {
  awk -F, -v s="$1" -v b="$2" '$1 == s && $2 == b {print $3}' "$OUT/ab.csv" | median_of_lines
}

GEN=$OUT/section.md
{
  echo "<!-- profile:begin: written by \`make bench-profile\` (scripts/bench_profile.sh); edit the script, not this section -->"
  echo
  echo "### Where the work goes, and one build against another"
  echo
  echo "\`make bench-profile\`, started $STARTED, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end;"
  echo "base: $BASE_LABEL;"
  echo "new: \`target/release/raytracer\` of commit $(measured_commit ' with uncommitted changes')."
  echo "Instructions and simulated cache misses (cachegrind: 32 KiB first level, 1 MiB last level)"
  echo "of one render of the 100,000-sphere grid at 1000², one thread; both builds wrote the same image."
  echo
  echo "| share | base instructions | new instructions | new/base | base L1 misses | new L1 misses | base LL misses | new LL misses |"
  echo "|---|---|---|---|---|---|---|---|"
  paste -d' ' "$OUT/base.split" "$OUT/new.split" | awk '
    BEGIN {
      name["closest"] = "closest hits (camera and reflection rays: traversal, and the tests inlined in it)"
      name["leaf"] = "closest hits: primitive tests, where a function of their own"
      name["shadow"] = "shadow rays (traversal and tests)"
      name["shading"] = "shading (the path loop)"
      name["build"] = "building the hierarchy"
      name["rest"] = "reading the scene, writing the image, the rest"
      name["total"] = "whole process"
    }
    {
      if ($1 == "total") { bt = $2; nt = $6 }
      row[NR] = $0
    }
    END {
      for (k = 1; k <= NR; k++) {
        split(row[k], f, " ")
        printf "| %s | %.2f G (%.1f %%) | %.2f G (%.1f %%) | %.3f | %.1f M | %.1f M | %.1f M | %.1f M |\n",
          name[f[1]], f[2] / 1e9, 100 * f[2] / bt, f[6] / 1e9, 100 * f[6] / nt, f[6] / f[2],
          f[3] / 1e6, f[7] / 1e6, f[4] / 1e6, f[8] / 1e6
      }
    }'
  echo
  echo "CPU seconds (user + system) of whole renders at 1000², one thread, the two builds alternating,"
  echo "medians of $RUNS each; the images were the same bytes."
  echo
  echo "| scene | base CPU s | new CPU s | new/base |"
  echo "|---|---|---|---|"
  for s in grid10000 grid100000 grid1000000; do
    awk -v s="$s" -v b="$(median "$s" base)" -v n="$(median "$s" new)" 'BEGIN {
      printf "| %s | %.2f | %.2f | %.3f |\n", s, b, n, n / b }'
  done
  echo
  echo "<!-- profile:end -->"
} >"$GEN"

splice_section "$DOC" profile "$GEN"
cat "$GEN"
