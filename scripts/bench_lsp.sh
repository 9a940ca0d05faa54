#!/usr/bin/env bash
# Part of `make bench`: the language server's re-check latency after a
# keystroke (examples/lsp_latency.rs; target ≤ 50 ms), for scenes of
# 64 KiB, 256 KiB and 1 MiB, KEYS edits each (default 61). Writes the table
# (p50, p95 and max wall time per edit, and the server's CPU time per edit)
# into docs/editors.md between its lsp-latency markers, naming the commit
# measured, and appends the raw summaries, dated, to
# target/bench/lsp_latency.csv.
#
# KEYS=N scripts/bench_lsp.sh
set -euo pipefail

cd "$(dirname "$0")/.."
. scripts/lib/splice.sh
. scripts/lib/commit.sh
OUT=target/bench
DOC=docs/editors.md
KEYS=${KEYS:-61}
SIZES=(65536 262144 1048576)
grep -q '^<!-- lsp-latency:begin' "$DOC" || { echo "bench_lsp: $DOC has no lsp-latency:begin marker" >&2; exit 2; }
commit=$(measured_commit ' plus uncommitted changes')
cargo build --release --locked --quiet
cargo build --release --locked --quiet --example lsp_latency
mkdir -p "$OUT"
[ -f "$OUT/lsp_latency.csv" ] || echo "date,bytes,keys,p50_ms,p95_ms,max_ms,cpu_mean_ms,diagnostics" >"$OUT/lsp_latency.csv"
load_before=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo n/a)
rows=""
for size in "${SIZES[@]}"; do
  result=$(target/release/examples/lsp_latency target/release/raytracer "$size" "$KEYS" 2>/dev/null)
  echo "$(date -u +%F),$result" >>"$OUT/lsp_latency.csv"
  IFS=, read -r bytes keys p50 p95 max cpu diagnostics <<<"$result"
  rows+="| $bytes | $keys | $p50 | $p95 | $max | $cpu | $diagnostics |"$'\n'
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo n/a)

table="$OUT/lsp_latency.md"
{
  echo "<!-- lsp-latency:begin: written by scripts/bench_lsp.sh (part of \`make bench\`); edit the script, not this section -->"
  echo
  echo "Of commit $commit, $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, load average"
  echo "$load_before at the start and $load_after at the end (the machine is shared). Wall"
  echo "milliseconds from \`didChange\` to the diagnostics published for it, over $KEYS edits per"
  echo "scene (p50 and p95 by nearest rank); server CPU is its user + system time per edit,"
  echo "in 10 ms ticks averaged over the edits. Target: 50 ms per keystroke."
  echo
  echo "| scene bytes | edits | p50 ms | p95 ms | max ms | server CPU ms per edit | diagnostics |"
  echo "|---:|---:|---:|---:|---:|---:|---:|"
  printf '%s' "$rows"
  echo
  echo "<!-- lsp-latency:end -->"
} >"$table"
splice_section "$DOC" lsp-latency "$table"
cat "$table"
