# SPDX-License-Identifier: GPL-3.0-or-later
"""Ctrl-C: SIGINT to a process in the middle of a long call raises
KeyboardInterrupt promptly in every phase, returns nothing half-built, and the
package works afterwards.

How promptly is measured twice.  The wall time from the signal to the
``except KeyboardInterrupt`` is what a user waits; on this shared 2-core
machine, with other builds running, it is mostly the time the process waits
for a core, so it is held to a generous bound.  The CPU time the process
spends between the signal and the catch (Linux's per-thread schedstat, in
nanoseconds, read by the parent as it sends the signal and by the child as
it catches it) is what the code controls, whatever the load: it is held to
0.2 s, the issue's bound.

    python3 tests/bindings/python/test_interrupt.py [TRIALS]

(with the package importable, e.g. build/python-venv/bin/python) prints the
distribution of both over TRIALS signals per phase at random moments.
"""

import glob
import os
import random
import signal
import subprocess
import sys
import textwrap
import time

import pytest

SCRIPT = textwrap.dedent("""
    import sys, taper
    r = None
    try:
        print("started", flush=True)
        r = taper.simulate(profile="monodisperse", n_granules=200_000)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted, result:", r, flush=True)
        after = taper.simulate(n_granules=10)
        print("after:", after.complete, flush=True)
        raise
""")


def test_sigint_interrupts_a_long_run():
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "started"
    time.sleep(1.5)  # well into the integration
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    waited = time.monotonic() - sent
    assert "interrupted, result: None" in out, (out, err)
    assert "after: True" in out, (out, err)
    assert "KeyboardInterrupt" in err
    assert proc.returncode != 0
    assert waited < 10, waited


# Ctrl-C while the first call imports numpy (import taper does not): the
# signal comes from an import hook, while numpy's extension initialises
# (the first numpy module it imports) or once it is loaded and numpy's
# Python half goes on (numpy's umath).  It raised KeyboardInterrupt inside
# numpy's initialisation (or an ImportError numpy made of it) and left numpy
# half loaded, so that every later call failed: "cannot load module more
# than once per process".
IMPORT_SCRIPT = textwrap.dedent("""
    import os, signal, sys, taper
    assert "numpy" not in sys.modules

    class InterruptNumpy:
        seen_extension = False

        def find_spec(self, name, path=None, target=None):
            if name.endswith("._multiarray_umath"):
                self.seen_extension = True
            elif {when}:
                sys.meta_path.remove(self)
                os.kill(os.getpid(), signal.SIGINT)
            return None

    sys.meta_path.insert(0, InterruptNumpy())
    try:
        taper.chain(n_granules=10)
        print("not interrupted", flush=True)
    except KeyboardInterrupt:
        print("KeyboardInterrupt", flush=True)
    print("after:", len(taper.chain(n_granules=10).R), taper.simulate(n_granules=10).complete)
""")


