#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""python_overheads.py [--repeat R] -- what the Python package costs beside
the library's own work (docs/python.md, "Overheads"), printed against the
targets of the package:

  import taper                  CPU seconds of the import in a fresh
                                interpreter (time.process_time around it),
                                R interpreters; numpy's own import beside it
  taper.theory(n_granules=2)    CPU per call: the scene built and checked,
                                the chain, the theory, the arrays, the Result
  taper.simulate(n_granules=10) CPU per call, the integration included; and
                                theory(n_granules=10), the same call without
                                the run, to show which part is the
                                library's; and the same with method rk8

Each per-call figure is the CPU time of a batch of calls divided by its
size, R batches: the smallest (what the code costs) and the median (what a
shared machine gave).  Run it with the Python the package is installed in:

    build/python-venv/bin/python drivers/bench/python_overheads.py

(the venv of the Python tests, made by `meson test -C build python_package`).
Not a test: the machine is shared and the figures move with its load; the
smallest of several batches is the repeatable one."""

import argparse
import statistics
import subprocess
import sys
import time

TARGETS = {"import": 0.1, "theory2": 20e-6, "simulate10": 0.3e-3}


def import_cpu(module, repeat):
    """CPU seconds of `import module` in `repeat` fresh interpreters."""
    code = ("import time; t = time.process_time(); import {m}; "
            "print(time.process_time() - t)").format(m=module)
    out = []
    for _ in range(repeat):
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                              check=True)
        out.append(float(proc.stdout))
    return out


def per_call(fn, repeat, budget=0.2):
    """CPU seconds per call of fn(), in `repeat` batches of about `budget`
    seconds each."""
    fn()
    n, t0 = 0, time.process_time()
    while time.process_time() - t0 < 0.05:
        fn()
        n += 1
    batch = max(1, int(n * budget / 0.05))
    out = []
    for _ in range(repeat):
        t0 = time.process_time()
        for _ in range(batch):
            fn()
        out.append((time.process_time() - t0) / batch)
    return out


def line(label, values, target, scale, unit):
    best, median = min(values), statistics.median(values)
    verdict = "within" if best <= target else "ABOVE"
    print(f"{label:34s} {best * scale:9.3g} {unit} (median {median * scale:.3g}, "
          f"range {best * scale:.3g}-{max(values) * scale:.3g})  target {target * scale:g} {unit}: "
          f"{verdict}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    print(f"python {sys.version.split()[0]}; {args.repeat} interpreters or batches each")
    line("import taper (CPU)", import_cpu("taper", args.repeat), TARGETS["import"], 1e3, "ms")
    numpy_import = import_cpu("numpy", args.repeat)
    print(f"{'  numpy alone, for comparison':34s} {min(numpy_import) * 1e3:9.3g} ms "
          f"(median {statistics.median(numpy_import) * 1e3:.3g}, range "
          f"{min(numpy_import) * 1e3:.3g}-{max(numpy_import) * 1e3:.3g}): not imported by "
          f"import taper")

    import taper
    line("taper.theory(n_granules=2)", per_call(lambda: taper.theory(n_granules=2), args.repeat),
         TARGETS["theory2"], 1e6, "us")
    sim = per_call(lambda: taper.simulate(n_granules=10), args.repeat)
    line("taper.simulate(n_granules=10)", sim, TARGETS["simulate10"], 1e6, "us")
    th10 = per_call(lambda: taper.theory(n_granules=10), args.repeat)
    steps = taper.simulate(n_granules=10).stats["steps"]
    print(f"{'  of which the call around the run':34s} {min(th10) * 1e6:9.3g} us "
          f"(theory(n_granules=10): scene, chain, theory, arrays, Result)")
    print(f"{'  and the run (the library)':34s} {(min(sim) - min(th10)) * 1e6:9.3g} us "
          f"(the difference: taper_sim_alloc, {steps} CVODE steps of method adams at rtol "
          f"1e-10, the run's columns and statistics)")
    rk8 = per_call(lambda: taper.simulate(n_granules=10, method="rk8"), args.repeat)
    rk8_steps = taper.simulate(n_granules=10, method="rk8").stats["steps"]
    line('  simulate(..., method="rk8")', rk8, TARGETS["simulate10"], 1e6, "us")
    print(f"{'':34s} ({rk8_steps} steps of rk8 at rtol 1e-10: docs/choosing.md)")


if __name__ == "__main__":
    main()
