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
#   lock       a second run into a directory in use is refused (exit 2); a
#              second scene of the same command into the same directory is not
#   phases     (slow) SIGTERM within 0.5 s in every phase: the theory of 10^7
#              granules, a wide window and a sampled run after the pulse,
#              the write of a complete result, gnuplot; the status and the
#              message say what is on disk
#   results    every result file ends with its footer (rows, bytes, CRC-32);
#              a write beyond `ulimit -f` is reported, its temporary removed;
#              temporaries a killed run left are removed by the next; a
#              figure that cannot be drawn is refused before the run, or
#              leaves no picture
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
    # Each signal at its default disposition in the run, whatever this
    # script inherited: under nohup SIGHUP arrives ignored, and the driver
    # rightly keeps an ignored SIGHUP ignored (the last case below); a
    # shell cannot reset an ignored signal, env --default-signal can.
    for sig in TERM HUP XCPU INT; do
        env --default-signal="$sig" "$TAPER" long.nml -o "s_$sig" > /dev/null 2> "s_$sig.err" &
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
    # Two scenes of one command into one directory (issue 36, item 5): the
    # second goes on under the first's lock; there is no other run.
    printf "&chain n_granules = 20 /\n&output dir = 'same' /\n" > a.nml
    printf "&chain n_granules = 21 /\n&output dir = 'same' /\n" > b.nml
    "$TAPER" a.nml b.nml > ab.out 2> ab.err || fail "a.nml b.nml into one directory: $(cat ab.err)"
    [ "$(tail -n 1 same/granules.tsv | cut -d, -f1)" = "# end: rows 21" ] || fail "the second scene's result is not there"
    "$TAPER" a.nml a.nml > /dev/null 2> aa.err || fail "a.nml a.nml: $(cat aa.err)"
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

# Seconds from $1 (date +%s.%N) to now.
since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }'; }

# SIGTERM to $pid (started with stdout to $1.out, stderr to $1.err) once
# $2 (a test command) holds; waits, and sets status and took.
term_when() {
    i=0
    while ! eval "$2" && kill -0 "$pid" 2> /dev/null && [ $i -lt 3000 ]; do sleep 0.01; i=$((i + 1)); done
    sent=$(date +%s.%N)
    kill -TERM "$pid" 2> /dev/null
    wait "$pid"
    status=$?
    took=$(since "$sent")
}

# Runs the phase $1 (a function below: it starts the driver, signals it
# through term_when and checks what is on disk) and fails unless the exit
# came within 0.5 s of the signal.  That is wall time, and on a shared
# machine a process that needs 0.05 s of CPU after the signal can wait for
# a core, or run slowly beside a build, for longer: a phase over the bound
# is run once more, and fails only if it is over again (a phase that does
# not look at its signal is over every time).
prompt() {
    rm -rf "p_$1"
    "phase_$1"
    echo "$1: $took s from SIGTERM to the exit"
    awk -v t="$took" 'BEGIN { exit !(t <= 0.5) }' && return
    echo "note: $1: $took s, over 0.5 s at a load average of $(cut -d' ' -f1 /proc/loadavg): once more" >&2
    rm -rf "p_$1"
    "phase_$1"
    echo "$1: $took s from SIGTERM to the exit"
    awk -v t="$took" 'BEGIN { exit !(t <= 0.5) }' || fail "$1: $took s from the signal to the exit, over 0.5 s twice"
}

# The theory of 10^7 granules (numerics off): ~1 s, stopped at once,
# nothing written.
phase_theory() {
    printf "&chain n_granules = 10000000 /\n&solver numerics = .false. /\n" > theory.nml
    "$TAPER" theory.nml -o p_theory > p_theory.out 2> p_theory.err &
    pid=$!
    term_when p_theory "sleep 0.4; true"
    [ "$status" -eq 3 ] || fail "theory: exit status $status, wanted 3 ($(cat p_theory.err))"
    # (under load the signal may still find the chain being built: "before
    # this run started"; the chain of 10^7 granules takes ~0.2 s)
    grep -q "interrupted by SIGTERM .*nothing of this run is written" p_theory.err ||
        fail "theory: $(cat p_theory.err)"
    [ -e p_theory/granules.tsv ] || [ -e p_theory/granules.partial.tsv ] && fail "theory: a result file"
}

# A loaded chain after the pulse: 800 granules in the window, no event
# (20000 steps of it, the integrator's old limit per call, take ~1 s).
phase_wide() {
    printf "&chain n_granules = 800, load = 1e-3 /\n&solver t_end = 1e6 /\n" > wide.nml
    "$TAPER" wide.nml -o p_wide > p_wide.out 2> p_wide.err &
    pid=$!
    term_when p_wide "sleep 3.5; true"
    [ "$status" -eq 3 ] && grep -q 'interrupted by SIGTERM at t = ' p_wide.err ||
        fail "wide window: exit status $status: $(cat p_wide.err)"
    grep -q 'past granule 799 of 799' p_wide.err ||
        echo "note: wide window: the pulse had not left the chain yet (a loaded machine): $(cat p_wide.err)" >&2
    grep -q '^# PARTIAL result (interrupted)' p_wide/granules.partial.tsv 2> /dev/null ||
        fail "wide window: no partial file"
}

