#!/usr/bin/env bash
# Part of `make bench`: the language server's re-check latency after a
# keystroke in a 1 MiB scene (examples/lsp_latency.rs; target ≤ 50 ms).
# Prints the summary and appends it, dated, to target/bench/lsp_latency.csv.
#
# KEYS=N scripts/bench_lsp.sh   (default 31 edits)
set -euo pipefail

cd "$(dirname "$0")/.."
OUT=target/bench
KEYS=${KEYS:-31}
cargo build --release --locked --quiet
cargo build --release --locked --quiet --example lsp_latency
mkdir -p "$OUT"
[ -f "$OUT/lsp_latency.csv" ] || echo "date,bytes,keys,median_ms,p90_ms,max_ms,cpu_mean_ms,diagnostics" >"$OUT/lsp_latency.csv"
result=$(target/release/examples/lsp_latency target/release/raytracer $((1 << 20)) "$KEYS" 2>/dev/null)
echo "$(date -u +%F),$result" >>"$OUT/lsp_latency.csv"
IFS=, read -r bytes keys median p90 max cpu diagnostics <<<"$result"
printf '\nlsp: re-check after a keystroke, %s-byte scene, %s edits (full sync, no debounce)\n' "$bytes" "$keys"
printf 'wall: median %s ms, p90 %s ms, max %s ms (target ≤ 50 ms); server CPU: mean %s ms per edit\n' "$median" "$p90" "$max" "$cpu"
printf '%s diagnostics each time; load average %s\n' "$diagnostics" "$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo n/a)"
