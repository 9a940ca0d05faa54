# Sourced by the scripts that write a section of a doc (bench, bench
# diagnostics, LSP latency, bench-profile, cold-times): each writes the
# section, markers included, to a file, and `splice_section` puts it in
# place of the doc's old section.

# splice_section DOC NAME SECTION: replace the lines of DOC from its
# `<!-- NAME:begin` marker through its `<!-- NAME:end -->` marker with the
# file SECTION. The new text goes to a file beside DOC first and is then
# renamed over it, so DOC is never half written. Exits 2, leaving DOC as it
# is, when DOC has no `NAME:begin` marker.
splice_section() {
  local doc=$1 name=$2 section=$3
  grep -q "^<!-- $name:begin" "$doc" ||
    { echo "${0##*/}: $doc has no $name:begin marker" >&2; exit 2; }
  awk -v section="$section" -v begin="^<!-- $name:begin" -v end="^<!-- $name:end -->" '
    $0 ~ begin {while ((getline line < section) > 0) print line; skip = 1; next}
    $0 ~ end {skip = 0; next}
    !skip {print}' "$doc" >"$doc.new"
  mv "$doc.new" "$doc"
}