# The same sampled (issue 36, item 1): the integrator returns at every
# sample, never at its steps' limit, long after the last event.
phase_sampled() {
    printf "&chain n_granules = 400, load = 1e-3 /\n&solver t_end = 2e5 /\n&sensors interval = 20.0, granules = 1, 200, 400 /\n" > sampled.nml
    "$TAPER" sampled.nml -o p_sampled > p_sampled.out 2> p_sampled.err &
    pid=$!
    term_when p_sampled "sleep 2.5; true"
    [ "$status" -eq 3 ] && grep -q 'interrupted by SIGTERM at t = ' p_sampled.err ||
        fail "sampled: exit status $status: $(cat p_sampled.err)"
    grep -q 'past granule 399 of 399' p_sampled.err ||
        echo "note: sampled: the pulse had not left the chain yet (a loaded machine): $(cat p_sampled.err)" >&2
    [ -e p_sampled/granules.tsv ] && fail "sampled: granules.tsv of an interrupted run"
    [ -f p_sampled/sensors.tsv ] || fail "sampled: the samples found are not written"
}

# The write of a complete result (item 2): the file being written is
# removed, nothing after it starts, and the message says so.
phase_write() {
    printf "&chain n_granules = 2000000 /\n&solver numerics = .false. /\n" > write.nml
    "$TAPER" write.nml -o p_write > p_write.out 2> p_write.err &
    pid=$!
    term_when p_write "ls -a p_write 2> /dev/null | grep -q '^\.granules'"
    [ "$status" -eq 3 ] || fail "writing: exit status $status, wanted 3 ($(cat p_write.err))"
    grep -q "interrupted by SIGTERM while writing p_write/granules.tsv: it is not written" p_write.err ||
        fail "writing: $(cat p_write.err)"
    [ -e p_write/granules.tsv ] && fail "writing: granules.tsv written after the signal said it is not"
    no_temp p_write writing
}

# A complete sampled run whose sensors.tsv is being written: granules.tsv
# (written before the signal) stays, whole; sensors.tsv is not written.
phase_sens() {
    printf "&chain n_granules = 100 /\n&solver t_end = 4e5 /\n&sensors interval = 1.0, granules = 1, 50, 100 /\n" > sens.nml
    "$TAPER" sens.nml -o p_sens > p_sens.out 2> p_sens.err &
    pid=$!
    term_when p_sens "ls -a p_sens 2> /dev/null | grep -q '^\.sensors'"
    [ "$status" -eq 3 ] || fail "sensors: exit status $status ($(cat p_sens.err))"
    grep -q "while writing p_sens/sensors.tsv: it is not written" p_sens.err || fail "sensors: $(cat p_sens.err)"
    tail -n 1 p_sens/granules.tsv | grep -q '^# end: rows 100,' || fail "sensors: granules.tsv not whole"
    [ -e p_sens/sensors.tsv ] && fail "sensors: sensors.tsv written after the signal said it is not"
}

# A sweep on two threads: the runs in progress stop and write what they
# found, no run starts after the signal, the next command resumes.
phase_sweep() {
    printf "&chain n_granules = 40000, 40001, 40002, 40003 /\n&output threads = 2 /\n" > sw.nml
    "$TAPER" sw.nml -o p_sweep > p_sweep.out 2> p_sweep.err &
    pid=$!
    term_when p_sweep "sleep 1; true"
    [ "$status" -eq 3 ] && grep -q "interrupted: [0-9] of 4 runs complete; run the same command to resume" p_sweep.err ||
        fail "sweep: exit status $status: $(cat p_sweep.err)"
    [ -e p_sweep/sweep.tsv ] && fail "sweep: sweep.tsv of an interrupted sweep"
}

# gnuplot drawing: stopped with the run, no picture left.
phase_fig() {
    printf '#!/bin/sh\n: > figure.png\nexec sleep 30\n' > slowplot
    chmod +x slowplot
    printf "&chain profile = 'backward_linear', s = 0.1, 0.2, n_granules = 20 /\n&solver numerics = .false. /\n&fit model = 'power', y = 'v', k_min = 3 /\n&figure name = 'f', y = 'v' /\n" > fig.nml
    TAPER_GNUPLOT=$(pwd)/slowplot "$TAPER" fig.nml -o p_fig > p_fig.out 2> p_fig.err &
    pid=$!
    term_when p_fig "[ -e p_fig/figure.png ]"
    [ "$status" -eq 3 ] || fail "gnuplot: exit status $status ($(cat p_fig.err))"
    grep -q "while writing p_fig/figure.png: it is not written" p_fig.err || fail "gnuplot: $(cat p_fig.err)"
    [ -e p_fig/figure.png ] && fail "gnuplot: a picture left under the result's name"
}

phases() {
    for phase in theory wide sampled write sens sweep fig; do prompt "$phase"; done
}

