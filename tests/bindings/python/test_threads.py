# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs release the GIL: chains in threads give the same results as one at a
time, and Python keeps running while a chain integrates."""

import threading
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

import taper

CHAINS = [
    dict(profile="monodisperse", n_granules=300),
    dict(profile="backward_linear", s=0.4, n_granules=300),
    dict(profile="forward_exponential", q=0.02, n_granules=150),
    dict(profile="backward_exponential", q=0.03, n_granules=200, method="bdf"),
]


@pytest.mark.slow
def test_threads_give_identical_results():
    alone = [taper.simulate(**kw) for kw in CHAINS]
    with ThreadPoolExecutor(max_workers=4) as pool:
        together = list(pool.map(lambda kw: taper.simulate(**kw), CHAINS * 2))
    for i, r in enumerate(together):
        ref = alone[i % len(CHAINS)]
        assert r.equals(ref), CHAINS[i % len(CHAINS)]
        assert r.stats.keys() == ref.stats.keys()
        for name, value in r.stats.items():   # NaN (no wall) equals NaN here
            assert value == ref.stats[name] or (value != value and ref.stats[name] != ref.stats[name]), name


def test_the_gil_is_released_during_a_run():
    done = threading.Event()
    ticks = 0

    def run():
        taper.simulate(profile="monodisperse", n_granules=10000)
        done.set()

    t = threading.Thread(target=run)
    start = time.monotonic()
    t.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    elapsed = time.monotonic() - start
    # A run holding the GIL would leave this loop a turn or two at most; with
    # the GIL released it turns about once a millisecond.
    assert elapsed > 0.1, "the run is too short to tell"
    assert ticks > 20, (ticks, elapsed)
