#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# mpi.sh TAPER MPIRUN -- a sweep on MPI ranks: a grid of
# 2 x 3 runs (q x exponent) with fits, on 2 and 3 ranks (3 oversubscribe
# this 2-core machine), every file byte-identical to the serial sweep's;
# then the launcher killed (SIGKILL) halfway and the sweep resumed under
# mpirun, byte-identical again.
set -u
TAPER=$1
. "$(dirname "$0")/same_result.sh"
MPIRUN=$2
case $TAPER in /*) ;; *) TAPER=$(pwd)/$TAPER ;; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
# As root, Open MPI wants to be told; more ranks than cores are fine here.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpirun() { timeout 300 "$MPIRUN" --oversubscribe "$@"; }

cat > grid.nml <<'NML'
&chain profile = 'backward_exponential', n_granules = 400
       q = 0.02, 0.05
       exponent = 2.0, 2.5, 3.0 /
&output threads = 1, progress = .false. /
&fit model = 'exponential', y = 'v', k_min = 10, factor = -1, label = 'rate' /
NML
same_as_serial() { # DIR: every file as in serial/out
    (cd serial/out && find . -type f ! -name .taper.lock | LC_ALL=C sort) > files.serial
    (cd "$1/out" && find . -type f ! -name .taper.lock | LC_ALL=C sort) > "files.$1"
    diff files.serial "files.$1" >&2 || { fail "$1: not the serial sweep's files"; return; }
    while IFS= read -r f; do
        same_result "serial/out/$f" "$1/out/$f" || fail "$1: $f differs from the serial sweep's"
    done < files.serial
}
mkdir serial np2 np3 killed
(cd serial && "$TAPER" ../grid.nml -o out > out.txt 2> err.txt) || fail "serial: $(cat serial/err.txt)"
[ "$(ls -d serial/out/q=* | wc -l)" -eq 6 ] || fail "serial: not 6 runs"
for k in 2 3; do
    (cd np$k && mpirun -np $k "$TAPER" ../grid.nml -o out > out.txt 2> err.txt)
    status=$?
    [ $status -eq 0 ] || fail "mpirun -np $k: exit status $status: $(cat np$k/err.txt)"
    same_as_serial np$k
    # One rank speaks: the messages of the serial sweep, in its order.
    grep '^!' serial/out.txt > a
    grep '^!' np$k/out.txt > b
    cmp -s a b || fail "mpirun -np $k: stdout differs from the serial sweep's"
done

# The launcher killed halfway, then the same command: resumed.
cat > long_$$.nml <<'NML'
&chain profile = 'backward_exponential', n_granules = 5000
       q = 1d-4, 2d-4
       exponent = 2.0, 2.5, 3.0 /
&output threads = 1, progress = .false. /
NML
mkdir longserial
(cd longserial && "$TAPER" ../long_$$.nml -o out > /dev/null 2>&1) || fail "long serial sweep"
(cd killed && exec "$MPIRUN" --oversubscribe -np 2 "$TAPER" ../long_$$.nml -o out > out1.txt 2> err1.txt) &
pid=$!
i=0
while [ "$(ls killed/out/*/scene.hash 2> /dev/null | wc -l)" -lt 2 ] && [ $i -lt 1200 ]; do
    sleep 0.05
    i=$((i + 1))
done
kill -KILL $pid 2> /dev/null
wait $pid 2> /dev/null
# The orphaned ranks notice within seconds that their launcher is gone.
i=0
while ps -eo args | grep -q "^$TAPER \.\./long_$$.nml" && [ $i -lt 200 ]; do
    sleep 0.1
    i=$((i + 1))
done
(cd killed && mpirun -np 2 "$TAPER" ../long_$$.nml -o out > out2.txt 2> err2.txt) ||
    fail "resumed under mpirun: $(cat killed/err2.txt)"
grep -q '^! resuming: [0-9]* of 6 runs reused' killed/out2.txt || echo "note: nothing to reuse (the sweep ended before it was killed?)" >&2
rm -rf serial && mv longserial serial
same_as_serial killed

[ $failures -eq 0 ] && echo "MPI: 2 and 3 ranks byte-identical to the serial sweep; resumed after SIGKILL of mpirun"
[ $failures -eq 0 ]
