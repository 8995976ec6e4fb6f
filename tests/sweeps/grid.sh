#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# grid.sh TAPER -- sweeps over any variable: a grid of
# 2 x 3 values over two variables, zipped lists, an integer sweep; one
# directory per run named by its values, sweep.tsv with one column per swept
# variable, and each run's numbers those of the same point run alone.
set -u
TAPER=$1
case $TAPER in /*) ;; *) TAPER=$(pwd)/$TAPER ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

cat > grid.nml <<'NML'
&chain profile = 'backward_exponential', n_granules = 40
       q = 0.05, 0.1
       exponent = 2.0, 2.5, 3.0 /
&output threads = 2 /
NML
"$TAPER" grid.nml -o out > grid.out 2> grid.err
status=$?
[ $status -eq 0 ] || fail "grid: exit status $status: $(cat grid.err)"
# One directory per run, named by its values, the later variable fastest.
ls out > dirs
cat > dirs.want <<'TXT'
q=0.05,exponent=2
q=0.05,exponent=2.5
q=0.05,exponent=3
q=0.1,exponent=2
q=0.1,exponent=2.5
q=0.1,exponent=3
runs.tsv
sweep.tsv
TXT
diff dirs.want dirs > /dev/null || fail "grid: directories $(tr '\n' ' ' < dirs)"
grep '^! wrote' grid.out | head -6 | sed 's|.*out/||; s|/granules.tsv||' > order
head -6 dirs.want | diff - order > /dev/null || fail "grid: runs not printed in sweep order: $(tr '\n' ' ' < order)"
# sweep.tsv: q and exponent columns, then granules.tsv's; 6 x 40 rows.
sed -n 1p out/sweep.tsv | cut -f 1-4 | grep -q "^q	exponent	k	R$" ||
    fail "grid: sweep.tsv header $(sed -n 1p out/sweep.tsv)"
rows=$(grep -vc '^#' out/sweep.tsv)
[ "$rows" -eq 241 ] || fail "grid: sweep.tsv has $rows lines, wanted 1 + 6 x 40"
pairs=$(grep -v '^#' out/sweep.tsv | sed 1d | cut -f 1,2 | uniq | tr '\t\n' ': ')
[ "$pairs" = "0.05:2 0.05:2.5 0.05:3 0.1:2 0.1:2.5 0.1:3 " ] ||
    fail "grid: sweep.tsv values $pairs"
# Each run's rows are those of the point run alone.
"$TAPER" grid.nml --set chain.q=0.1 --set chain.exponent=2.5 -o alone > /dev/null 2>&1 ||
    fail "grid: the point alone does not run"
grep -v '^#' alone/granules.tsv > a
grep -v '^#' 'out/q=0.1,exponent=2.5/granules.tsv' > b
cmp -s a b || fail "grid: run q=0.1,exponent=2.5 differs from the point run alone"
# The run's echo is the scene at its point.
grep -q '^#   exponent = 2.5$' 'out/q=0.1,exponent=2.5/granules.tsv' ||
    fail "grid: granules.tsv does not echo exponent = 2.5"

# Zipped lists: the i-th values together.
cat > zip.nml <<'NML'
&chain profile = 'backward_linear', n_granules = 30
       s = 0.01, 0.02, 0.03
       exponent = 2.5, 3.0, 3.5 /
&solver rtol = 1d-8, 1d-9, 1d-10 /
&sweep mode = 'zip' /
NML
"$TAPER" zip.nml -o zout > /dev/null 2> zip.err || fail "zip: $(cat zip.err)"
ls -d zout/s=* | tr '\n' ' ' > zdirs
[ "$(cat zdirs)" = "zout/s=0.01,exponent=2.5,rtol=1e-08 zout/s=0.02,exponent=3,rtol=1e-09 zout/s=0.03,exponent=3.5,rtol=1e-10 " ] ||
    fail "zip: directories $(cat zdirs)"
sed -n 1p zout/sweep.tsv | cut -f 1-4 | grep -q "^s	exponent	rtol	k$" || fail "zip: sweep.tsv header"
grep -q '^#   rtol = 1e-09$' 'zout/s=0.02,exponent=3,rtol=1e-09/granules.tsv' || fail "zip: rtol not at its point"

# An integer sweep; one variable keeps the form NAME=VALUE.
cat > ints.nml <<'NML'
&chain n_granules = 20, 30 /
&solver numerics = .false. /
NML
"$TAPER" ints.nml -o iout > /dev/null 2> ints.err || fail "integers: $(cat ints.err)"
[ -f iout/n_granules=20/granules.tsv ] && [ -f iout/n_granules=30/granules.tsv ] ||
    fail "integers: $(ls iout)"
sed -n 2p iout/sweep.tsv | grep -q 'sweep over n_granules: the rows of every n_granules=VALUE/granules.tsv' ||
    fail "integers: sweep.tsv comment line $(sed -n 2p iout/sweep.tsv)"
[ "$(grep -vc '^#' iout/sweep.tsv)" -eq 51 ] || fail "integers: sweep.tsv rows"

# &output every = 5 thins granules.tsv and sweep.tsv, not the fits: the runs
# keep every granule for them in report.tsv.
printf "&chain profile = 'backward_exponential', n_granules = 300, q = 0.02, 0.05 /\n&fit model = 'exponential', y = 'v', k_min = 10 /\n" > ev.nml
"$TAPER" ev.nml -o ev1 > /dev/null 2>&1 || fail "every: the sweep"
"$TAPER" ev.nml -o ev5 --set output.every=5 > /dev/null 2>&1 || fail "every = 5: the sweep"
cmp -s ev1/fits.tsv ev5/fits.tsv || fail "every = 5 changes fits.tsv"
[ "$(grep -vc '^#' ev5/sweep.tsv)" -eq $((1 + 2 * 61)) ] || fail "every = 5: sweep.tsv rows"
[ -f ev5/q=0.02/report.tsv ] && [ ! -f ev1/q=0.02/report.tsv ] || fail "every: report.tsv"

# Zipped lists of different lengths: a scene error naming the later list.
printf "&chain q = 0.1, 0.2\n exponent = 2, 3, 4 /\n&sweep mode = 'zip' /\n" > bad.nml
"$TAPER" bad.nml -o bout > /dev/null 2> bad.err
status=$?
[ $status -eq 2 ] || fail "zip lengths: exit status $status, wanted 2"
grep -q "bad.nml:2: &chain exponent: .*same length" bad.err || fail "zip lengths: $(cat bad.err)"

[ $failures -eq 0 ] && echo "grids, zipped lists and integer sweeps: all checks pass"
[ $failures -eq 0 ]
