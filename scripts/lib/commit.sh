# Sourced by the scripts that name the code they measured beside what
# they measured (bench, bench diagnostics, LSP latency, bench-profile,
# scaling, accuracy, fuzz).

# measured_commit MARK [PATH...]: HEAD's short hash, followed by MARK when
# the sources the binaries are built from (src/, crates/, the manifests)
# or any PATH given differ from HEAD; `?` outside a git checkout.
measured_commit() {
  local mark=$1 commit
  shift
  commit=$(git rev-parse --short HEAD 2>/dev/null) || { echo '?'; return; }
  git diff --quiet HEAD -- src crates Cargo.toml Cargo.lock "$@" || commit="$commit$mark"
  echo "$commit"
}
