#!/usr/bin/env bash
# `make bench`: our tracer against POV-Ray 3.7 and Embree 3, side by side
# in one run, written into docs/performance.md.
#
# Scenes (generated into target/bench/): scenes/sample.txt at 400² and
# 1000², and grids of 10,000, 100,000 and 1,000,000 reflective spheres at
# 1000² (examples/grid_scene.rs). In every repetition each scene is
# rendered, one after the other, by ours (`--threads 1`), POV-Ray (`+WT1`,
# from `raytracer convert --to pov`; not the million-sphere grid, whose
# parse alone would take most of the run), Embree (bench/embree/harness.cpp,
# built here with g++, from `raytracer convert --to scene`) with its
# single-ray API, Embree with its packet API for the camera rays (tiles of
# 4×2 pixels through rtcIntersect8) and ours with `--threads 2`. No anti-aliasing anywhere. Embree's ray counts and image
# are compared with ours (and with ours in single precision, rendered once
# per scene, as Embree's geometry is); a scene where they disagree fails
# the run. Each repetition also builds each grid's world alone
# (crates/render/examples/bvh_build.rs), so the grids' building and
# tracing are compared with Embree's apart.
#
# Then the front end on the million-sphere file: `raytracer check` against
# `wc -w`, alternating, and check's peak memory against the file size.
#
# The tables (medians), the machine and the targets replace the part of
# docs/performance.md between its `bench:begin` and `bench:end` markers.
# Raw samples go to target/bench/samples.csv, agreement.csv, phases.csv and
# frontend.csv.
#
# REPS=7 make bench   (default 5)
set -euo pipefail

cd "$(dirname "$0")/.."
. scripts/lib/splice.sh
. scripts/lib/commit.sh
. scripts/lib/median.sh
REPS=${REPS:-5}
OUT=target/bench
BIN=target/release/raytracer
DOC=docs/performance.md
STARTED=$(date -u '+%F %H:%M UTC')
LOAD_BEFORE=$(cut -d' ' -f1-3 /proc/loadavg)
SECONDS=0

need_apt() {
  # $1 a file or command that shows the package is there, $2 the package
  if ! command -v "$1" >/dev/null && [ ! -e "$1" ]; then
    echo "installing $2" >&2
    apt-get update -qq && apt-get install -y -qq "$2" >/dev/null
  fi
}
need_apt povray povray
need_apt /usr/bin/time time
need_apt g++ g++
need_apt /usr/include/embree3/rtcore.h libembree-dev

cargo build --release --locked --quiet
cargo build --release --locked --quiet --example grid_scene
cargo build --release --locked --quiet -p raytracer-render --example bvh_build
mkdir -p "$OUT"
g++ -O2 -std=c++17 -o "$OUT/embree_harness" bench/embree/harness.cpp -lembree3
cp scenes/wood_tex.ppm "$OUT/"
cp scenes/sample.txt "$OUT/sample400.txt"
sed 's/^camera 400/camera 1000/' scenes/sample.txt >"$OUT/sample1000.txt"
for n in 10000 100000 1000000; do
  target/release/examples/grid_scene "$n" "$OUT/grid$n.txt" 1000
done
SCENES=(sample400 sample1000 grid10000 grid100000 grid1000000)
POV_SCENES=" sample400 sample1000 grid10000 grid100000 "
for s in "${SCENES[@]}"; do
  case "$POV_SCENES" in *" $s "*) "$BIN" convert "$OUT/$s.txt" --to pov -o "$OUT/$s.pov" ;; esac
  "$BIN" convert "$OUT/$s.txt" --to scene -o "$OUT/$s.scene.txt"
done

# Each run appends: scene,tracer,threads,seconds,wall,peak_kb,rays,primary,front_s,cpu_s
echo "scene,tracer,threads,seconds,wall,peak_kb,rays,primary,front_s,cpu_s" >"$OUT/samples.csv"
# Embree against ours, per run: scene, Embree's mode (embree: single rays,
# embree8: packets), ours_rays, embree_rays, then the largest and mean
# difference from our image and from our f32 image
echo "scene,mode,ours_rays,embree_rays,max_diff,mean_diff,max_diff_f32,mean_diff_f32" >"$OUT/agreement.csv"
# Building apart from tracing, per run of a grid: scene, tracer (ours: the world built
# alone by crates/render/examples/bvh_build.rs; embree, embree8: as the
# harness times its rtcCommitScene and its rays), build and trace seconds
# (ours: trace left empty, its render's seconds minus the build's median)
echo "scene,tracer,build,trace" >"$OUT/phases.csv"

