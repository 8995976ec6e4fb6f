#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# faults.sh TAPER -- a failing run does not end a sweep:
# a grid with points the library refuses (forward_linear needs N < 1 + 1/s)
# and runs that stop at max_steps (partial).  Every other run completes;
# sweep.tsv has their rows and a comment line per failed run, runs.tsv a
# status per run, fits.tsv nan for the failed point; exit status 5.
set -u
TAPER=$1
case $TAPER in /*) ;; *) TAPER=$(pwd)/$TAPER ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

cat > fault.nml <<'NML'
&chain profile = 'forward_linear'
       n_granules = 50, 200
       s = 0.001, 0.01 /
&solver max_steps = 0, 40 /
&fit model = 'power', x = 'k', y = 'v', k_min = 5, k_max = 40 /
NML
"$TAPER" fault.nml -o out > out.txt 2> err.txt
status=$?
[ $status -eq 5 ] || fail "exit status $status, wanted 5 (some runs failed): $(cat err.txt)"
grep -q "fault.nml: 5 of 8 runs failed" err.txt || fail "no summary: $(cat err.txt)"
# The refusal names the scene's line, the variable and the run.
grep -q "^fault.nml:2: &chain n_granules: .*(run n_granules=200,s=0.01,max_steps=0)$" err.txt ||
    fail "refusal not named: $(cat err.txt)"
grep -q "^fault.nml: run n_granules=50,s=0.001,max_steps=40: max_steps reached" err.txt ||
    fail "partial run not named: $(cat err.txt)"
# The complete runs' rows; one comment line per failed run.
[ "$(grep -vc '^#' out/sweep.tsv)" -eq $((1 + 50 + 50 + 200)) ] ||
    fail "sweep.tsv rows: $(grep -vc '^#' out/sweep.tsv)"
[ "$(grep -c '^# partial run ' out/sweep.tsv)" -eq 3 ] || fail "sweep.tsv: partial runs not marked"
grep -q '^# refused run n_granules=200,s=0.01,max_steps=40: no rows (fault.nml:2: &chain n_granules: ' out/sweep.tsv ||
    fail "sweep.tsv: refused run not marked"
# runs.tsv: one status per run.
awk -F '\t' 'NR > 1 && !/^#/ { print $1 " " $5 }' out/runs.tsv > status
cat > status.want <<'TXT'
n_granules=50,s=0.001,max_steps=0 complete
n_granules=50,s=0.001,max_steps=40 partial
n_granules=50,s=0.01,max_steps=0 complete
n_granules=50,s=0.01,max_steps=40 partial
n_granules=200,s=0.001,max_steps=0 complete
n_granules=200,s=0.001,max_steps=40 partial
n_granules=200,s=0.01,max_steps=0 refused
n_granules=200,s=0.01,max_steps=40 refused
TXT
diff status.want status >&2 || fail "runs.tsv statuses"
[ -f 'out/n_granules=50,s=0.001,max_steps=40/granules.partial.tsv' ] || fail "no granules.partial.tsv"
[ ! -e 'out/n_granules=200,s=0.01,max_steps=0' ] || fail "a refused run left a directory"
# Fits for every run, nan where there is no data.
[ "$(grep -c '^0.01	numerics	nan' out/fits.tsv)" -eq 3 ] || fail "fits.tsv: $(cat out/fits.tsv)"
[ "$(grep -c '^0.001	numerics	0\.' out/fits.tsv)" -eq 2 ] || fail "fits.tsv: complete runs not fitted"

# A sweep without failures exits 0 and has no comment line but the first.
printf "&chain profile = 'forward_linear', n_granules = 50, s = 0.001, 0.01 /\n" > good.nml
"$TAPER" good.nml -o good > /dev/null 2>&1 || fail "good sweep: exit status $?"
[ "$(grep -c '^#' good/sweep.tsv)" -eq 2 ] || fail "good sweep: comment lines in sweep.tsv"
tail -1 good/sweep.tsv | grep -q '^# end: rows 100, bytes [0-9]*, crc32 [0-9a-f]\{8\}$' ||
    fail "good sweep: sweep.tsv ends without its footer: $(tail -1 good/sweep.tsv)"

# An UNTRUSTED run (energy error beyond &output max_energy_error) keeps its
# rows; the sweep exits 4, runs.tsv says untrusted.
printf "&chain profile = 'forward_exponential', q = 0.01, n_granules = 1500 /\n&solver atol = 1d-13, 0.1 /\n" > ut.nml
"$TAPER" ut.nml -o ut > /dev/null 2> ut.err
status=$?
[ $status -eq 4 ] || fail "untrusted run: exit status $status, wanted 4: $(cat ut.err)"
[ "$(grep -vc '^#' ut/sweep.tsv)" -eq 3001 ] || fail "untrusted run: its rows are not in sweep.tsv"
awk -F '\t' 'NR > 1 && !/^#/ { print $1 " " $3 }' ut/runs.tsv | tr '\n' ' ' | grep -q '^atol=1e-13 complete atol=0.1 untrusted $' ||
    fail "untrusted run: runs.tsv $(cat ut/runs.tsv)"

# One variable (issue 36, item 9): a forward linear sweep over s from the
# monodisperse limit s = 0, with one s beyond N < 1 + 1/s: that run fails
# alone (refused, the reason in runs.tsv), the others complete, status 5,
# and runs.tsv carries each run's statistics under granules.tsv's names,
# the pulse's speed among them (the header's), and the CPU time each run
# took (the refused one's too: it ran until the library refused it).
printf "&chain profile = 'forward_linear', n_granules = 20, s = 0, 0.01, 0.1, 0.02 /\n" > one.nml
"$TAPER" one.nml -o one > one.out 2> one.err
status=$?
[ $status -eq 5 ] || fail "one variable: exit status $status, wanted 5: $(cat one.err)"
grep -q "^one.nml:1: &chain n_granules: forward_linear with s = 0.10000000000000001 needs n_granules < 1 + 1/s = 11 .*(run s=0.1)$" one.err ||
    fail "one variable: the refused point not named: $(cat one.err)"
awk -F '\t' 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i }
     NR > 1 && !/^#/ { printf "%s %s %s %s %.6f %s %s\n", $col["run"], $col["status"],
                       $col["steps"] ~ /^[1-9][0-9]*$/ ? "steps" : $col["steps"],
                       $col["t_final"] ~ /^[0-9.e+-]+$/ ? "t_final" : $col["t_final"],
                       $col["energy_transmitted"] + $col["energy_reflected"] + $col["energy_in_chain"],
                       ($col["pulse_speed"] + 0 > 0 ? "speed" : $col["pulse_speed"]),
                       ($col["cpu_time[s]"] ~ /^[0-9]+\.[0-9][0-9][0-9][0-9][0-9][0-9]$/ &&
                        $col["cpu_time[s]"] + 0 > 0 ? "cpu" : $col["cpu_time[s]"]) }' \
    one/runs.tsv > one.status
cat > one.want <<'TXT'
s=0 complete steps t_final 0.500000 speed cpu
s=0.01 complete steps t_final 0.500000 speed cpu
s=0.1 refused nan nan nan nan cpu
s=0.02 complete steps t_final 0.500000 speed cpu
TXT
diff one.want one.status >&2 || fail "one variable: runs.tsv $(cat one/runs.tsv)"
head -1 one/runs.tsv | grep -q "^run	s	status	steps	rhs_evals	.*	t_final	energy_error	.*	pulse_speed	cpu_time\[s\]	message$" ||
    fail "runs.tsv: column names: $(head -1 one/runs.tsv)"
awk -F '\t' '$1 == "s=0.1" { print $NF }' one/runs.tsv | grep -q "needs n_granules < 1 + 1/s = 11" ||
    fail "runs.tsv: the refused run's reason"
speed=$(awk -F '\t' 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "pulse_speed") c = i }
                      $1 == "s=0.02" { print $c }' one/runs.tsv)
grep -qx "# pulse_speed = $speed" one/s=0.02/granules.tsv ||
    fail "runs.tsv: pulse_speed $speed is not the header's: $(grep pulse_speed one/s=0.02/granules.tsv)"
# s = 0 is the monodisperse chain: its rows are the monodisperse scene's.
printf "&chain n_granules = 20 /\n" > mono.nml
"$TAPER" mono.nml -o mono > /dev/null 2>&1 || fail "monodisperse: exit status $?"
grep -v '^#' mono/granules.tsv > mono.rows
grep -v '^#' one/s=0/granules.tsv > s0.rows
cmp -s mono.rows s0.rows || fail "s = 0 is not the monodisperse chain"
# A point out of the variable's own range is a typo of the scene: refused.
printf "&chain profile = 'forward_linear', n_granules = 20, s = 0.01, -0.1 /\n" > neg.nml
"$TAPER" neg.nml -o neg > /dev/null 2> neg.err
[ $? -eq 2 ] && grep -q "^neg.nml:1: &chain s: s = -0.1 is out of range" neg.err ||
    fail "s = -0.1 in a sweep: $(cat neg.err)"
# A tapered profile without its s or q would be the monodisperse chain
# under another name: refused; s = 0 given is meant.
printf "&chain profile = 'backward_exponential' /\n" > noq.nml
"$TAPER" noq.nml -o noq > /dev/null 2> noq.err
[ $? -eq 2 ] && grep -q "^noq.nml:1: &chain q: profile = 'backward_exponential' needs its tapering q" noq.err ||
    fail "no q: $(cat noq.err)"

[ $failures -eq 0 ] && echo "failing runs: marked, the others complete, exit status 5"
[ $failures -eq 0 ]
