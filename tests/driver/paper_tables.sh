#!/bin/sh
# paper_tables.sh TAPER SOURCE_DIR -- suite 'paper': the scenes of Tables I-V
# (share/scenes/paper/table*.nml, the full scenes: together a few seconds).
#
# Theory column: equal to the paper's printed digits (within half a unit of
# the last printed digit), except the rows docs/paper.md shows to be wrong
# or on a rounding boundary (THEORY_EXCEPT below, each with its reason).
#
# Numerics column: |ours - paper's| <= tol, with
#   tol = 3 * stderr  +  window  +  half a unit of the paper's last digit,
# where stderr is the fit's standard error and `window` is the change of our
# value when the fit window is shortened by a fifth at either end (measured
# here, by re-running the scene).  The stderr is the noise of the fit, the
# window term its systematic dependence on a choice the paper does not state.
# Rows beyond that are listed in NUMERICS_EXCEPT (docs/paper.md, "Tables"):
# they are asserted to stay beyond it, so that a change is noticed.
set -u
absolute() { case $1 in /*) echo "$1" ;; *) echo "$(pwd)/$1" ;; esac; }
TAPER=$(absolute "$1")
SRC=$(absolute "$2")
WORK=$(mktemp -d "${TMPDIR:-/tmp}/taper_paper.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# table param: the paper's theory digit is wrong or on a rounding boundary.
THEORY_EXCEPT="table1:0.6 table3:0.02 table4:0.05"
# table param: the paper's numerics differ from ours beyond tol.
NUMERICS_EXCEPT="table1:0.3 table1:0.4 table1:0.5 table1:0.6 table1:0.8 table1:0.9 table2:0.06 table2:0.07 table2:0.08 table2:0.09 table3:0.01 table3:0.02 table3:0.03 table3:0.04 table3:0.05 table3:0.06 table3:0.07 table3:0.08 table3:0.09 table4:0.01 table4:0.02 table4:0.03 table4:0.04 table4:0.05 table4:0.06 table5:0.01 table5:0.03 table5:0.04 table5:0.05 table5:0.06"
# Every row, listed or not, must still agree with the paper's numerics to 5 %
# relative (the spread of the paper's own numerics around its theory), except
# Table IV q = 0.05, whose printed numerics is the theory value (the row's
# two columns look swapped: docs/paper.md).
LOOSE_EXCEPT="table4:0.05"

in_list() { case " $2 " in *" $1 "*) return 0 ;; esac; return 1; }

# value SCENE GROUP.KEY: the scene's resolved value, read by the driver
# itself (no second namelist reader here).
value() { "$TAPER" "$1" --get "$2"; }

for t in 1 2 3 4 5; do
    scene=$SRC/share/scenes/paper/table$t.nml
    "$TAPER" "$scene" -o "table$t" > "table$t.out" 2> "table$t.err" ||
        { fail "table$t: exit status $? ($(cat "table$t.err"))"; continue; }
    # The window variant: the fit window shortened by a fifth at both ends.
    lo=$(value "$scene" fit.k_min) && hi=$(value "$scene" fit.k_max) &&
        digits=$(value "$scene" table.digits) ||
        { fail "table$t: the driver cannot read the scene's fit window"; continue; }
    cut=$(( (hi - lo) / 5 ))
    "$TAPER" "$scene" --set "fit.k_min=$((lo + cut))" --set "fit.k_max=$((hi - cut))" \
        -o "variant$t" > /dev/null 2>&1 ||
        { fail "table$t: the window variant does not run"; continue; }
    sed -n '/^Table/,$p' "table$t.out"
    # param theory numerics stderr paper_th paper_num variant_numerics
    paste "table$t/table.tsv" "variant$t/table.tsv" | grep -v '^#' | tail -n +2 |
        awk -F '\t' -v OFS=' ' '{ print $1, $2, $3, $4, $5, $6, $11 }' > rows
    while read -r param theory num err pth pnum vnum; do
        p=$(printf '%g' "$param")
        verdict=$(awk -v th="$theory" -v pth="$pth" -v num="$num" -v err="$err" -v pnum="$pnum" \
            -v vnum="$vnum" -v d="$digits" 'BEGIN {
                unit = 10 ^ -d
                dth = th - pth; if (dth < 0) dth = -dth
                w = num - vnum; if (w < 0) w = -w
                tol = 3 * err + w + unit / 2
                dn = num - pnum; if (dn < 0) dn = -dn
                rel = dn / (pnum < 0 ? -pnum : pnum)
                printf "%s %s %.3g %.3g %s\n", (dth <= unit / 2 * (1 + 1e-9)) ? "th_ok" : "th_bad",
                       (dn <= tol) ? "num_ok" : "num_bad", dn, tol, (rel <= 0.05) ? "near" : "far" }')
        set -- $verdict
        echo "  table$t $p: theory $1; numerics $2 (|ours - paper| = $3, tol = $4)"
        if in_list "table$t:$p" "$THEORY_EXCEPT"; then
            [ "$1" = th_bad ] || fail "table$t $p: listed as a wrong printed theory value, but it agrees"
        else
            [ "$1" = th_ok ] || fail "table$t $p: theory $theory, paper prints $pth"
        fi
        if ! in_list "table$t:$p" "$LOOSE_EXCEPT"; then
            [ "$5" = near ] || fail "table$t $p: numerics $num more than 5 % from the paper's $pnum"
        fi
        if in_list "table$t:$p" "$NUMERICS_EXCEPT"; then
            [ "$2" = num_bad ] || fail "table$t $p: listed as differing numerics, but within tol"
        else
            [ "$2" = num_ok ] || fail "table$t $p: numerics $num, paper $pnum (|diff| $3 > tol $4)"
        fi
    done < rows
done
[ "$failures" -eq 0 ] || { echo "$failures failures"; exit 1; }
echo "paper tables: all rows as documented"