json_number() {
  # $1 key, $2 file: the number after "key":
  sed -n 's/^ *"'"$1"'": \([0-9.e-]*\),*$/\1/p' "$2"
}

ours() {
  # $1 scene, $2 threads; the image is PPM so Embree's can be compared with it
  local json="$OUT/$1.stats.json" timing="$OUT/$1.time" start end
  start=$EPOCHREALTIME
  /usr/bin/time -f "%e %M %U %S" -o "$timing" \
    "$BIN" render "$OUT/$1.txt" "$OUT/$1.ours.ppm" --threads "$2" --quiet --stats-json "$json"
  end=$EPOCHREALTIME
  local render rays primary front user system
  render=$(json_number render "$json")
  rays=$(awk -F'[:,]' '/"(primary|shadow|reflection)_rays"/ {s += $2} END {print s}' "$json")
  primary=$(json_number primary_rays "$json")
  front=$(awk -v p="$(json_number parse "$json")" -v c="$(json_number check "$json")" \
    -v l="$(json_number lower "$json")" 'BEGIN {printf "%.4f", p + c + l}')
  read -r _ peak user system <"$timing"
  wall=$(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.4f", b - a}')
  echo "$1,ours,$2,$render,$wall,$peak,$rays,$primary,$front,$(awk -v u="$user" -v s="$system" 'BEGIN {print u + s}')" >>"$OUT/samples.csv"
}

ours_build() {
  # $1 scene: building its world alone, on one thread, once
  local report
  report=$(target/release/examples/bvh_build "$OUT/$1.txt" 1)
  echo "$1,ours,$(sed -n 's/^seconds //p' <<<"$report")," >>"$OUT/phases.csv"
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
  echo "$1,povray,1,$trace,$wall,$peak,,,," >>"$OUT/samples.csv"
}

embree() {
  # $1 scene, $2 mode (embree: the single-ray API; embree8: camera rays in
  # packets of 8): Embree's build + trace seconds, compared with ours' last image
  local report="$OUT/$1.$2.txt" flags=()
  [ "$2" = embree8 ] && flags=(--packets)
  /usr/bin/time -f "%e %M %U %S" -o "$OUT/$1.$2.time" \
    "$OUT/embree_harness" "${flags[@]}" "$OUT/$1.scene.txt" "$OUT/$1.$2.ppm" "$OUT/$1.ours.ppm" "$OUT/$1.ours-f32.ppm" >"$report"
  local rays wall peak user system
  value() { sed -n "s/^$1 //p" "$report"; }
  rays=$(awk '/^(primary|shadow|reflection)_rays / {s += $2} END {print s}' "$report")
  read -r wall peak user system <"$OUT/$1.$2.time"
  echo "$1,$2,1,$(value seconds),$wall,$peak,$rays,$(value primary_rays),,$(awk -v u="$user" -v s="$system" 'BEGIN {print u + s}')" >>"$OUT/samples.csv"
  echo "$1,$2,$(value build),$(value trace)" >>"$OUT/phases.csv"
  local ours_rays diffs
  ours_rays=$(awk -F, -v s="$1" '$1 == s && $2 == "ours" {r = $7} END {print r}' "$OUT/samples.csv")
  diffs=$(awk '/^diff / {printf ",%s,%s", $3, $4}' "$report")
  echo "$1,$2,$ours_rays,$rays$diffs" >>"$OUT/agreement.csv"
}

for s in "${SCENES[@]}"; do
  echo "$s in single precision, for comparing with Embree" >&2
  "$BIN" render "$OUT/$s.txt" "$OUT/$s.ours-f32.ppm" --precision f32 --quiet
done
for rep in $(seq "$REPS"); do
  for s in "${SCENES[@]}"; do
    echo "rep $rep/$REPS: $s" >&2
    ours "$s" 1
    case "$s" in grid*) ours_build "$s" ;; esac
    case "$POV_SCENES" in *" $s "*) pov "$s" ;; esac
    embree "$s" embree
    embree "$s" embree8
    ours "$s" 2
  done
