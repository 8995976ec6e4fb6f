#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""si_units.py RESCALED_DIR SI_DIR -- the SI files of a scene (&output units =
'si') are its rescaled files times the unit scales, exactly.

For each of granules.tsv, sensors.tsv, walls.tsv present in both directories:
the column names agree once the SI header's units ("t_pass[s]") are taken
off, every SI column's unit is the one of its dimension, and every value of
the SI file equals the rescaled value times the SI value of one rescaled unit
(granules.tsv's "# unit_DIM = VALUE UNIT" lines) to printing precision
(%.17g: a relative difference of at most 4 ulp), nan where the other is nan.
The statistics of the header lines with a unit are checked the same way,
but pulse_speed, a difference of X_pass over one of t_pass (so not a
rescaled speed times one scale): each file's is checked against its own
columns.
Sizes are in units of R_1, displacements in unit_length (eq. (5)): R and X0
scale with unit_radius (&material radius), X_pass = X0 + x_k becomes
X0 unit_radius + x_k unit_length (to 1e-12: x_k = X_pass - X0 is a
difference).
Standard library only.  Exit 0, or 1 naming the first differences.
"""
import math
import os
import re
import sys

UNITS = {"m": "length", "s": "time", "m/s": "velocity", "kg": "mass", "N": "force",
         "J": "energy", "N s": "impulse"}


def read(path):
    with open(path) as f:
        lines = f.read().splitlines()
    names = lines[0].split("\t")
    comments = [l for l in lines[1:] if l.startswith("#")]
    rows = [[float(x) for x in l.split("\t")] for l in lines[1:] if l and not l.startswith("#")]
    return names, comments, rows


def scales(comments):
    out = {}
    for l in comments:
        m = re.match(r"# unit_(\w+) = (\S+) (m|s|m/s|kg|N|J|N s)$", l)
        if m:
            out[m.group(1)] = (float(m.group(2)), m.group(3))
        m = re.match(r"# unit_radius = (\S+) m: ", l)
        if m:
            out["radius"] = (float(m.group(1)), "m")
    return out


def pulse_speed(names, rows):
    """The pulse's speed over the last tenth of the granules passed, as
    drivers/scenes/results/pulse.h defines it, from a granules.tsv's rows."""
    k, x, t = names.index("k"), names.index("X_pass"), names.index("t_pass")
    known = [r for r in rows if math.isfinite(r[x]) and math.isfinite(r[t])]
    if len(known) < 2:
        return math.nan
    reached = int(known[-1][k])
    first = next(r for r in known if r[k] >= reached - max(1, reached // 10))
    dt = known[-1][t] - first[t]
    return (known[-1][x] - first[x]) / dt if dt else math.nan


def close(a, b, rtol=4 * 2.0**-52):
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return a == b or abs(a - b) <= rtol * max(abs(a), abs(b))


def main():
    rdir, sdir = sys.argv[1], sys.argv[2]
    unit = scales(read(os.path.join(sdir, "granules.tsv"))[1])
    if set(unit) != set(UNITS.values()) | {"radius"}:
        print(f"{sdir}/granules.tsv: unit lines {sorted(unit)}")
        return 1
    bad = 0
    checked = 0
    for name in ("granules.tsv", "sensors.tsv", "walls.tsv"):
        rp, sp = os.path.join(rdir, name), os.path.join(sdir, name)
        if not os.path.exists(sp):
            continue
        rn, rc, rr = read(rp)
        sn, sc, sr = read(sp)
        factors = []
        for a, b in zip(rn, sn):
            m = re.match(r"(.+)\[(.+)\]$", b)
            base, u = (m.group(1), m.group(2)) if m else (b, None)
            if base != a:
                print(f"{name}: column {b} against {a}")
                return 1
            if u is not None and u not in UNITS:
                print(f"{name}: unknown unit in {b}")
                return 1
            size = name == "granules.tsv" and base in ("R", "X0")
            factors.append(unit["radius"][0] if size else unit[UNITS[u]][0] if u else 1.0)
            if u and unit[UNITS[u]][1] != u:
                print(f"{name}: {b}: unit_{UNITS[u]} is in {unit[UNITS[u]][1]}")
                return 1
        if len(rn) != len(sn) or len(rr) != len(sr) or not rr:
            print(f"{name}: {len(rn)}x{len(rr)} rescaled against {len(sn)}x{len(sr)} SI")
            return 1
        x0 = rn.index("X0") if name == "granules.tsv" and "X0" in rn else None
        for i, (ra, sa) in enumerate(zip(rr, sr)):
            for c, (x, y) in enumerate(zip(ra, sa)):
                checked += 1
                if rn[c] == "X_pass" and x0 is not None:
                    want = ra[x0] * unit["radius"][0] + (x - ra[x0]) * unit["length"][0]
                    ok = close(want, y, 1e-12)
                else:
                    want = x * factors[c]
                    ok = close(want, y)
                if not ok:
                    bad += 1
                    if bad <= 5:
                        print(f"{name} row {i + 1} {sn[c]}: rescaled {x!r} -> {want!r}, "
                              f"SI file {y!r}")
        # the header's statistics with units
        rstats = {l.split(" = ")[0][2:]: l.split(" = ")[1] for l in rc if " = " in l}
        for l in sc:
            m = re.match(r"# (\w+)\[(.+)\] = (\S+)$", l)
            if not m or m.group(1) not in rstats:
                continue
            if m.group(1) == "pulse_speed":
                checked += 2
                for file, names, rows, value in ((rp, rn, rr, rstats["pulse_speed"]),
                                                 (sp, sn, sr, m.group(3))):
                    want = pulse_speed([re.sub(r"\[.*\]$", "", c) for c in names], rows)
                    if not close(want, float(value), 1e-15):
                        bad += 1
                        print(f"{file}: pulse_speed {value}, its columns give {want!r}")
                continue
            checked += 1
            x = float(rstats[m.group(1)])
            if not close(x * unit[UNITS[m.group(2)]][0], float(m.group(3))):
                bad += 1
                print(f"{name}: {m.group(1)}: {x} rescaled, {m.group(3)} SI")
    if bad:
        print(f"{bad} of {checked} values differ")
        return 1
    print(f"si_units: {checked} values: SI = rescaled x unit")
    return 0


if __name__ == "__main__":
    sys.exit(main())
