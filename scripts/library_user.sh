#!/usr/bin/env bash
# Part of `make test`: the library without its command line. Builds and
# runs tests/library-user, which depends on this crate with
# `default-features = false`, and fails when `cargo tree` shows any
# dependency that only the command line needs.
set -euo pipefail

cd "$(dirname "$0")/.."
CARGO=${CARGO:-cargo}
CLI_ONLY="clap indicatif plotters lsp-server lsp-types ignore ctrlc cpu-time"

MANIFEST=tests/library-user/Cargo.toml
CARGO_TARGET_DIR="$PWD/target" $CARGO run --release --locked --quiet --manifest-path "$MANIFEST" >/dev/null
tree=$($CARGO tree --locked --manifest-path "$MANIFEST" -e normal --prefix none)
found=""
for crate in $CLI_ONLY; do
  if grep -q "^$crate v" <<<"$tree"; then
    found="$found $crate"
  fi
done
if [ -n "$found" ]; then
  echo "error: the library without its command line still depends on:$found" >&2
  echo "help: make the dependency optional and enable it in the \`cli\` feature of Cargo.toml" >&2
  exit 1
fi
echo "library-user: builds and runs without$(printf ' %s' $CLI_ONLY | sed 's/ /, /2g')"
