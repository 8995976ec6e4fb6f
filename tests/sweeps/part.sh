#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# part.sh TAPER -- a sweep split without MPI: parts
# 1/3, 2/3, 3/3 (a job array) each compute their share of the runs into the
# same directory, then the command without --part merges them (reuses all,
# computes none) into results byte-identical to the whole sweep in one go
# (but for each run's CPU time, which runs.tsv takes from its scene.hash).
set -u
TAPER=$1
. "$(dirname "$0")/same_result.sh"
case $TAPER in /*) ;; *) TAPER=$(pwd)/$TAPER ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

cat > grid.nml <<'NML'
&chain profile = 'backward_exponential', n_granules = 300, 200
       q = 0.02, 0.05, 0.1 /
&output progress = .false. /
&fit model = 'exponential', y = 'v', k_min = 10 /
NML
mkdir whole parts
(cd whole && "$TAPER" ../grid.nml -o out > out.txt 2> err.txt) || fail "whole sweep: $(cat whole/err.txt)"
for i in 1 2 3; do
    (cd parts && "$TAPER" ../grid.nml -o out --part $i/3 > part$i.txt 2> err$i.txt) ||
        fail "part $i/3: $(cat parts/err$i.txt)"
    grep -q "^! part $i/3: 2 of the 6 runs" parts/part$i.txt || fail "part $i/3: $(grep '^!' parts/part$i.txt)"
    [ ! -f parts/out/sweep.tsv ] || fail "part $i/3 wrote sweep.tsv"
done
# Every run computed once, by one part; the dear ones (N = 300) spread.
[ "$(cat parts/part*.txt | grep -c '^! wrote .*granules.tsv')" -eq 6 ] || fail "runs computed twice or never"
for i in 1 2 3; do
    grep -q "^! wrote out/n_granules=300," parts/part$i.txt || fail "part $i/3 has no run of N = 300"
done
(cd parts && "$TAPER" ../grid.nml -o out > merge.txt 2> merge.err) || fail "merge: $(cat parts/merge.err)"
grep -q '^! resuming: 6 of 6 runs reused' parts/merge.txt || fail "merge computed runs: $(grep '^!' parts/merge.txt)"
(cd whole/out && find . -type f ! -name .taper.lock | LC_ALL=C sort) > files.whole
(cd parts/out && find . -type f ! -name .taper.lock | LC_ALL=C sort) > files.parts
diff files.whole files.parts >&2 || fail "merged files differ from the whole sweep's"
while IFS= read -r f; do
    same_result "whole/out/$f" "parts/out/$f" || fail "$f differs after the merge"
done < files.whole
# The merge computed nothing: each run's CPU time in runs.tsv is the one
# its part recorded in its scene.hash (positive, to the microsecond).
awk -F '\t' 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "cpu_time[s]") c = i }
              NR > 1 && !/^#/ { print $1, $c }' parts/out/runs.tsv > cpu.runs
for d in parts/out/*/; do
    run=$(basename "$d")
    echo "$run $(sed -n 's/^cpu_time\[s\] //p' "$d/scene.hash")"
done | LC_ALL=C sort > cpu.stamps
LC_ALL=C sort cpu.runs | diff - cpu.stamps >&2 || fail "runs.tsv's CPU times are not the parts' scene.hash's"
awk '!($2 > 0) { bad = 1 } END { exit bad || NR != 6 }' cpu.runs || fail "CPU times: $(cat cpu.runs)"

for bad in 0/3 4/3 1/0 x 2/ -1/2; do
    "$TAPER" grid.nml -o bad --part "$bad" > /dev/null 2> err.txt
    [ $? -eq 2 ] && grep -q 'write I/N' err.txt || fail "--part $bad accepted: $(cat err.txt)"
done
printf "&chain n_granules = 20 /\n" > one.nml
"$TAPER" one.nml --part 1/2 > /dev/null 2> err.txt
[ $? -eq 2 ] && grep -q 'not a sweep' err.txt || fail "--part of a single run: $(cat err.txt)"

[ $failures -eq 0 ] && echo "--part: 3 parts merged, byte-identical to the whole sweep"
[ $failures -eq 0 ]
