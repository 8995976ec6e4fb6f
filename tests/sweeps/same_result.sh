# SPDX-License-Identifier: GPL-3.0-or-later
# same_result.sh -- sourced by the sweep tests that compare two computations
# of one sweep (serial, MPI, resumed, merged from parts) file by file:
#
#   same_result A B    0 when A and B hold the same result
#
# Byte for byte, but for the one measurement of the machine a sweep writes:
# each run's CPU time, runs.tsv's column cpu_time[s] and the last line of
# each run's scene.hash (`cpu_time[s] SECONDS`).  runs.tsv is compared
# without that column and without its footer (whose CRC-32 covers it), after
# the footer is checked against the file; scene.hash without that line.
# (Scratch files .same_result.a and .b in the working directory.)

# FILE's lines without the column named cpu_time[s] and without its footer.
without_cpu_column() {
    awk -F '\t' -v OFS='\t' '
        NR == 1 { for (i = 1; i <= NF; i++) if ($i == "cpu_time[s]") c = i }
        /^# end: rows / { next }
        /^#/ || !c { print; next }
        { out = ""; n = 0
          for (i = 1; i <= NF; i++) if (i != c) { out = n++ ? out OFS $i : $i }
          print out }' "$1"
}

# 0 when FILE's footer matches it (rows, bytes, CRC-32: docs/scene.md).
footer_holds() {
    python3 - "$1" <<'PY'
import re, sys, zlib
data = open(sys.argv[1], "rb").read()
cut = data.rindex(b"\n", 0, len(data) - 1) + 1
m = re.fullmatch(rb"# end: rows (\d+), bytes (\d+), crc32 ([0-9a-f]{8})\n", data[cut:])
rows = sum(1 for i, l in enumerate(data[:cut].split(b"\n")[:-1])
           if i > 0 and l and not l.startswith(b"#"))
sys.exit(0 if m and int(m[2]) == cut and int(m[3], 16) == zlib.crc32(data[:cut])
         and int(m[1]) == rows else 1)
PY
}

same_result() {
    case $1 in
    */runs.tsv)
        footer_holds "$1" && footer_holds "$2" || return 1
        without_cpu_column "$1" > .same_result.a && without_cpu_column "$2" > .same_result.b ||
            return 1
        cmp -s .same_result.a .same_result.b ;;
    */scene.hash)
        grep -v '^cpu_time\[s\] ' "$1" > .same_result.a
        grep -v '^cpu_time\[s\] ' "$2" > .same_result.b
        cmp -s .same_result.a .same_result.b ;;
    *) cmp -s "$1" "$2" ;;
    esac
}