@pytest.mark.parametrize("when", [
    'self.seen_extension and name.startswith("numpy.")',  # inside the extension's init
    'name.endswith("core.umath")',                         # after it
])
def test_sigint_while_numpy_is_imported(when):
    p = subprocess.run([sys.executable, "-c", IMPORT_SCRIPT.format(when=when)],
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    assert p.stdout.splitlines() == ["KeyboardInterrupt", "after: 10 True"], (p.stdout, p.stderr)


# Every phase of a call (issue 35: KeyboardInterrupt within 0.2 s in every
# phase; issue 36, item 1): the call, and the longest a signal may wait
# after the call starts to land somewhere inside it on this machine.
PHASES = {
    # building 10^7 granules, their columns, the theory's mu
    "chain": ("taper.chain(n_granules=10**7)", 0.6),
    # the binary-collision theory of 10^7 granules and its columns
    "theory": ("taper.theory(n_granules=10**7)", 1.0),
    # a run's every phase for 10^6 granules: chain, set-up (theory, scales),
    # the first steps before any pass, the integration, the columns
    "simulate": ("taper.simulate(n_granules=10**6)", 3.0),
    # a loaded chain after the pulse: a window of 800 granules and no event
    # (the integration's own look at the monitor, every ~0.05 s of steps)
    "wide window": ("taper.simulate(n_granules=800, load=1e-3, t_end=1e6)", 4.0),
    # the same sampled: every call of the integrator ends at a sample, never
    # at the steps' limit, and the pulse has passed (the sampler's look)
    "sampling": ("taper.simulate(n_granules=400, load=1e-3, t_end=2e5, interval=20.0)", 3.0),
}
CPU_BOUND = 0.2    # seconds of the process's CPU between the signal and the catch
WALL_BOUND = 1.5   # seconds of wall time, on a loaded 2-core machine

PHASE_SCRIPT = textwrap.dedent("""
    import glob, time, taper

    def cpu():
        return 1e-9 * sum(int(open(f).read().split()[0])
                          for f in glob.glob("/proc/self/task/*/schedstat"))

    try:
        print("started", flush=True)
        {call}
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("caught", repr(time.monotonic()), repr(cpu()), flush=True)
""")


def _cpu_of(pid):
    """The process's CPU seconds so far: the sum over its threads."""
    total = 0
    for f in glob.glob(f"/proc/{pid}/task/*/schedstat"):
        try:
            with open(f) as fp:
                total += int(fp.read().split()[0])
        except (OSError, ValueError, IndexError):
            pass  # a thread that ended meanwhile
    return 1e-9 * total


def interrupt_once(call, delay):
    """SIGINT `delay` seconds into `call` in a fresh interpreter: (wall,
    cpu) seconds from the signal to the catch, or None when the call ended
    first."""
    proc = subprocess.Popen([sys.executable, "-c", PHASE_SCRIPT.format(call=call)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "started", proc.stderr.read()
    time.sleep(delay)
    cpu_sent = _cpu_of(proc.pid)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    caught = [line.split() for line in out.splitlines() if line.startswith("caught")]
    if not caught:
        assert "finished" in out, (call, out, err)
        return None
    return float(caught[0][1]) - sent, float(caught[0][2]) - cpu_sent


schedstat = pytest.mark.skipif(not os.path.exists("/proc/self/schedstat"),
                               reason="needs Linux's /proc/PID/task/TID/schedstat")


def interrupt_at(call, delay, tries=3):
    """interrupt_once at the same moment until it is within both bounds, at
    most `tries` times: the best (wall, cpu) seen (the least CPU), or None.
    On a shared machine the CPU time of the same instructions swells with
    what the other core runs (its caches and memory bandwidth, a host's
    other guests): 0.05 s became 0.2-0.5 s while a build and another test
    ran beside this one.  A phase that does not look at the signal misses
    the bound at every try; a busy neighbour seldom twice."""
    best = None
    for _ in range(tries):
        got = interrupt_once(call, delay)
        if got is None:
            return best
        if best is None or got[1] < best[1]:
            best = got
        if best[1] < CPU_BOUND and best[0] < WALL_BOUND:
            break
    return best


@pytest.mark.slow
@schedstat
@pytest.mark.parametrize("phase", sorted(PHASES))
def test_sigint_within_a_fifth_of_a_second(phase):
    """Three signals at random moments of each call."""
    call, longest = PHASES[phase]
    rng = random.Random(phase)
    seen = []
    while len(seen) < 3:
        got = interrupt_at(call, rng.uniform(0.0, longest))
        if got is None:
            longest *= 0.5  # the call was quicker than that here
            continue
        seen.append(got)
    for wall, cpu in seen:
        assert cpu < CPU_BOUND, (phase, "CPU seconds from the signal to the catch", seen)
        assert wall < WALL_BOUND, (phase, "wall seconds from the signal to the catch", seen)


def main(trials):
    print(f"load average {os.getloadavg()[0]:.1f}; {trials} signals a phase at random moments")
    for phase, (call, longest) in PHASES.items():
        seen, limit = [], longest
        while len(seen) < trials:
            got = interrupt_once(call, random.uniform(0.0, limit))
            if got is None:
                limit *= 0.8
            else:
                seen.append(got)
        wall = sorted(w for w, _ in seen)
        cpu = sorted(c for _, c in seen)
        print(f"{phase:12s} wall median {wall[len(wall) // 2]:.3f} max {wall[-1]:.3f} s; "
              f"CPU median {cpu[len(cpu) // 2]:.3f} max {cpu[-1]:.3f} s")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
