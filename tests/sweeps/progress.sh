#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# progress.sh TAPER -- what a sweep shows: on a terminal
# (script(1) gives it one), a progress line with runs done / total, the
# rate, the time left and the threads; none when stderr is a file; the
# library's warnings name the run they come from.
set -u
TAPER=$1
case $TAPER in /*) ;; *) TAPER=$(pwd)/$TAPER ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# A steep forward chain with a loose atol: the library warns (energy drift).
cat > warn.nml <<'NML'
&chain profile = 'forward_exponential', q = 0.01, n_granules = 1500, 1600 /
&solver atol = 0.1 /
&output threads = 2 /
NML
"$TAPER" warn.nml -o out > out.txt 2> err.txt
status=$?
# 4: the energy error makes the runs UNTRUSTED, which they say too.
[ $status -eq 0 ] || [ $status -eq 4 ] || fail "exit status $status: $(cat err.txt)"
grep -q '^warn.nml: run n_granules=1500: warning: energy error' err.txt ||
    fail "warnings do not name their run: $(cat err.txt)"
grep -q '^warn.nml: run n_granules=1600: warning: energy error' err.txt || fail "second run's warning"
! grep -q 'taper: runs' err.txt || fail "a progress line in a file"

if command -v script > /dev/null 2>&1; then
    rm -rf out
    script -qc "'$TAPER' warn.nml -o out > /dev/null" /dev/null > tty.txt 2>&1
    tr '\r' '\n' < tty.txt > lines.txt
    grep -aq 'taper: runs 2/2  [0-9.e+]* runs/s  [0-9]* s left  \[1 rank x 2 threads\]' lines.txt ||
        fail "no progress line on a terminal: $(cat lines.txt)"
    grep -aq 'warn.nml: run n_granules=1600: warning' lines.txt || fail "warnings on a terminal"
else
    echo "note: script(1) not found: the terminal's progress line is not checked"
fi

[ $failures -eq 0 ] && echo "progress on a terminal; warnings name their run"
[ $failures -eq 0 ]
