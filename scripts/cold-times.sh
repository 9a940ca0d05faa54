#!/usr/bin/env bash
# `make cold-times`: how long a newcomer waits, measured from bare clones of
# this repository's HEAD and written into docs/contributing.md between its
# `cold-times:begin` and `cold-times:end` markers.
#
# With the cargo registry warm (`cargo fetch` first, not timed), it times:
# - `make run` in a fresh clone (its own, empty target/);
# - `make test` in a second fresh clone (everything it builds, cold);
# - in that second clone, `make test` again after a change to one file of
#   the library (a statement added to the body of `geometry::unit`, a
#   function of the front end), and `make check` (the fast tier) after a
#   second such change: what a contributor waits for per change.
# Each clone is a plain `git clone` with nothing beside it, so the figures
# include nothing this checkout has built. Cargo's own timing reports for
# the two cold builds go to target/cold-times/, and the five longest
# compilation units of each are written with the times.
#
# Takes about as long as the three runs (15 to 20 minutes on 2 cores).
set -euo pipefail

cd "$(dirname "$0")/.."
. scripts/lib/splice.sh
ROOT=$PWD
DOC=docs/contributing.md
OUT=$ROOT/target/cold-times
COMMIT=$(git rev-parse --short HEAD)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
mkdir -p "$OUT"
grep -q '^<!-- cold-times:begin' "$DOC" || { echo "cold-times: $DOC has no cold-times:begin marker" >&2; exit 2; }
if ! git diff --quiet HEAD -- src crates tests Cargo.toml Cargo.lock Makefile; then
  echo "cold-times: commit first; the clones measure HEAD ($COMMIT), not the working tree" >&2
  exit 2
fi

cargo fetch --locked --quiet

# $1 label, then the command; prints whole seconds.
timed() {
  local label=$1 start end
  shift
  start=$(date +%s)
  "$@" >"$OUT/$label.log" 2>&1 || { echo "cold-times: $label failed, see $OUT/$label.log" >&2; exit 1; }
  end=$(date +%s)
  echo $((end - start))
}

# The five longest units of the newest cargo timing report under $1.
top_units() {
  local report
  report=$(ls -t "$1"/target/cargo-timings/cargo-timing-2*.html | head -1)
  python3 - "$report" <<'EOF'
import json, re, sys
text = open(sys.argv[1]).read()
units = json.loads(re.search(r"const UNIT_DATA = (\[.*?\]);\n", text, re.S).group(1))
units.sort(key=lambda u: -u["duration"])
for u in units[:5]:
    target = u.get("target", "").strip() or "lib"
    print(f"| {u['name']} {target} | {u['duration']:.0f} s |")
EOF
}

mmss() { printf '%d min %02d s' $(($1 / 60)) $(($1 % 60)); }

git clone --quiet "$ROOT" "$WORK/run"
git clone --quiet "$ROOT" "$WORK/test"
LOAD=$(cut -d' ' -f1 /proc/loadavg)

RUN=$(cd "$WORK/run" && timed make-run make run CARGO_FLAGS=--timings)
RUN_TOP=$(top_units "$WORK/run")
TEST=$(cd "$WORK/test" && timed make-test make test CARGO_FLAGS=--timings)
TEST_TOP=$(top_units "$WORK/test")
sed -i 's/^pub fn unit(v: \[f64; 3\]) -> Option<DVec3> {$/&\n    std::hint::black_box(());/' "$WORK/test/crates/scene/src/geometry.rs"
grep -q 'black_box' "$WORK/test/crates/scene/src/geometry.rs" || { echo "cold-times: crates/scene/src/geometry.rs has no \`pub fn unit\` to edit" >&2; exit 2; }
REBUILD=$(cd "$WORK/test" && timed make-test-touched make test)
# The fast tier after another such change, what a contributor runs per edit.
sed -i 's/^    std::hint::black_box(());$/&\n    std::hint::black_box(());/' "$WORK/test/crates/scene/src/geometry.rs"
CHECK=$(cd "$WORK/test" && timed make-check-touched make check)
cp -r "$WORK/run/target/cargo-timings" "$OUT/make-run-timings"
cp -r "$WORK/test/target/cargo-timings" "$OUT/make-test-timings"

gen=$(mktemp)
{
  echo "<!-- cold-times:begin: written by \`make cold-times\` (scripts/cold-times.sh); edit the script, not this section -->"
  echo "Measured by \`make cold-times\` from bare clones of commit \`$COMMIT\` on"
  echo "$(nproc) cores, $(date -u '+%F'), load average $LOAD at the start, the cargo"
  echo "registry already downloaded:"
  echo
  echo "| step | time |"
  echo "|---|---|"
  echo "| \`make run\` in a fresh clone | $(mmss "$RUN") |"
  echo "| \`make test\` in a fresh clone (release build, fmt, clippy, the whole suite) | $(mmss "$TEST") |"
  echo "| \`make test\` again after a change to one file of the library (a statement added to \`geometry::unit\`) | $(mmss "$REBUILD") |"
  echo "| \`make check\` (the fast tier) after another such change | $(mmss "$CHECK") |"
  echo
  echo "The longest compilation units (cargo's \`--timings\`) of the cold \`make run\`:"
  echo
  echo "| unit | time |"
  echo "|---|---|"
  echo "$RUN_TOP"
  echo
  echo "and of the cold \`make test\` (units build two at a time, so they overlap):"
  echo
  echo "| unit | time |"
  echo "|---|---|"
  echo "$TEST_TOP"
  echo "<!-- cold-times:end -->"
} >"$gen"
splice_section "$DOC" cold-times "$gen"
rm -f "$gen"
echo "cold-times: make run $(mmss "$RUN"), make test $(mmss "$TEST"), after one file $(mmss "$REBUILD"), make check after one file $(mmss "$CHECK")"
