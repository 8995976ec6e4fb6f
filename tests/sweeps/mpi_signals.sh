#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# mpi_signals.sh TAPER MPIRUN -- an MPI sweep stopped by a signal, on 2
# ranks, then the same command: it reuses the runs that were complete and
# ends with every file byte-identical to a serial sweep's.
#  - SIGINT or SIGTERM to the ranks (as srun, scancel and a batch queue's
#    time limit deliver them): exit status 3, the signal named, as in a
#    serial sweep.
#  - SIGINT to one rank only: the whole sweep stops, status 3, and the runs
#    of the other rank say which rank got which signal.
#  - SIGINT or SIGTERM to mpirun: Open MPI's mpirun passes either on to
#    every rank as SIGTERM and exits with its own status (1 in Open MPI
#    4.1, whatever the ranks return): the runs say "SIGTERM from mpirun",
#    the status is not 0, and the sweep resumes all the same.
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

# Six runs; the exponent-2 runs take seconds, the others a fraction.
scene=sweep_$$.nml
cat > $scene <<'NML'
&chain profile = 'backward_exponential', n_granules = 2000
       q = 1d-4, 2d-4
       exponent = 2.0, 2.5, 3.0 /
&output threads = 1, progress = .false. /
NML
mkdir serial
(cd serial && "$TAPER" ../$scene -o out > out.txt 2> err.txt) || fail "serial sweep: $(cat serial/err.txt)"
(cd serial/out && find . -type f ! -name .taper.lock | LC_ALL=C sort) > files.serial

# The ranks of the sweep running: taper processes of this scene.
ranks_of() { ps -eo pid=,args= | awk -v t="$TAPER" -v s="../$scene" '$2 == t && $3 == s { print $1 }'; }
# The rank whose MPI rank is $1 (Open MPI's or PMI's environment variable).
rank_pid() {
    for p in $(ranks_of); do
        tr '\0' '\n' < /proc/$p/environ 2> /dev/null |
            grep -qx -e "OMPI_COMM_WORLD_RANK=$1" -e "PMI_RANK=$1" && echo $p
    done
}

# interrupt NAME WHOM SIGNAL: a sweep in NAME/, stopped once a run is
# complete by SIGNAL to WHOM (ranks, rank1, mpirun); leaves its exit status
# in NAME/status and the runs then complete in NAME/complete.
interrupt() {
    mkdir "$1"
    (cd "$1" && exec "$MPIRUN" --oversubscribe -np 2 "$TAPER" ../$scene -o out > out1.txt 2> err1.txt) &
    pid=$!
    i=0
    while [ "$(ls $1/out/*/scene.hash 2> /dev/null | wc -l)" -lt 1 ] && [ $i -lt 1200 ]; do
        sleep 0.05
        i=$((i + 1))
    done
    case $2 in
    ranks) kill -$3 $(ranks_of) ;;
    rank1) kill -$3 $(rank_pid 1) ;;
    mpirun) kill -$3 $pid ;;
    esac
    wait $pid
    echo $? > "$1/status"
    ls $1/out/*/scene.hash 2> /dev/null | wc -l > "$1/complete"
    # The ranks are gone before the same command runs again.
    i=0
    while [ -n "$(ranks_of)" ] && [ $i -lt 200 ]; do
        sleep 0.1
        i=$((i + 1))
    done
}

# resume NAME: the same command again, to the end, byte-identical.
resume() {
    (cd "$1" && "$MPIRUN" --oversubscribe -np 2 "$TAPER" ../$scene -o out > out2.txt 2> err2.txt) ||
        fail "$1: resumed sweep: exit status $?: $(cat $1/err2.txt)"
    done_before=$(cat "$1/complete")
    if [ "$done_before" -lt 6 ]; then
        reused=$(sed -n 's/^! resuming: \([0-9]*\) of 6 runs reused.*/\1/p' "$1/out2.txt")
        [ -n "$reused" ] && [ "$reused" -ge "$done_before" ] ||
            fail "$1: resume reused '$reused' runs, $done_before were complete"
    fi
    (cd "$1/out" && find . -type f ! -name .taper.lock | LC_ALL=C sort) > "files.$1"
    diff files.serial "files.$1" >&2 || fail "$1: not the serial sweep's files"
    while IFS= read -r f; do
        same_result "serial/out/$f" "$1/out/$f" || fail "$1: $f differs from the serial sweep's"
    done < files.serial
}

# stopped NAME: the sweep in NAME/ was stopped before its end (else the
# signal came too late to test anything: noted, not failed).
stopped() {
    [ "$(cat "$1/complete")" -lt 6 ] && return 0
    echo "note: $1: the sweep ended before the signal" >&2
    return 1
}
said_interrupted() {
    grep -q "$scene: interrupted: [0-9] of 6 runs complete; run the same command to resume" "$1/err1.txt" ||
        fail "$1: no summary: $(cat "$1/err1.txt")"
    [ ! -f "$1/out/sweep.tsv" ] || fail "$1: an interrupted sweep wrote sweep.tsv"
}

for sig in INT TERM; do
    interrupt ranks_$sig ranks $sig
    if stopped ranks_$sig; then
        [ "$(cat ranks_$sig/status)" -eq 3 ] || fail "SIG$sig to the ranks: exit status $(cat ranks_$sig/status), wanted 3"
        grep -q ": interrupted by SIG$sig at t = " ranks_$sig/err1.txt ||
            fail "SIG$sig to the ranks: signal not named: $(cat ranks_$sig/err1.txt)"
        ! grep -q "interrupted by SIG[A-Z]* \(from\|to\) " ranks_$sig/err1.txt ||
            fail "SIG$sig to the ranks: named as another's: $(cat ranks_$sig/err1.txt)"
        said_interrupted ranks_$sig
    fi
    resume ranks_$sig
done

interrupt rank1 rank1 INT
if stopped rank1; then
    [ "$(cat rank1/status)" -eq 3 ] || fail "SIGINT to rank 1: exit status $(cat rank1/status), wanted 3"
    grep -q ": interrupted by SIGINT\( to rank 1\)\? at t = " rank1/err1.txt ||
        fail "SIGINT to rank 1: signal not named: $(cat rank1/err1.txt)"
    said_interrupted rank1
fi
resume rank1

for sig in INT TERM; do
    interrupt mpirun_$sig mpirun $sig
    if stopped mpirun_$sig; then
        [ "$(cat mpirun_$sig/status)" -ne 0 ] || fail "SIG$sig to mpirun: exit status 0"
        grep -q ": interrupted by SIGTERM from [a-z]* at t = " mpirun_$sig/err1.txt ||
            fail "SIG$sig to mpirun: the launcher's SIGTERM not named: $(cat mpirun_$sig/err1.txt)"
        said_interrupted mpirun_$sig
    fi
    resume mpirun_$sig
done

[ $failures -eq 0 ] && echo "MPI signals: SIGINT, SIGTERM to the ranks: status 3, named; to mpirun: named as its SIGTERM; every sweep resumed byte-identical to the serial one"
[ $failures -eq 0 ]
