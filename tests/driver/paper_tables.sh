#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# paper_tables.sh TAPER SOURCE_DIR -- suite 'paper': every value of the
# paper's Tables I-V, as the shipped scenes produce it, against its stored
# expected value (tests/driver/paper_tables.tsv), and the tables section of
# docs/paper.md against the same runs.
#
# Each row of paper_tables.tsv names a scene of share/scenes/paper/, a swept
# value, a column of the scene's table.tsv (theory, theory_fit, numerics), the
# expected value and its tolerance:
#   numerics:           stderr of the fit + the tolerance study (the largest
#                       change of the scene's numerics when rtol goes from the
#                       default 1e-10 to 1e-9);
#   theory, theory_fit: 1e-9 relative (no integrator involved).
# A value outside expected +- tolerance fails: the dynamics or the fit changed.
# Where docs/paper.md claims agreement with the paper's printed digits
# (paper_check = yes), ours rounded to the printed decimals must print them;
# and wherever the TSV stores the paper's digits, the scene's paper column
# (table.tsv) must print the same.  No exceptions: a row whose printed digit
# the paper gets wrong has paper_check = no, and docs/paper.md says why.
# Values are read from the driver's own output (DIR/table.tsv), never from
# the scene file.  After an intended change regenerate the TSV and the docs:
#   python3 tests/driver/paper_tables.py expected build/drivers/taper/taper > tests/driver/paper_tables.tsv
#   python3 tests/driver/paper_tables.py docs build/drivers/taper/taper
# PAPER_TABLES_TSV=FILE checks against FILE instead (e.g. a perturbed copy).
set -u
absolute() { case $1 in /*) echo "$1" ;; *) echo "$(pwd)/$1" ;; esac; }
TAPER=$(absolute "$1")
SRC=$(absolute "$2")
EXPECTED=$(absolute "${PAPER_TABLES_TSV:-$SRC/tests/driver/paper_tables.tsv}")
WORK=$(mktemp -d "${TMPDIR:-/tmp}/taper_paper.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

for scene in $(grep -v '^#' "$EXPECTED" | tail -n +2 | cut -f1 | uniq); do
    TAPER_GNUPLOT=none "$TAPER" "$SRC/share/scenes/paper/$scene.nml" -o "$scene" \
        > "$scene.out" 2> "$scene.err" ||
        { fail "$scene: exit status $? ($(cat "$scene.err"))"; continue; }
    sed -n '/^Table/,$p' "$scene.out"
done

# expected rows joined with the table.tsv of their scene, checked in awk
awk -F '\t' -v work="$WORK" '
    function load(scene,   f, line, n, h, i, c) {
        if (scene in loaded) return
        loaded[scene] = 1; f = work "/" scene "/table.tsv"; n = 0
        while ((getline line < f) > 0) {
            if (line ~ /^#/) continue
            split(line, c, "\t")
            if (n++ == 0) { for (i in c) h[i] = c[i]; continue }
            for (i in c) val[scene, sprintf("%g", c[1]), h[i]] = c[i]
        }
        close(f)
    }
    /^#/ || $1 == "scene" { next }
    {
        scene = $1; p = $2; col = $3; exp_ = $4 + 0; tol = $5 + 0; paper = $8; check = $9
        load(scene)
        if (!((scene, p, col) in val)) { printf "FAIL: %s %s %s: no value\n", scene, p, col; bad++; next }
        v = val[scene, p, col] + 0; d = v - exp_; if (d < 0) d = -d
        status = (d <= tol) ? "ok" : "FAIL"
        why = ""
        if (paper != "-") {
            dec = paper; sub(/^[^.]*\.?/, "", dec); nd = length(dec)
            pcol = (col == "numerics") ? "paper_numerics" : "paper_theory"
            scene_paper = sprintf("%." nd "f", val[scene, p, pcol] + 0)
            if (scene_paper != paper) { status = "FAIL"; why = why "; the scene says the paper prints " scene_paper }
        }
        if (check == "yes") {
            printed = sprintf("%." nd "f", v)
            why = why sprintf("; prints %s, paper %s", printed, paper)
            if (printed != paper) status = "FAIL"
        }
        printf "%s: %s %s %s = %.12g (expected %.12g +- %.2g, |diff| %.2g)%s\n", status, scene, p, col,
               v, exp_, tol, d, why
        if (status == "FAIL") bad++
    }
    END { exit bad > 0 }' "$EXPECTED" > checks || failures=$((failures + $(grep -c '^FAIL' checks)))
cat checks

# docs/paper.md: its tables section is what these runs generate.
(cd "$SRC" && python3 tests/driver/paper_tables.py docs "$TAPER" --runs "$WORK" --check) ||
    fail "docs/paper.md: tables section"
[ "$failures" -eq 0 ] || { echo "$failures failures"; exit 1; }
echo "paper tables: every value within its tolerance, every claimed paper digit reproduced, docs/paper.md current"
