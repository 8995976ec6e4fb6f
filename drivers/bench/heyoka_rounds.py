#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""heyoka_rounds.py -- taper against heyoka, paired, in interleaved rounds.

    python3 drivers/bench/heyoka_rounds.py BUILD_DIR PYTHON CHAIN N REF
            [--rounds R] [--taper-tols T,T,...] [--rk8-tols T,T,...]
            [--heyoka-tols T,T,...] [--json FILE]

Each round runs, in an order shuffled anew every round (so that on a shared
machine neither side always runs first),

    BUILD_DIR/drivers/bench/taper-bench --heyoka-python PYTHON \\
        --single CHAIN METHOD TOL N REF

for taper's default settings, CVODE Adams (`adams`) at each of --taper-tols,
taper's method rk8 at each of --rk8-tols (default none) and heyoka
(peers/peer_heyoka.py) at each of --heyoka-tols (--taper-tols and
--heyoka-tols default to 1e-5, 1e-6, ..., 1e-13).  REF is taper-reference's output for the chain
(tests/unit/reference/ has the study's chains); the error is the largest
relative pass-time error over granules 1..N-2.  Times are CPU seconds:
taper's run, and heyoka's integration alone (its compilation is printed
apart).  Then, for each error level 1e-6, 1e-8, 1e-9, 1e-10, 1e-12 and
each round: the fastest complete run of either side at or below it, and
the ratio heyoka / taper; the summary gives the median ratio and its range
over the rounds, with the runs that set them: first against taper's
fastest run of any method, then (where rk8 ran) against CVODE's alone (the
default and `adams`, the default method) and rk8's alone.
"""
import argparse
import json
import random
import re
import statistics
import subprocess
import sys

LEVELS = [1e-6, 1e-8, 1e-9, 1e-10, 1e-12]
TOLS = ",".join(f"1e-{k}" for k in range(5, 14))


def run_one(bench, python, chain, method, tol, n, ref):
    cmd = [bench, "--heyoka-python", python, "--single", chain, method, tol, str(n), ref]
    p = subprocess.run(cmd, capture_output=True, text=True)
    line = p.stdout.strip()
    m = re.search(r" cpu (\S+) s.* steps (\S+).* err_t (\S+)", line)
    if p.returncode != 0 or not m:
        return {"method": method, "tol": tol, "ok": False, "line": line + p.stderr.strip()}
    c = re.search(r" compile (\S+) s", line)
    return {"method": method, "tol": tol, "ok": "incomplete" not in line, "cpu": float(m.group(1)),
            "steps": int(m.group(2)), "err": float(m.group(3)), "compile": float(c.group(1)) if c else None}


def summary(results, label="taper", pick=lambda r: r["method"] != "heyoka"):
    """Per error level and round: the fastest complete run picked by `pick`
    and heyoka's, their ratio; printed as median and range over the rounds."""
    rounds = sorted({r["round"] for r in results})
    print(f"heyoka against {label}:")
    for level in LEVELS:
        ratios, taper_cpu, heyoka_cpu, taper_runs, heyoka_runs = [], [], [], set(), set()
        for rd in rounds:
            ok = [r for r in results if r["round"] == rd and r["ok"] and r["err"] <= level]
            t = [r for r in ok if r["method"] != "heyoka" and pick(r)]
            h = [r for r in ok if r["method"] == "heyoka"]
            if not t or not h:
                continue
            a, b = min(t, key=lambda r: r["cpu"]), min(h, key=lambda r: r["cpu"])
            ratios.append(b["cpu"] / a["cpu"])
            taper_cpu.append(a["cpu"])
            heyoka_cpu.append(b["cpu"])
            taper_runs.add(f"{a['method']} {a['tol']} (err {a['err']:.1e})")
            heyoka_runs.add(f"tol {b['tol']} (err {b['err']:.1e})")
        if not ratios:
            best = lambda keep: min((r["err"] for r in results if r["ok"] and keep(r)), default=float("nan"))
            print(f"{level:.0e}: not reached by both (best error: {label} "
                  f"{best(lambda r: r['method'] != 'heyoka' and pick(r)):.1e},"
                  f" heyoka {best(lambda r: r['method'] == 'heyoka'):.1e})")
            continue
        print(f"{level:.0e}: heyoka/{label} {statistics.median(ratios):.1f}x (rounds: {min(ratios):.1f}-{max(ratios):.1f}, "
              f"{len(ratios)} rounds); {label} {statistics.median(taper_cpu):.4f} s [{'; '.join(sorted(taper_runs))}], "
              f"heyoka {statistics.median(heyoka_cpu):.3f} s [{'; '.join(sorted(heyoka_runs))}]")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir")
    ap.add_argument("python")
    ap.add_argument("chain")
    ap.add_argument("n", type=int)
    ap.add_argument("ref")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--taper-tols", default=TOLS)
    ap.add_argument("--rk8-tols", default="")
    ap.add_argument("--heyoka-tols", default=TOLS)
    ap.add_argument("--json")
    a = ap.parse_args()
    bench = a.build_dir + "/drivers/bench/taper-bench"
    runs = [("default", "0")] + [("adams", t) for t in a.taper_tols.split(",") if t] + \
           [("rk8", t) for t in a.rk8_tols.split(",") if t] + \
           [("heyoka", t) for t in a.heyoka_tols.split(",") if t]
    shuffle = random.Random(1)
    results = []
    for rd in range(a.rounds):
        order = runs[:]
        shuffle.shuffle(order)
        for method, tol in order:
            r = run_one(bench, a.python, a.chain, method, tol, a.n, a.ref)
            r["round"] = rd
            results.append(r)
            print(json.dumps(r), flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(results, f)
    summary(results)
    if any(r["method"] == "rk8" for r in results):
        summary(results, "cvode", lambda r: r["method"] in ("default", "adams"))
        summary(results, "rk8", lambda r: r["method"] == "rk8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
