#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# resume.sh TAPER -- an interrupted sweep resumes.
#  - A sweep killed halfway (SIGKILL: no handler runs) and run again with the
#    same command reuses the runs it completed, redoes the others, and ends
#    with results byte-identical to an uninterrupted sweep: every file of
#    the output directory, run directories and sweep.tsv alike.
#  - Another sweep in the same directory: the runs it shares are reused,
#    the run directories of the earlier sweep removed; a changed setting
#    (rtol) reuses nothing.
set -u
TAPER=$1
. "$(dirname "$0")/same_result.sh"
case $TAPER in /*) ;; *) TAPER=$(pwd)/$TAPER ;; esac
tmp=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

cat > sweep.nml <<'NML'
&chain profile = 'backward_linear', s = 1d-5
       n_granules = 5000, 5001, 5002, 5003, 5004, 5005, 5006, 5007 /
&output threads = 1, progress = .false. /
&fit model = 'power', y = 'v', k_min = 10 /
NML
mkdir ref run
(cd ref && "$TAPER" ../sweep.nml -o out > out.txt 2> err.txt) || fail "uninterrupted sweep: $(cat ref/err.txt)"

# Killed once two runs are complete.
(cd run && exec "$TAPER" ../sweep.nml -o out > out1.txt 2> err1.txt) &
pid=$!
i=0
while [ "$(ls run/out/*/scene.hash 2> /dev/null | wc -l)" -lt 2 ] && [ $i -lt 600 ]; do
    sleep 0.05
    i=$((i + 1))
done
kill -KILL $pid 2> /dev/null
wait $pid 2> /dev/null
done_before=$(ls run/out/*/scene.hash 2> /dev/null | wc -l)
[ "$done_before" -lt 8 ] || echo "note: the sweep ended before it was killed" >&2
[ ! -f run/out/sweep.tsv ] || [ "$done_before" -eq 8 ] || fail "a killed sweep left a sweep.tsv"

(cd run && "$TAPER" ../sweep.nml -o out > out2.txt 2> err2.txt) || fail "resumed sweep: exit status $?: $(cat run/err2.txt)"
reused=$(sed -n 's/^! resuming: \([0-9]*\) of 8 runs reused.*/\1/p' run/out2.txt)
[ -n "$reused" ] && [ "$reused" -ge 2 ] && [ "$reused" -ge "$done_before" ] ||
    fail "resume reused '${reused}' runs, $done_before were complete: $(cat run/out2.txt | grep '^!')"
[ "$(grep -c '^! reused ' run/out2.txt)" = "${reused:-x}" ] || fail "reused runs not listed"
(cd ref/out && find . -type f ! -name .taper.lock | LC_ALL=C sort) > files.ref
(cd run/out && find . -type f ! -name .taper.lock | LC_ALL=C sort) > files.run
diff files.ref files.run >&2 || fail "the resumed sweep's files differ from the uninterrupted one's"
while IFS= read -r f; do
    same_result "ref/out/$f" "run/out/$f" || fail "$f differs after resume"
done < files.ref

# Ctrl-C (SIGINT): the run in progress ends partial, exit status 3, no
# sweep.tsv; the same command then completes it, byte-identical again.
mkdir int
(cd int && exec "$TAPER" ../sweep.nml -o out > out1.txt 2> err1.txt) &
pid=$!
i=0
while [ "$(ls int/out/*/scene.hash 2> /dev/null | wc -l)" -lt 2 ] && [ $i -lt 600 ]; do
    sleep 0.05
    i=$((i + 1))
done
kill -INT $pid 2> /dev/null
wait $pid
status=$?
if [ "$(ls int/out/*/scene.hash 2> /dev/null | wc -l)" -lt 8 ]; then
    [ $status -eq 3 ] || fail "SIGINT: exit status $status, wanted 3"
    grep -q "sweep.nml: interrupted: .* runs complete; run the same command to resume" int/err1.txt ||
        fail "SIGINT: $(cat int/err1.txt)"
    [ ! -f int/out/sweep.tsv ] || fail "SIGINT: an interrupted sweep wrote sweep.tsv"
fi
(cd int && "$TAPER" ../sweep.nml -o out > out2.txt 2> err2.txt) || fail "after SIGINT: $(cat int/err2.txt)"
while IFS= read -r f; do
    same_result "ref/out/$f" "int/out/$f" || fail "$f differs after SIGINT and resume"
done < files.ref
[ "$(cd int/out && find . -type f ! -name .taper.lock | LC_ALL=C sort)" = "$(cat files.ref)" ] || fail "SIGINT: files differ"

# Another sweep in the same directory (the scene edited: a run's hash
# covers the scene file's name, which its granules.tsv echoes): shared runs
# reused, the others gone.
sed 's/5000, 5001, 5002, 5003, 5004, 5005, 5006, 5007/5001, 5000, 4000/' sweep.nml > other.nml
mv other.nml sweep.nml
(cd run && "$TAPER" ../sweep.nml -o out > out3.txt 2> err3.txt) || fail "other sweep: $(cat run/err3.txt)"
grep -q '^! resuming: 2 of 3 runs reused' run/out3.txt || fail "other sweep: $(grep '^!' run/out3.txt)"
grep -q '^! removed 6 run directories of an earlier sweep from out' run/out3.txt ||
    fail "other sweep: stale runs not removed: $(grep '^!' run/out3.txt)"
[ "$(ls run/out | tr '\n' ' ')" = "fits.tsv n_granules=4000 n_granules=5000 n_granules=5001 runs.tsv sweep.tsv " ] ||
    fail "other sweep: $(ls run/out | tr '\n' ' ')"
[ "$(grep -vc '^#' run/out/sweep.tsv)" -eq $((1 + 5001 + 5000 + 4000)) ] || fail "other sweep: sweep.tsv mixes runs"
# A changed setting: nothing reused.
(cd run && "$TAPER" ../sweep.nml -o out --set solver.rtol=1d-9 > out4.txt 2> err4.txt) || fail "rtol: $(cat run/err4.txt)"
! grep -q '^! resuming' run/out4.txt || fail "runs of another rtol reused: $(grep '^!' run/out4.txt)"
grep -q '^#   rtol = 1e-09$' run/out/n_granules=5000/granules.tsv || fail "rtol: run not redone"

[ $failures -eq 0 ] && echo "resume: $reused of 8 runs reused after SIGKILL, results byte-identical; other sweeps never mixed in"
[ $failures -eq 0 ]
