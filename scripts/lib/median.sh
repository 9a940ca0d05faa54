# Sourced by the measuring scripts (bench, bench diagnostics, bench-profile,
# scaling): one median for all of them.

# median_of_lines: the median of the numbers on standard input, one a line
# (the mean of the two middle ones for an even count; nothing for none).
median_of_lines() {
  sort -g | awk '{v[NR] = $1} END {if (NR == 0) print ""; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2}'
}
