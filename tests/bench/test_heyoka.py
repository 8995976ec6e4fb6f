#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""test_heyoka.py -- the heyoka peer of taper-bench against converged references.

    python3 test_heyoka.py TAPER_BENCH REFERENCE_DIR

Skips (exit 77) unless the Python named by TAPER_HEYOKA_PYTHON (default
python3) imports heyoka.  Otherwise runs peers/peer_heyoka.py through
`taper-bench --single` on two chains of the study and asserts, against
tests/unit/reference/ (taper-reference: long double, ~1e-16):

 * the pass times of granules 1..N-2 within 1e-9 at heyoka's tol 1e-11
   (measured: 7.7e-13 on forward exponential N = 100, 1.5e-11 on backward
   linear N = 400):
   the contact switches and their kicks (peers/peer_heyoka.py) integrate
   the Hertz force, not a stand-in for it;
 * every pass time found and the energy conserved to 1e-8;
 * the same chains through taper's default settings agree with heyoka's
   pass times within 1e-8 (both measured against the same reference).
"""
import os
import re
import subprocess
import sys

CASES = [  # chain, N, reference file
    ("forward_exponential", 100, "forward_exponential_100.txt"),
    ("backward_linear", 400, "backward_linear_400.txt"),
]


def single(bench, python, chain, method, tol, n, ref):
    cmd = [bench, "--heyoka-python", python, "--single", chain, method, str(tol), str(n), ref]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"FAIL: {' '.join(cmd)}: exit {p.returncode}\n{p.stdout}{p.stderr}")
    line = p.stdout.strip()
    get = lambda key: float(re.search(key + r" (\S+)", line).group(1))
    return line, get("err_t"), get("missing"), get("drift"), get(r"t_pass\(N-1\)")


def main():
    bench, ref_dir = sys.argv[1], sys.argv[2]
    python = os.environ.get("TAPER_HEYOKA_PYTHON", "python3")
    try:
        ok = subprocess.run([python, "-c", "import heyoka"], capture_output=True).returncode == 0
    except OSError:
        ok = False
    if not ok:
        print(f"SKIP: {python} cannot import heyoka (TAPER_HEYOKA_PYTHON names one that can)")
        return 77
    failures = 0
    for chain, n, ref_name in CASES:
        ref = os.path.join(ref_dir, ref_name)
        line, err, missing, drift, last = single(bench, python, chain, "heyoka", 1e-11, n, ref)
        print(line)
        if not (err <= 1e-9 and missing == 0 and drift <= 1e-8 and "incomplete" not in line):
            print(f"FAIL: {chain} N={n}: heyoka err_t {err:.2e} (bound 1e-9), missing {missing:.0f}, "
                  f"energy drift {drift:.1e} (bound 1e-8)")
            failures += 1
        line_t, err_t, _, _, last_t = single(bench, python, chain, "default", 0, n, ref)
        print(line_t)
        if not abs(last - last_t) <= 1e-8 * abs(last_t):
            print(f"FAIL: {chain} N={n}: t_pass(N-1) heyoka {last!r}, taper {last_t!r}")
            failures += 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