done

# The front end on the million-sphere file, alternating with `wc -w`.
BIG="$OUT/grid1000000.txt"
# Wall and CPU (user + system, every thread) time: check may use more
# threads than wc's one, which wall time alone would hide.
echo "tool,wall,peak_kb,cpu_s" >"$OUT/frontend.csv"
for rep in $(seq "$REPS"); do
  echo "rep $rep/$REPS: check and wc -w" >&2
  /usr/bin/time -f "%e %M %U %S" -o "$OUT/check.time" "$BIN" check "$BIG" >/dev/null 2>&1
  read -r wall peak user sys <"$OUT/check.time"
  echo "check,$wall,$peak,$(awk -v u="$user" -v s="$sys" 'BEGIN {print u + s}')" >>"$OUT/frontend.csv"
  /usr/bin/time -f "%e %M %U %S" -o "$OUT/wc.time" wc -w "$BIG" >/dev/null
  read -r wall peak user sys <"$OUT/wc.time"
  echo "wc,$wall,$peak,$(awk -v u="$user" -v s="$sys" 'BEGIN {print u + s}')" >>"$OUT/frontend.csv"
done

median() {
  # the median of column $3 of the rows of file $4 whose first columns are $1 and $2
  awk -F, -v a="$1" -v b="$2" -v col="$3" '$1 == a && ($2 == b || b == "") && $col != "" {print $col}' "$4" |
    median_of_lines
}
sample() {
  # median of column $3 for scene $1 and "tracer,threads" $2
  awk -F, -v key="$1,$2" -v col="$3" '($1 "," $2 "," $3) == key {print $col}' "$OUT/samples.csv" |
    median_of_lines
}

