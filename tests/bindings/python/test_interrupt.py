# SPDX-License-Identifier: GPL-3.0-or-later
"""Ctrl-C: SIGINT to a process in the middle of a long run raises
KeyboardInterrupt promptly, returns nothing half-built, and the package works
afterwards."""

import os
import signal
import subprocess
import sys
import textwrap
import time

SCRIPT = textwrap.dedent("""
    import sys, taper
    r = None
    print("started", flush=True)
    try:
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
