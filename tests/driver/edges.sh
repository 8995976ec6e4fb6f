#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# edges.sh TAPER SECTION -- the driver at the edges of its ranges, one
# section per item (each registered as its own test in meson.build):
#   signals    SIGTERM/SIGHUP/SIGXCPU keep the partial result (exit 3, the
#              signal named); a second signal while the partial file is
#              written leaves no temporary file
#   trust      conservation beyond &output max_energy_error: exit 4 and a
#              "# UNTRUSTED:" line; within it: exit 0, no such line
#   stdout     > /dev/full: exit 1, nothing run; | head -1: the run's own
#              status and every file written
#   format     granules.tsv: column names on line 1; &output columns/every;
#              no dynamics columns without numerics
#   lock       a second run into a directory in use is refused (exit 2)
#   cli        -o without a value, -o naming a file, &end, n_granules = 1e9,
#              - for stdin, GROUP.KEY=VALUE overrides, several scenes, the
#              progress line (under script(1), a terminal)
set -u
absolute() { case $1 in /*) echo "$1" ;; *) echo "$(pwd)/$1" ;; esac; }
TAPER=$(absolute "$1")
SECTION=$2
WORK=$(mktemp -d "${TMPDIR:-/tmp}/taper_edges.XXXXXX") || exit 1
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}
no_temp() { ls -a "$1" 2> /dev/null | grep '^\.granules' && fail "$2: temporary file left in $1"; }

# A run long enough to be interrupted (seconds), a partial file large enough
# to take a while to write (2e6 granules, 160 MB).
printf "&chain n_granules = 200000 /\n" > long.nml
printf "&chain n_granules = 2000000 /\n" > huge.nml

signals() {
    for sig in TERM HUP XCPU INT; do
        "$TAPER" long.nml -o "s_$sig" > /dev/null 2> "s_$sig.err" &
        pid=$!
        sleep 1
        kill -s "$sig" "$pid"
        wait "$pid"
        status=$?
        [ "$status" -eq 3 ] || fail "SIG$sig: exit status $status, wanted 3 ($(cat "s_$sig.err"))"
        [ -e "s_$sig/granules.tsv" ] && fail "SIG$sig wrote granules.tsv"
        grep -q "^# PARTIAL result (interrupted): interrupted by SIG$sig" "s_$sig/granules.partial.tsv" 2> /dev/null ||
            fail "SIG$sig: no partial file naming the signal"
        grep -q "interrupted by SIG$sig" "s_$sig.err" || fail "SIG$sig: stderr does not name it: $(cat "s_$sig.err")"
        no_temp "s_$sig" "SIG$sig"
    done
    # A second SIGTERM while the 160 MB partial file is written: the process
    # dies by it (143) and removes the temporary file.  Polled every 10 ms;
    # writing takes about 2 s, so the window is hit every time here.
    "$TAPER" huge.nml -o twice > /dev/null 2> twice.err &
    pid=$!
    sleep 1.5
    kill -TERM "$pid"
    seen=0
    while kill -0 "$pid" 2> /dev/null; do
        if ls -a twice | grep -q '^\.granules'; then
            seen=1
            kill -TERM "$pid"
            break
        fi
        sleep 0.01
    done
    wait "$pid"
    status=$?
    if [ "$seen" -eq 1 ]; then
        [ "$status" -eq 143 ] || fail "second SIGTERM during the write: exit status $status, wanted 143"
        no_temp twice "second SIGTERM during the write"
        [ -e twice/granules.partial.tsv ] && fail "second SIGTERM: a partial file appeared after all"
    else
        echo "note: the partial file was written before a second signal could be sent" >&2
    fi
    # SIGHUP ignored by the parent (nohup) stays ignored: the run completes.
    printf "&chain n_granules = 100000 /\n" > short.nml
    (trap '' HUP; exec "$TAPER" short.nml -o hup > /dev/null 2>&1) &
    pid=$!
    sleep 0.5
    kill -HUP "$pid" 2> /dev/null
    wait "$pid"
    status=$?
    [ "$status" -eq 0 ] || fail "SIGHUP under nohup: exit status $status, wanted 0"
}

trust() {
    printf "&chain n_granules = 50 /\n&solver rtol = 0.1, atol = 0.1 /\n" > loose.nml
    "$TAPER" loose.nml -o loose > /dev/null 2> loose.err
    status=$?
    [ "$status" -eq 4 ] || fail "rtol = atol = 0.1: exit status $status, wanted 4"
    grep -q '^# UNTRUSTED: energy error .* exceeds 0.001' loose/granules.tsv ||
        fail "rtol = atol = 0.1: no UNTRUSTED line in granules.tsv"
    grep -q 'UNTRUSTED result' loose.err || fail "rtol = atol = 0.1: stderr says nothing: $(cat loose.err)"
    # The bound is the scene's: raised (to the largest allowed), the same run is trusted.
    "$TAPER" loose.nml -o loose2 output.max_energy_error=1d300 output.max_momentum_error=1d300 > /dev/null 2>&1
    status=$?
    [ "$status" -eq 0 ] || fail "bounds of 1e300: exit status $status, wanted 0"
    grep -q '^# UNTRUSTED' loose2/granules.tsv && fail "bounds of 1e300: still UNTRUSTED"
    # Default tolerances: trusted.
    printf "&chain n_granules = 50 /\n" > good.nml
    "$TAPER" good.nml -o good > /dev/null 2>&1 || fail "default tolerances: exit status $?"
    grep -q '^# UNTRUSTED' good/granules.tsv && fail "default tolerances: UNTRUSTED"
    # A sweep with one untrusted run: status 4, sweep.tsv still written.
    printf "&chain profile = 'backward_linear', s = 0.001, 0.002, n_granules = 40 /\n&solver rtol = 0.1, atol = 0.1 /\n" > sweep.nml
    "$TAPER" sweep.nml -o sweep > /dev/null 2>&1
    status=$?
    [ "$status" -eq 4 ] || fail "untrusted sweep: exit status $status, wanted 4"
    [ -f sweep/sweep.tsv ] || fail "untrusted sweep: no sweep.tsv"
}

stdout_checks() {
    printf "&chain n_granules = 30 /\n" > small.nml
    "$TAPER" small.nml -o full > /dev/full 2> full.err
    status=$?
    [ "$status" -eq 1 ] || fail "> /dev/full: exit status $status, wanted 1"
    grep -q 'cannot write to standard output' full.err || fail "> /dev/full: $(cat full.err)"
    [ -e full/granules.tsv ] && fail "> /dev/full: the scene ran with its echo lost"
    "$TAPER" --defaults > /dev/full 2> /dev/null
    [ $? -eq 1 ] || fail "--defaults > /dev/full must exit 1"
    # A reader that stops after one line: the run's status, every file.
    status=$( { "$TAPER" small.nml -o piped 2> piped.err; echo $? > piped.status; } | head -n 1 > /dev/null; cat piped.status)
    [ "$status" -eq 0 ] || fail "| head -1: exit status $status, wanted 0 ($(cat piped.err))"
    [ -f piped/granules.tsv ] || fail "| head -1: no granules.tsv"
    [ -s piped.err ] && fail "| head -1: stderr: $(cat piped.err)"
    # A sweep writes many lines after the reader left.
    printf "&chain profile = 'backward_linear', s = 0.01, 0.02, 0.03 /\n&solver numerics = .false. /\n" > sw.nml
    status=$( { "$TAPER" sw.nml -o pipedsw 2> /dev/null; echo $? > sw.status; } | head -n 1 > /dev/null; cat sw.status)
    [ "$status" -eq 0 ] || fail "sweep | head -1: exit status $status, wanted 0"
    [ -f pipedsw/sweep.tsv ] || fail "sweep | head -1: no sweep.tsv"
}

format_checks() {
    printf "&chain n_granules = 25 /\n" > f.nml
    "$TAPER" f.nml -o f > /dev/null 2>&1 || fail "format run: exit $?"
    first=$(head -n 1 f/granules.tsv)
    [ "$first" = "$(printf 'k\tR\tm\tX0\tt_pass\tT_res\tv_peak\tt_peak\tX_pass\ttheory_v\ttheory_T\ttheory_t')" ] ||
        fail "first line of granules.tsv is '$first'"
    # Exactly one line before the rows that is not a comment.
    n=$(grep -vc '^#' f/granules.tsv)
    [ "$n" -eq 26 ] || fail "$n lines that are not comments, wanted 1 + 25"
    # Theory only: no columns of the dynamics.
    "$TAPER" f.nml -o th solver.numerics=.false. > /dev/null 2>&1 || fail "theory run: exit $?"
    [ "$(head -n 1 th/granules.tsv)" = "$(printf 'k\tR\tm\tX0\ttheory_v\ttheory_T\ttheory_t')" ] ||
        fail "theory-only header: $(head -n 1 th/granules.tsv)"
    # Chosen columns and thinned rows: k 1, 11, 21 and the last, 25.
    "$TAPER" f.nml -o sel "output.columns='v_peak, theory_v'" output.every=10 > /dev/null 2>&1 ||
        fail "columns/every run: exit $?"
    [ "$(head -n 1 sel/granules.tsv)" = "$(printf 'k\tv_peak\ttheory_v')" ] ||
        fail "chosen columns: $(head -n 1 sel/granules.tsv)"
    ks=$(grep -v '^#' sel/granules.tsv | sed 1d | cut -f 1 | tr '\n' ' ')
    [ "$ks" = "1 11 21 25 " ] || fail "every = 10: rows k = $ks"
    # A dynamics column without numerics, an unknown column: refused (2).
    "$TAPER" f.nml solver.numerics=.false. "output.columns='t_pass'" > /dev/null 2> e1.err
    [ $? -eq 2 ] || fail "t_pass without numerics must exit 2"
    grep -q 'output columns: column t_pass is a result of the dynamics' e1.err || fail "t_pass without numerics: $(cat e1.err)"
    "$TAPER" f.nml "output.columns='v_pek'" > /dev/null 2> e2.err
    [ $? -eq 2 ] || fail "unknown column must exit 2"
    grep -q "no column 'v_pek'" e2.err || fail "unknown column: $(cat e2.err)"
    # gnuplot reads the names from the first line.
    if command -v gnuplot > /dev/null 2>&1; then
        gnuplot -e "set datafile columnheaders; set table 'gp.txt'; plot 'f/granules.tsv' using 'k':'v_peak' with points" 2> gp.err ||
            fail "gnuplot: $(cat gp.err)"
        rows=$(grep -c ' i$' gp.txt 2> /dev/null || echo 0)
        [ "$rows" -eq 25 ] || fail "gnuplot read $rows points, wanted 25 ($(head -c 300 gp.txt))"
    fi
}

lock() {
    "$TAPER" long.nml -o shared > /dev/null 2> first.err &
    pid=$!
    sleep 0.5
    "$TAPER" long.nml -o shared > /dev/null 2> second.err
    status=$?
    [ "$status" -eq 2 ] || fail "second run into a directory in use: exit status $status, wanted 2"
    grep -q 'shared is in use by another taper run' second.err || fail "second run: $(cat second.err)"
    kill -INT "$pid"
    wait "$pid"
    [ $? -eq 3 ] || fail "the first run was disturbed: $(cat first.err)"
    grep -q 'interrupted by SIGINT' shared/granules.partial.tsv || fail "the first run's partial file is not its own"
    # Once the first has ended, the directory is free again.
    printf "&chain n_granules = 20 /\n" > short.nml
    "$TAPER" short.nml -o shared > /dev/null 2>&1 || fail "the directory stays locked after the run: $?"
    [ -e shared/granules.partial.tsv ] && fail "a re-run left the stale partial file"
}

cli() {
    printf "&chain n_granules = 20 /\n&solver numerics = .false. /\n" > c.nml
    "$TAPER" c.nml -o > /dev/null 2> e.err
    [ $? -eq 2 ] || fail "-o without a value must exit 2"
    grep -q '^taper: -o: needs a directory' e.err || fail "-o without a value: $(head -n 1 e.err)"
    "$TAPER" c.nml --set > /dev/null 2> e.err
    grep -q '^taper: --set: needs GROUP.KEY=VALUE' e.err || fail "--set without a value: $(head -n 1 e.err)"
    : > afile
    "$TAPER" c.nml -o afile > /dev/null 2> e.err
    [ $? -eq 2 ] || fail "-o naming a file must exit 2"
    grep -q 'afile: exists and is not a directory' e.err || fail "-o naming a file: $(cat e.err)"
    # &end closes a group.
    printf "&chain n_granules = 12 &end\n&solver numerics = .false. &END\n" > end.nml
    "$TAPER" end.nml -o end > /dev/null 2> e.err || fail "&end: $(cat e.err)"
    [ "$("$TAPER" end.nml --get chain.n_granules)" = 12 ] || fail "&end: n_granules not read"
    # n_granules = 1e9 names the range.
    printf "&chain n_granules = 1e9 /\n" > e9.nml
    "$TAPER" e9.nml > /dev/null 2> e.err
    [ $? -eq 2 ] || fail "n_granules = 1e9 must exit 2"
    grep -q 'e9.nml:1: &chain n_granules: 1e9 is not written as an integer: n_granules takes integers in \[2, 1e+07\]' e.err ||
        fail "n_granules = 1e9: $(cat e.err)"
    # Standard input.
    "$TAPER" - -o stdin_out < c.nml > /dev/null 2> e.err || fail "- (stdin): $(cat e.err)"
    [ -f stdin_out/granules.tsv ] || fail "- (stdin): no granules.tsv"
    grep -q '^# scene file: stdin' stdin_out/granules.tsv || fail "- (stdin): scene file not named stdin"
    printf "&chain n_granules = x /\n" | "$TAPER" - > /dev/null 2> e.err
    grep -q '^stdin:1: &chain n_granules' e.err || fail "- (stdin) errors: $(cat e.err)"
    # GROUP.KEY=VALUE overrides, positional or with --set.
    [ "$("$TAPER" c.nml chain.n_granules=1000 --get chain.n_granules)" = 1000 ] || fail "chain.n_granules=1000 not applied"
    "$TAPER" c.nml chain.n_granules=33 -o ov > /dev/null 2>&1 || fail "override run"
    [ "$(grep -vc '^#' ov/granules.tsv)" -eq 34 ] || fail "chain.n_granules=33: wrong number of rows"
    "$TAPER" c.nml chain.n_granulez=3 > /dev/null 2> e.err
    [ $? -eq 2 ] || fail "an override of an unknown variable must exit 2"
    # Several scenes: each into its own directory; -o takes one scene.
    printf "&chain n_granules = 10 /\n&solver numerics = .false. /\n&output dir = 'one' /\n" > one.nml
    printf "&chain n_granules = 11 /\n&solver numerics = .false. /\n&output dir = 'two' /\n" > two.nml
    "$TAPER" one.nml two.nml > both.out 2> e.err || fail "two scenes: $(cat e.err)"
    [ -f one/granules.tsv ] && [ -f two/granules.tsv ] || fail "two scenes: missing results"
    [ "$(grep -c '^! scene ' both.out)" -eq 2 ] || fail "two scenes: the echo does not name each"
    "$TAPER" one.nml e9.nml two.nml > /dev/null 2>&1
    [ $? -eq 2 ] || fail "a bad scene among several must give status 2"
    "$TAPER" one.nml two.nml -o x > /dev/null 2> e.err
    [ $? -eq 2 ] || fail "-o with two scenes must exit 2"
    # The progress line (stderr a terminal): simulation time, never nan.
    if command -v script > /dev/null 2>&1; then
        printf "&chain n_granules = 60000 /\n" > prog.nml
        script -qec "'$TAPER' prog.nml -o prog > /dev/null" /dev/null > prog.tty 2>&1
        grep -q 'granule [0-9]*/[0-9]*  t = [0-9.e+]*  ' prog.tty || fail "progress line without t = : $(tail -c 300 prog.tty)"
        grep -q 'nan' prog.tty && fail "progress line shows nan: $(tr '\r' '\n' < prog.tty | grep nan | head -n 2)"
    fi
}

case $SECTION in
    signals) signals ;;
    trust) trust ;;
    stdout) stdout_checks ;;
    format) format_checks ;;
    lock) lock ;;
    cli) cli ;;
    *) echo "edges.sh: unknown section $SECTION" >&2; exit 2 ;;
esac
if [ "$failures" -ne 0 ]; then
    echo "$SECTION: $failures failure(s)" >&2
    exit 1
fi
echo "$SECTION: all checks passed"