# The generated section of docs/performance.md.
GEN="$OUT/performance.generated.md"
failed=0
{
  echo "<!-- bench:begin: written by \`make bench\` (scripts/bench.sh); edit the script, not this section -->"
  echo
  echo "### The run"
  echo
  echo "\`make bench\`, REPS=$REPS, started $STARTED, took $((SECONDS / 60)) min $((SECONDS % 60)) s"
  echo "on $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'),"
  echo "$(nproc) logical CPUs ($(grep -c '^processor' /proc/cpuinfo) in /proc/cpuinfo), $(awk '/MemTotal/ {printf "%.1f GiB", $2 / 1048576}' /proc/meminfo) memory,"
  echo "load average $LOAD_BEFORE at the start and $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  echo "(the machine is shared: loads above $(nproc) mean other jobs took turns on our core)."
  echo "Binary: \`$BIN\` of commit $(measured_commit ' plus uncommitted changes'); $(rustc --version | cut -d' ' -f1-2);"
  echo "$(povray --version 2>&1 | sed -n 's/^POV-Ray \(3[.0-9]*[0-9]\).*/POV-Ray \1/p' | head -1); Embree $(dpkg-query -W -f '${Version}' libembree-dev 2>/dev/null | cut -d+ -f1) (Debian's \`libembree-dev\`, $(g++ --version | head -1 | sed 's/ (.*)//'), -O2)."
  echo
  echo "### Renders, one thread, medians of $REPS"
  echo
  echo "ours: \`seconds.render\` (building the hierarchy and tracing); POV-Ray: its Trace Time; Embree:"
  echo "\`rtcCommitScene\` plus tracing. Rays are primary + shadow + reflection. MB is the peak"
  echo "resident set (\`/usr/bin/time %M\` / 1024); wall is the whole process, reading the scene included;"
  echo "CPU is the whole process's user + system time, which other tenants' load does not inflate the"
  echo "way it inflates wall times. Embree 8: Embree with its camera rays in packets (tiles of 4×2"
  echo "pixels through \`rtcIntersect8\`), the rest of each path as before."
  echo
  echo "| scene | ours s | POV-Ray s | Embree s | Embree 8 s | ours/POV-Ray | ours/Embree | ours/Embree 8 | ours Mrays/s | ours ns/primary ray | ours MB | POV-Ray MB | Embree MB | ours wall s | ours CPU s | Embree wall s | Embree CPU s | ours 2 threads s |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
  for s in "${SCENES[@]}"; do
    awk -v s="$s" -v o="$(sample "$s" ours,1 4)" -v p="$(sample "$s" povray,1 4)" -v e="$(sample "$s" embree,1 4)" \
      -v e8="$(sample "$s" embree8,1 4)" \
      -v r="$(sample "$s" ours,1 7)" -v pr="$(sample "$s" ours,1 8)" -v om="$(sample "$s" ours,1 6)" \
      -v pm="$(sample "$s" povray,1 6)" -v em="$(sample "$s" embree,1 6)" -v w="$(sample "$s" ours,1 5)" \
      -v ew="$(sample "$s" embree,1 5)" -v t="$(sample "$s" ours,2 4)" -v oc="$(sample "$s" ours,1 10)" \
      -v ec="$(sample "$s" embree,1 10)" '
      function f(x, fmt) { return x == "" ? "—" : sprintf(fmt, x) }
      BEGIN {
        printf "| %s | %.3f | %s | %.3f | %.3f | %s | %.2f | %.2f | %.1f | %.0f | %.1f | %s | %.1f | %.3f | %.3f | %.3f | %.3f | %.3f |\n",
          s, o, f(p, "%.3f"), e, e8, p == "" ? "—" : sprintf("%.2f", o / p), o / e, o / e8, r / o / 1e6, o / pr * 1e9,
          om / 1024, pm == "" ? "—" : sprintf("%.1f", pm / 1024), em / 1024, w, oc, ew, ec, t
      }'
  done
  echo
  echo "POV-Ray does not render the million-sphere grid here: parsing its 1,000,000 \`sphere\` blocks"
  echo "alone would take longer than the rest of the run."
  echo
  echo "### Building and tracing apart, grids, one thread, medians of $REPS"
  echo
  echo "Ours: building the world alone (\`crates/render/examples/bvh_build.rs\`: the objects converted and"
  echo "the hierarchy built, in a process of its own, once per repetition), and tracing as \`seconds.render\`"
  echo "minus that build (medians of each). Embree: the harness's \`rtcCommitScene\` and its rays."
  echo
  echo "| scene | ours build s | ours trace s | Embree build s | Embree trace s | Embree 8 build s | Embree 8 trace s | ours build/Embree build | ours trace/Embree trace | ours trace/Embree 8 trace |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  for s in grid10000 grid100000 grid1000000; do
    awk -v s="$s" -v o="$(sample "$s" ours,1 4)" -v ob="$(median "$s" ours 3 "$OUT/phases.csv")" \
      -v eb="$(median "$s" embree 3 "$OUT/phases.csv")" -v et="$(median "$s" embree 4 "$OUT/phases.csv")" \
      -v e8b="$(median "$s" embree8 3 "$OUT/phases.csv")" -v e8t="$(median "$s" embree8 4 "$OUT/phases.csv")" 'BEGIN {
      printf "| %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f | %.2f | %.2f |\n",
        s, ob, o - ob, eb, et, e8b, e8t, ob / eb, (o - ob) / et, (o - ob) / e8t }'
  done
  echo
  echo "### Embree against ours: the same picture"
  echo
  echo "Embree's geometry is single precision, ours double by default, so a ray grazing an edge may"
  echo "go the other way, and in the sphere grids, where rays bounce up to 8 times between mirrors,"
  echo "such differences spread. Per scene and Embree mode (the last repetition): the rays each cast (primary + shadow"
  echo "+ reflection), and the largest and mean absolute difference of Embree's image from ours and"
  echo "from ours rendered with \`--precision f32\`, in 8-bit steps over every channel. The run fails"
  echo "when the ray counts differ by more than 1 % or the mean difference from our f32 image exceeds 0.5."
  echo
  echo "| scene | Embree | ours rays | Embree rays | difference | max diff | mean diff | max diff (f32) | mean diff (f32) | agree |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  for s in "${SCENES[@]}"; do
   for mode in embree embree8; do
    line=$(awk -F, -v s="$s" -v m="$mode" '$1 == s && $2 == m {l = $0} END {print l}' "$OUT/agreement.csv")
    IFS=, read -r _ _ our_rays emb_rays max_diff mean_diff max32 mean32 <<<"$line"
    verdict=$(awk -v a="$our_rays" -v b="$emb_rays" -v m="$mean32" 'BEGIN {
      d = (b - a) / a; if (d < 0) d = -d; print (d <= 0.01 && m <= 0.5) ? "yes" : "NO" }')
    [ "$verdict" = yes ] || failed=1
    awk -v s="$s" -v a="$our_rays" -v b="$emb_rays" -v x="$max_diff" -v m="$mean_diff" -v x32="$max32" \
      -v m32="$mean32" -v v="$verdict" -v mode="$([ "$mode" = embree8 ] && echo packets || echo single rays)" 'BEGIN {
      printf "| %s | %s | %d | %d | %+.3f %% | %d | %.4f | %d | %.4f | %s |\n", s, mode, a, b, (b - a) / a * 100, x, m, x32, m32, v }'
   done
  done
  echo
  echo "### The front end on the million-sphere scene"
  echo
  size=$(stat -c %s "$BIG")
  check_s=$(median check "" 2 "$OUT/frontend.csv")
  check_kb=$(median check "" 3 "$OUT/frontend.csv")
  wc_s=$(median wc "" 2 "$OUT/frontend.csv")
  check_cpu=$(median check "" 4 "$OUT/frontend.csv")
  wc_cpu=$(median wc "" 4 "$OUT/frontend.csv")
  front_s=$(sample grid1000000 ours,1 9)
  awk -v size="$size" -v c="$check_s" -v ck="$check_kb" -v w="$wc_s" -v f="$front_s" -v reps="$REPS" \
    -v cc="$check_cpu" -v wcc="$wc_cpu" 'BEGIN {
    printf "`examples/grid_scene 1000000` at 1000², %.1f MB; `raytracer check` and `wc -w` on it\n", size / 1e6
    printf "alternating, %d runs each (medians; `/usr/bin/time` has 10 ms steps, so two times\n", reps
    printf "one step apart are not told apart). Wall is the process'"'"'s elapsed time; CPU its user +\n"
    printf "system time summed over its threads (`wc -w` runs one): check with more than one thread\n"
    printf "can be faster in wall time while using more CPU. Then `render`'"'"'s parse + check + lower\n"
    printf "from its `--stats-json` seconds (median of the renders above).\n\n"
    print "| measure | value |"
    print "|---|---|"
    printf "| file size | %.1f MB |\n", size / 1e6
    printf "| `raytracer check` wall | %.2f s (%.0f MB/s) |\n", c, size / c / 1e6
    printf "| `raytracer check` CPU, all threads | %.2f s |\n", cc
    printf "| `wc -w` wall | %.2f s (%.0f MB/s) |\n", w, size / w / 1e6
    printf "| check / wc -w | %.2f |\n", c / w
    printf "| `raytracer check` CPU (user + system) | %.2f s |\n", cc
    printf "| `wc -w` CPU (user + system) | %.2f s |\n", wcc
    printf "| check / wc -w, CPU | %.2f |\n", cc / wcc
    printf "| check peak resident | %.1f MB (%.2f × the file) |\n", ck * 1024 / 1e6, ck * 1024 / size
    printf "| render: parse + check + lower | %.3f s |\n", f
  }'
  echo
  echo "### Scaling: whole process, one thread, 1000²"
  echo
  w100k=$(sample grid100000 ours,1 5)
  w1m=$(sample grid1000000 ours,1 5)
  echo "| 100,000 spheres s | 1,000,000 spheres s | ratio |"
  echo "|---|---|---|"
  awk -v a="$w100k" -v b="$w1m" 'BEGIN {printf "| %.3f | %.3f | %.2f |\n", a, b, b / a}'
  echo
  echo "### Against the targets of issue 18"
  echo
  echo "| target | measured | |"
  echo "|---|---|---|"
  for s in "${SCENES[@]}"; do
    awk -v s="$s" -v o="$(sample "$s" ours,1 4)" -v e="$(sample "$s" embree,1 4)" 'BEGIN {
      printf "| %s: ours/Embree ≤ 0.8 | %.2f | %s |\n", s, o / e, o / e <= 0.8 ? "met" : "not met" }'
  done
  awk -v o="$(sample sample1000 ours,1 4)" -v p="$(sample sample1000 ours,1 8)" -v c="$(sample sample1000 ours,1 10)" 'BEGIN {
    ns = o / p * 1e9
    printf "| sample1000: ≤ 40 ns per primary ray (`seconds.render` / primary rays) | %.0f ns (whole-process CPU time / primary rays: %.0f ns) | %s |\n",
      ns, c / p * 1e9, ns <= 40 ? "met" : "not met" }'
  awk -v c="$check_cpu" -v w="$wc_cpu" 'BEGIN {
    printf "| `check` of 1M spheres within 2 × the CPU time of `wc -w` | %.2f s against %.2f s | %s |\n", c, w, c <= 2 * w ? "met" : "not met" }'
  awk -v ck="$check_kb" -v size="$size" 'BEGIN {
    r = ck * 1024 / size; printf "| `check` peak ≤ 2 × file size | %.2f × | %s |\n", r, r <= 2 ? "met" : "not met" }'
  awk -v f="$front_s" 'BEGIN {printf "| `render` parse + check + lower ≤ 1 s | %.3f s | %s |\n", f, f <= 1 ? "met" : "not met" }'
  awk -v a="$w100k" -v b="$w1m" 'BEGIN {
    printf "| 1M spheres within 2 × the 100k time (whole process) | %.2f × | %s |\n", b / a, b / a <= 2 ? "met" : "not met" }'
  echo
  echo "### Against the targets of issue 46"
  echo
  echo "| target | measured | |"
  echo "|---|---|---|"
  for s in grid10000 grid100000 grid1000000; do
    awk -v s="$s" -v o="$(sample "$s" ours,1 4)" -v e="$(sample "$s" embree,1 4)" -v e8="$(sample "$s" embree8,1 4)" 'BEGIN {
      printf "| %s: ours ≤ 0.8 × Embree single-ray | %.2f | %s |\n", s, o / e, o / e <= 0.8 ? "met" : "not met"
      printf "| %s: ours ≤ 1.0 × Embree packets | %.2f | %s |\n", s, o / e8, o / e8 <= 1.0 ? "met" : "not met" }'
  done
  for s in sample400 sample1000; do
    awk -v s="$s" -v o="$(sample "$s" ours,1 4)" -v p="$(sample "$s" povray,1 4)" 'BEGIN {
      printf "| %s: ours ≤ 0.35 × POV-Ray | %.2f | %s |\n", s, o / p, o / p <= 0.35 ? "met" : "not met" }'
  done
  echo
  echo "What each grid's single-ray target leaves for building, given tracing as it is (the table"
  echo "\"Building and tracing apart\"): 0.8 × Embree's build and trace, less our tracing alone."
  echo
  echo "| scene | 0.8 × Embree s | ours trace s | left for the build s | ours build s |"
  echo "|---|---|---|---|---|"
  for s in grid10000 grid100000 grid1000000; do
    awk -v s="$s" -v o="$(sample "$s" ours,1 4)" -v e="$(sample "$s" embree,1 4)" \
      -v ob="$(median "$s" ours 3 "$OUT/phases.csv")" 'BEGIN {
      printf "| %s | %.3f | %.3f | %.3f | %.3f |\n", s, 0.8 * e, o - ob, 0.8 * e - (o - ob), ob }'
  done
  echo
  echo "<!-- bench:end -->"
} >"$GEN"

splice_section "$DOC" bench "$GEN"
cat "$GEN"
echo "samples: $OUT/samples.csv, $OUT/agreement.csv, $OUT/phases.csv, $OUT/frontend.csv; wrote $DOC" >&2

scripts/bench_lsp.sh
scripts/bench_diagnostics.sh
if [ "$failed" = 1 ]; then
  echo "bench: Embree and ours disagree on some scene (see the agreement table)" >&2
  exit 1
fi
