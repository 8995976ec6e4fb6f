#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""test_compare_runs.py BUILD_DIR SOURCE_DIR -- drivers/tools/compare_runs.py,
the tool behind docs/benchmarks.md's accuracy tables: a run against a run of
the same chain at a tighter tolerance differs by about the looser tolerance
and never by zero, a run against itself by exactly zero, and runs of
different chains are refused with exit status 2."""

import os
import subprocess
import sys
import tempfile

build, source = sys.argv[1], sys.argv[2]
driver = os.path.join(build, "drivers", "taper", "taper")
tool = os.path.join(source, "drivers", "tools", "compare_runs.py")
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def scene(directory, name, n, rtol, every=1):
    path = os.path.join(directory, name + ".nml")
    with open(path, "w") as f:
        f.write(f"&chain profile = 'monodisperse', n_granules = {n} /\n"
                f"&solver rtol = {rtol}, atol = {rtol * 1e-3} /\n"
                f"&output progress = .false., every = {every} /\n")
    out = os.path.join(directory, name)
    subprocess.run([driver, path, "-o", out], check=True, capture_output=True)
    return out


def compare(*args):
    p = subprocess.run([sys.executable, tool, *args], capture_output=True, text=True)
    table = {}
    for line in p.stdout.splitlines():
        cells = line.split("\t")
        if len(cells) == 4 and cells[0] in ("t_pass", "v_peak"):
            table[cells[0]] = float(cells[1])
    return p.returncode, table, p.stdout + p.stderr


with tempfile.TemporaryDirectory() as d:
    loose = scene(d, "loose", 60, 1e-6)
    tight = scene(d, "tight", 60, 1e-11)
    other = scene(d, "other", 61, 1e-11)
    status, table, text = compare(loose, tight, "--at", "30")
    check(status == 0, f"loose vs tight: exit {status}: {text}")
    check(0.0 < table.get("t_pass", 0.0) < 1e-4, f"t_pass difference {table.get('t_pass')}")
    check(0.0 < table.get("v_peak", 0.0) < 1e-3, f"v_peak difference {table.get('v_peak')}")
    check("k = 30: t_pass" in text, "no line for --at 30")
    status, table, text = compare(loose, tight, "--bins")
    rows = [line.split("\t") for line in text.splitlines()]
    decades = [r for r in rows if len(r) == 5 and r[0].lstrip("-").isdigit()]
    check(status == 0 and decades, f"--bins printed no decades: {text}")
    check(sum(int(r[1]) for r in decades) == 59, "--bins does not count granules 1..59")
    check(all(0.0 < float(r[3]) < 1e-3 for r in decades), f"--bins T_res errors: {decades}")
    # Files thinned with &output every: the bins are those of the rows kept,
    # each binned by its own T_res (not by the difference of kept t_pass rows,
    # which spans `every` granules).
    thin_loose = scene(d, "thin_loose", 60, 1e-6, every=5)
    thin_tight = scene(d, "thin_tight", 60, 1e-11, every=5)
    status, table, thin_text = compare(thin_loose, thin_tight, "--bins")
    thin = [line.split("\t") for line in thin_text.splitlines()]
    full_range = {r[0]: tuple(map(int, r[4].split("-"))) for r in decades}
    thin_range = {r[0]: tuple(map(int, r[4].split("-")))
                  for r in thin if len(r) == 5 and r[0].lstrip("-").isdigit()}
    check(status == 0 and thin_range and all(
              dec in full_range and full_range[dec][0] <= lo and hi <= full_range[dec][1]
              for dec, (lo, hi) in thin_range.items()),
          f"--bins on thinned files: granule ranges {thin_range} outside the full "
          f"files' {full_range}: {thin_text}")
    status, table, text = compare(tight, tight)
    check(status == 0 and table.get("t_pass") == 0.0, f"a run against itself: {text}")
    status, table, text = compare(loose, other)
    check(status == 2 and "not the same chain" in text, f"different chains: exit {status}: {text}")
    status, table, text = compare(loose, os.path.join(d, "missing"))
    check(status == 2, f"missing reference: exit {status}")

for f in failures:
    print("FAIL:", f)
print(f"compare_runs: {len(failures)} failures")
sys.exit(1 if failures else 0)
