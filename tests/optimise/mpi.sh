#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# mpi.sh TAPER MPIRUN SOURCE_DIR SECTION -- a calibration and a design on
# MPI ranks (drivers/taper/optimise_mpi.c), one section per test:
#
#   same     share/scenes/optimise/calibrate_sensor.nml and design_taper.nml
#            with &output threads = 1, serial and under mpirun -np 2: the
#            optimiser's files (calibration.tsv, residuals.tsv, design.tsv,
#            profile.tsv, evaluations.tsv, the scene at the optimum) are
#            byte-identical, and rank 1 made runs: the line "! runs on 2
#            ranks: A on rank 0, B on rank 1" has B > 0 and A + B = the runs
#            the result file counts (runs, and a design's profile_runs); and
#            --part on the calibration refused (not a sweep) on every rank
#   signals  the calibration, its chain lengthened to 400 beads followed for
#            2 ms so that it lasts seconds, stopped by SIGTERM to the ranks
#            (exit status 3, as serial), by SIGINT to rank 1 alone (which
#            stops rank 0 too: status 3) and by SIGTERM to mpirun (Open MPI's mpirun
#            passes it on to every rank and exits with its own status, not
#            0): every rank ends, no calibration.tsv is written, and the same
#            command resumes from evaluations.tsv to the serial calibration
#            (its file identical but for the counts of runs made and reused)
set -u
absolute() { case $1 in /*) echo "$1" ;; *) echo "$(pwd)/$1" ;; esac; }
TAPER=$(absolute "$1")
MPIRUN=$2
SCENES=$(absolute "$3")/share/scenes/optimise
SECTION=$4
WORK=$(mktemp -d "${TMPDIR:-/tmp}/taper_optimise_mpi.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}
# As root, Open MPI wants to be told; more ranks than cores are fine here.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpirun() { timeout 300 "$MPIRUN" --oversubscribe "$@"; }

# spread DIR OUT RESULT: OUT's runs line says rank 1 made runs and the
# ranks' runs add up to the count in DIR/RESULT (a design's: the
# optimiser's runs and the profiles').
spread() {
    line=$(grep '^! runs on 2 ranks: ' "$2")
    a=$(echo "$line" | sed -n 's/.*: \([0-9]*\) on rank 0, \([0-9]*\) on rank 1$/\1/p')
    b=$(echo "$line" | sed -n 's/.*: \([0-9]*\) on rank 0, \([0-9]*\) on rank 1$/\2/p')
    runs=$(sed -n 's/^# \(profile_\)\{0,1\}runs = \([0-9]*\).*/\2/p' "$1/$3" | awk '{ n += $1 } END { print n }')
    [ -n "$a" ] && [ -n "$b" ] || { fail "$2: no runs line: '$line'"; return; }
    [ "$b" -gt 0 ] || fail "$2: rank 1 made no run: $line"
    [ "$((a + b))" -eq "$runs" ] || fail "$2: $a + $b runs on the ranks, $3 counts $runs"
}

# one NAME SCENE RESULT FILES...: SCENE serial and on 2 ranks, FILES compared.
one() {
    name=$1 scene=$2 result=$3
    shift 3
    mkdir "serial_$name" "np2_$name"
    (cd "serial_$name" && "$TAPER" "$SCENES/$scene" -o out output.threads=1 > out.txt 2> err.txt) ||
        fail "$name: serial: exit status $?: $(cat "serial_$name/err.txt")"
    (cd "np2_$name" && mpirun -np 2 "$TAPER" "$SCENES/$scene" -o out output.threads=1 > out.txt 2> err.txt) ||
        fail "$name: mpirun -np 2: exit status $?: $(cat "np2_$name/err.txt")"
    for f in "$result" "$@"; do
        [ -s "serial_$name/out/$f" ] || fail "$name: serial: no $f"
        cmp -s "serial_$name/out/$f" "np2_$name/out/$f" ||
            fail "$name: $f differs under mpirun -np 2: $(diff "serial_$name/out/$f" "np2_$name/out/$f" | head -5)"
    done
    spread "np2_$name/out" "np2_$name/out.txt" "$result"
    ! grep -q '^! runs on' "serial_$name/out.txt" || fail "$name: a serial run speaks of ranks"
}

