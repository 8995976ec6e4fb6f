#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""compare_runs.py -- how far one taper run is from a reference run.

    python3 drivers/tools/compare_runs.py RUN REFERENCE [--at K1,K2,...] [--bins]

RUN and REFERENCE are output directories of `taper` (or their granules.tsv
files) of the same chain, typically at two tolerances.  Prints, for each
observable, the largest relative difference over the granules where both
have a value, where it occurs, and how many granules have a value in one run
only; then the relative differences at the granules given with --at; then the
solver statistics of both headers side by side.  With --bins, also the
largest relative errors of t_pass and of T_res = t_pass(k) - t_pass(k-1)
(computed from t_pass, so values the run wrote as nan count too) in decades
of T_res / t_pass.  This is how the accuracy tables of docs/benchmarks.md
("Long chains at looser tolerances") were made.

Exit status: 0, or 2 for unreadable input or runs of different chains.
Standard library only.
"""
import math
import os
import sys

OBSERVABLES = ("t_pass", "T_res", "v_peak", "t_peak", "X_pass")
STATS = ("steps", "restarts", "max_window", "energy_error", "momentum_error", "t_final")


def read_run(path):
    """Header statistics and columns of a granules.tsv (or of DIR/granules.tsv)."""
    if os.path.isdir(path):
        path = os.path.join(path, "granules.tsv")
    stats, header, rows = {}, None, []
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if line.startswith("#"):
                key, sep, value = line[1:].partition(" = ")
                if sep and key.strip() in STATS:
                    stats[key.strip()] = value.strip()
            elif header is None:
                header = line.split("\t")
            elif line:
                rows.append(line.split("\t"))
    if header is None or "k" not in header:
        raise ValueError(f"{path}: no column header with k: not a taper granules.tsv")
    columns = {name: [float(r[i]) for r in rows] for i, name in enumerate(header)}
    return path, stats, columns


def relative(a, b):
    return abs(a - b) / abs(b) if b != 0.0 else abs(a - b)


def compare(run, ref, name):
    """(largest relative difference, its granule, values in one run only)."""
    worst, at, one_sided = 0.0, None, 0
    for k, a, b in zip(run["k"], run[name], ref[name]):
        k = int(k)  # the granule of the row (&output every may thin them)
        if math.isnan(a) or math.isnan(b):
            one_sided += math.isnan(a) != math.isnan(b)
            continue
        d = relative(a, b)
        if d > worst or at is None:
            worst, at = d, k
    return worst, at, one_sided


def residence_bins(run, ref):
    """{decade of T/t: [count, max t_pass error, max T_res error, first k, last k]}.

    Reads the T_res column (t_pass(k) - t_pass(k-1) as the library computes
    it) and each row's own k, so that files thinned with &output every give
    the right bins for the rows they keep."""
    bins = {}
    for k, a, b, ta, tb in zip(run["k"], run["t_pass"], ref["t_pass"], run["T_res"], ref["T_res"]):
        k = int(k)
        if not all(math.isfinite(x) for x in (a, b, ta, tb)) or tb == 0.0 or b == 0.0:
            continue
        decade = math.floor(math.log10(abs(tb) / abs(b)))
        entry = bins.setdefault(decade, [0, 0.0, 0.0, k, k])
        entry[0] += 1
        entry[1] = max(entry[1], relative(a, b))
        entry[2] = max(entry[2], relative(ta, tb))
        entry[4] = k
    return bins


def main(argv):
    args, at, want_bins = [], [], False
    i = 1
    while i < len(argv):
        if argv[i] == "--at" and i + 1 < len(argv):
            at = [int(x) for x in argv[i + 1].split(",") if x]
            i += 2
        elif argv[i] == "--bins":
            want_bins = True
            i += 1
        elif argv[i] in ("-h", "--help"):
            print(__doc__.strip())
            return 0
        else:
            args.append(argv[i])
            i += 1
    if len(args) != 2:
        print("usage: compare_runs.py RUN REFERENCE [--at K1,K2,...] [--bins]", file=sys.stderr)
        return 2
    try:
        run_path, run_stats, run = read_run(args[0])
        ref_path, ref_stats, ref = read_run(args[1])
    except (OSError, ValueError) as e:
        print(f"compare_runs: {e}", file=sys.stderr)
        return 2
    if run["k"] != ref["k"] or run.get("R") != ref.get("R"):
        print(f"compare_runs: {run_path} and {ref_path} are not the same chain "
              "(granule count or radii differ)", file=sys.stderr)
        return 2
    print(f"# {run_path} against {ref_path}, {len(run['k'])} granules")
    print("observable\tmax_rel_diff\tat_k\tvalue_in_one_run_only")
    for name in OBSERVABLES:
        if name in run and name in ref:
            worst, k, one_sided = compare(run, ref, name)
            print(f"{name}\t{worst:.3e}\t{k if k is not None else 'nan'}\t{one_sided}")
    rows = {int(k): i for i, k in enumerate(run["k"])}
    for k in at:
        if k not in rows:
            print(f"compare_runs: --at {k} is not a granule of these files", file=sys.stderr)
            return 2
        cells = [f"{name} {relative(run[name][rows[k]], ref[name][rows[k]]):.3e}"
                 for name in ("t_pass", "v_peak") if name in run]
        print(f"k = {k}: " + ", ".join(cells))
    if want_bins and not all(name in run and name in ref for name in ("t_pass", "T_res")):
        print("compare_runs: --bins needs the t_pass and T_res columns in both files "
              "(&output columns left them out)", file=sys.stderr)
        return 2
    if want_bins:
        print("log10(T_res/t_pass)\tgranules\tmax_rel_diff_t_pass\tmax_rel_diff_T_res\tk_range")
        for decade, (count, err_t, err_T, first, last) in sorted(residence_bins(run, ref).items(),
                                                                  reverse=True):
            print(f"{decade}\t{count}\t{err_t:.2e}\t{err_T:.2e}\t{first}-{last}")
    print("statistic\trun\treference")
    for key in STATS:
        print(f"{key}\t{run_stats.get(key, '-')}\t{ref_stats.get(key, '-')}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
