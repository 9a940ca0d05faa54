#!/usr/bin/env bash
# `make gradescope`: Gradescope's autograder bundle (docs/grading.md,
# "Gradescope") at target/gradescope/autograder.zip, or at $1/autograder.zip.
#
# At the zip's root: Gradescope's `setup.sh` and `run_autograder`
# (scripts/gradescope/), the `raytracer` binary that grades ($RAYTRACER,
# default target/release/raytracer, which `make gradescope` builds), the
# suite (`suite/`: $SUITE, a suite folder, or the built-in suite), the
# course's reference options when $REFERENCE_OPTIONS names their file
# (`reference.json`), or the course's own tracer when $REFERENCE_TRACER is
# its command (`--reference-tracer`, like `./tracer {scene} {out}`) and
# $REFERENCE_TRACER_DIR the folder it runs from (`reference/`, its command
# in `reference.txt`), and `cache/`, our reference image of every scene,
# rendered here by that same binary, so no submission renders one (the
# cache is keyed by the binary's hash: a bundle's cache fits its binary).
set -euo pipefail
cd "$(dirname "$0")/.."

out=${1:-target/gradescope}
mkdir -p "$out"
out=$(cd "$out" && pwd)
bin=${RAYTRACER:-target/release/raytracer}
stage="$out/autograder"
rm -rf "$stage" "$out/autograder.zip"
mkdir -p "$stage"

cp "$bin" "$stage/raytracer"
here=$stage
cp scripts/gradescope/setup.sh scripts/gradescope/run_autograder "$stage/"
chmod 0755 "$stage/setup.sh" "$stage/run_autograder" "$stage/raytracer"
if [ -n "${SUITE:-}" ]; then
    cp -R "$SUITE" "$stage/suite"
else
    "$stage/raytracer" grade --export-suite "$stage/suite"
fi
options=()
if [ -n "${REFERENCE_OPTIONS:-}" ]; then
    cp "$REFERENCE_OPTIONS" "$stage/reference.json"
    options=(--reference-options "$stage/reference.json")
fi
if [ -n "${REFERENCE_TRACER:-}" ]; then
    if [ -z "${REFERENCE_TRACER_DIR:-}" ]; then
        echo "REFERENCE_TRACER needs REFERENCE_TRACER_DIR, the folder it runs from" >&2
        exit 2
    fi
    cp -R "$REFERENCE_TRACER_DIR" "$stage/reference"
    printf '%s\n' "$REFERENCE_TRACER" >"$stage/reference.txt"
    options+=(--reference-tracer "$REFERENCE_TRACER")
    # Its images are cached by its command and files, from this folder:
    # run_autograder grades from the same.
    here=$stage/reference
fi

# The references: `grade` renders every scene's before it runs a tracer,
# and `true` writes no image (exit 1, every scene `bad_image`, is expected).
warm=$(mktemp -d)
trap 'rm -rf "$warm"' EXIT
status=0
(cd "$here" && "$stage/raytracer" grade --tracer 'true {scene} {out}' "$stage/suite" "${options[@]}" \
    --cache "$stage/cache" --unprotected -o "$warm/report" >"$warm/log" 2>&1) || status=$?
if [ "$status" -gt 1 ]; then
    cat "$warm/log" >&2
    echo "cannot render the references (exit $status)" >&2
    exit 1
fi

(cd "$stage" && zip -qr ../autograder.zip .)
echo "wrote $out/autograder.zip"