same() {
    one calibrate calibrate_sensor.nml calibration.tsv residuals.tsv evaluations.tsv fitted.nml
    one design design_taper.nml design.tsv profile.tsv evaluations.tsv optimum.nml
    # Refused by rank 0 before it starts: every rank leaves the scene (no
    # worker left waiting for its end), exit status 2.
    timeout 60 "$MPIRUN" --oversubscribe -np 2 "$TAPER" "$SCENES/calibrate_sensor.nml" --part 1/2 \
        -o part > part.out 2> part.err
    status=$?
    [ "$status" -ne 124 ] || fail "--part on a calibration under mpirun: the ranks hang"
    [ "$status" -ne 0 ] || fail "--part on a calibration under mpirun: exit status 0"
    grep -q "is not a sweep" part.err || fail "--part on a calibration: $(cat part.err)"
}

# The ranks still running this test's calibration.
ranks() { ps -eo pid=,args= | awk -v t="$TAPER" '$2 == t && /calibrate_sensor/ { print $1 }'; }
# The one whose MPI rank is $1 (Open MPI's or PMI's environment variable).
rank_pid() {
    for p in $(ranks); do
        tr '\0' '\n' < /proc/$p/environ 2> /dev/null |
            grep -qx -e "OMPI_COMM_WORLD_RANK=$1" -e "PMI_RANK=$1" && echo $p
    done
}

signals() {
    set -- chain.n_granules=400 solver.t_end=2e-3 output.threads=1
    mkdir serial
    (cd serial && "$TAPER" "$SCENES/calibrate_sensor.nml" -o out "$@" > out.txt 2> err.txt) ||
        fail "serial: exit status $?: $(cat serial/err.txt)"
    for whom in ranks rank1 mpirun; do
        mkdir "$whom"
        (cd "$whom" && exec "$MPIRUN" --oversubscribe -np 2 "$TAPER" "$SCENES/calibrate_sensor.nml" \
            -o out "$@" > out1.txt 2> err1.txt) &
        pid=$!
        i=0 # until the Jacobian's runs have begun: a few rows in evaluations.tsv
        while [ "$(cat "$whom/out/evaluations.tsv" 2> /dev/null | grep -c '^[0-9]')" -lt 4 ] &&
            [ $i -lt 1200 ]; do
            sleep 0.05
            i=$((i + 1))
        done
        case $whom in
        ranks) kill -TERM $(ranks) ;;
        rank1) kill -INT $(rank_pid 1) ;;
        mpirun) kill -TERM $pid ;;
        esac
        wait $pid
        status=$?
        i=0
        while [ -n "$(ranks)" ] && [ $i -lt 100 ]; do
            sleep 0.1
            i=$((i + 1))
        done
        [ -z "$(ranks)" ] || fail "signal to the $whom: a rank still runs: $(ranks)"
        # 4 of 41 runs made when the signal comes: the calibration cannot
        # have ended by itself.
        [ ! -e "$whom/out/calibration.tsv" ] || fail "signal to the $whom: calibration.tsv written"
        case $whom in
        ranks | rank1) [ "$status" -eq 3 ] || fail "signal to the $whom: exit status $status, wanted 3" ;;
        mpirun) [ "$status" -ne 0 ] || fail "SIGTERM to mpirun: exit status 0" ;;
        esac
        grep -q "calibration interrupted: .*the same command resumes" "$whom/err1.txt" ||
            fail "signal to the $whom: $(cat "$whom/err1.txt")"
        done=$(grep -c '^[0-9]' "$whom/out/evaluations.tsv")
        (cd "$whom" && mpirun -np 2 "$TAPER" "$SCENES/calibrate_sensor.nml" -o out "$@" > out2.txt 2> err2.txt) ||
            fail "$whom: resumed: exit status $?: $(cat "$whom/err2.txt")"
        grep -q "resuming: $done runs of an interrupted calibration are reused" "$whom/out2.txt" ||
            fail "$whom: resumed: $(grep resuming "$whom/out2.txt") ($done runs before)"
        for f in calibration.tsv residuals.tsv; do
            grep -v -e '^# runs' -e '^# end:' "serial/out/$f" > a
            grep -v -e '^# runs' -e '^# end:' "$whom/out/$f" > b
            cmp -s a b || fail "$whom: resumed: $f differs from the serial one: $(diff a b | head -5)"
        done
    done
}

case $SECTION in
same | signals) "$SECTION" ;;
*) echo "mpi.sh: no section $SECTION" >&2; exit 2 ;;
esac
[ "$failures" -eq 0 ] && echo "optimise mpi $SECTION: all checks passed"
exit $((failures > 0))