results() {
    # The footer: rows, bytes and the CRC-32 of every byte above it.
    printf "&chain n_granules = 30 /\n&ends right = 'wall' /\n&solver t_end = 60 /\n&sensors interval = 0.5, granules = 1, 30 /\n" > w.nml
    "$TAPER" w.nml -o foot > /dev/null 2> foot.err || fail "footer run: $(cat foot.err)"
    for f in granules.tsv sensors.tsv walls.tsv; do
        python3 - "foot/$f" <<'PY' || fail "$f: its footer does not check"
import re, sys, zlib
data = open(sys.argv[1], "rb").read()
cut = data.rindex(b"\n", 0, len(data) - 1) + 1
rows, size, crc = re.fullmatch(rb"# end: rows (\d+), bytes (\d+), crc32 ([0-9a-f]{8})\n", data[cut:]).groups()
body = data[:cut]
lines = body.split(b"\n")[:-1]
assert int(size) == len(body) and int(crc, 16) == zlib.crc32(body)
assert int(rows) == sum(1 for i, l in enumerate(lines) if i and l and not l.startswith(b"#"))
PY
    done
    [ "$(tail -n 1 foot/granules.tsv | cut -d, -f1)" = "# end: rows 30" ] || fail "granules.tsv: $(tail -n 1 foot/granules.tsv)"
    # A file-size limit (ulimit -f, 64 kB): the write fails, is reported,
    # its temporary removed; status 1 (issue 36, item 4).
    printf "&chain n_granules = 20000 /\n&solver numerics = .false. /\n" > big.nml
    (ulimit -f 128; exec "$TAPER" big.nml -o fsize > /dev/null 2> fsize.err)
    status=$?
    [ "$status" -eq 1 ] || fail "ulimit -f: exit status $status, wanted 1 ($(cat fsize.err))"
    grep -q "writing fsize/granules.tsv failed: File too large (the incomplete file is removed)" fsize.err ||
        fail "ulimit -f: $(cat fsize.err)"
    [ -e fsize/granules.tsv ] && fail "ulimit -f: granules.tsv"
    no_temp fsize "ulimit -f"
    # Temporaries a killed run left (SIGKILL while writing): removed by the
    # next run into the directory, and only those of taper's own names.
    printf "&chain n_granules = 2000000 /\n&solver numerics = .false. /\n" > huge_th.nml
    "$TAPER" huge_th.nml -o killed > /dev/null 2>&1 &
    pid=$!
    i=0
    while ! ls -a killed 2> /dev/null | grep -q '^\.granules' && [ $i -lt 3000 ]; do sleep 0.01; i=$((i + 1)); done
    kill -KILL "$pid"
    wait "$pid" 2> /dev/null
    ls -a killed | grep -q '^\.granules.tsv\.' || fail "SIGKILL: no temporary to clean (the test lost the race)"
    : > killed/.sensors.tsv.AbC123
    : > killed/.mine.txt
    printf "&chain n_granules = 20 /\n" > small.nml
    "$TAPER" small.nml -o killed > killed.out 2>&1 || fail "run after SIGKILL: $(cat killed.out)"
    grep -q '^! removed 2 temporary files a killed taper left in killed$' killed.out ||
        fail "the temporaries removed are not said: $(grep '^!' killed.out)"
    no_temp killed "after SIGKILL"
    ls -a killed | grep -q '^\.sensors' && fail "a stale .sensors.tsv temporary stayed"
    [ -e killed/.mine.txt ] || fail "a file that is not taper's was removed"
    # A figure of the dynamics without them: refused before the run (item 6).
    src=$(dirname "$TAPER")/../../..
    if [ -f "$src/share/scenes/paper/fig02.nml" ]; then
        "$TAPER" "$src/share/scenes/paper/fig02.nml" solver.numerics=.false. -o fig02 > /dev/null 2> fig02.err
        status=$?
        [ "$status" -eq 2 ] && grep -q "&figure curves: curves = 'numerics' draws the dynamics" fig02.err ||
            fail "fig02 without numerics: exit status $status: $(cat fig02.err)"
        [ -e fig02 ] && fail "fig02 without numerics: a directory made before the refusal"
    fi
    # gnuplot failing after it opened the picture: no picture left.
    printf '#!/bin/sh\n: > figure.png\nexit 1\n' > badplot
    chmod +x badplot
    printf "&chain profile = 'backward_linear', s = 0.1, 0.2, n_granules = 20 /\n&solver numerics = .false. /\n&figure name = 'f', y = 'v' /\n" > figok.nml
    TAPER_GNUPLOT=$(pwd)/badplot "$TAPER" figok.nml -o badfig > /dev/null 2> badfig.err
    status=$?
    [ "$status" -eq 1 ] || fail "gnuplot failing: exit status $status ($(cat badfig.err))"
    grep -q "failed on badfig/figure.gp (status [0-9]*): badfig/figure.png not written" badfig.err ||
        fail "gnuplot failing: $(cat badfig.err)"
    [ -e badfig/figure.png ] && fail "gnuplot failing: a blank figure.png under the result's name"
}

case $SECTION in
    signals) signals ;;
    phases) phases ;;
    results) results ;;
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
