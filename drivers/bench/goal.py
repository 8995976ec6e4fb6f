#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""goal.py -- the speed goal's benchmark in one command.

    python3 drivers/bench/goal.py BUILD_DIR [--ref TAPER] [--repeats R] [--n N]
                                  [--accuracy] [--big] [--keep DIR]

The goal: monodisperse N = 1e5 at default settings at least 2.5x faster than
commit bc35120 built against Debian's system SUNDIALS, pass times of the two
within 1e-8; N = 1e6 in under 60 s; and what each part contributes.

1. The reference: bc35120's driver against the system SUNDIALS, built once
   into BUILD_DIR/goal-bc35120 from this repository (`git archive bc35120`,
   `meson setup`, only its driver compiled; ~1 min), unless --ref names a
   binary.  `ldd` must show the system's libsundials_cvode.
2. Three configurations, each on the scene `&chain profile='monodisperse',
   n_granules=N /` (every other setting the default), run in turn R times
   after one warm-up round, the order rotated every round so that none
   always runs first on a shared machine:
     ref      bc35120, system SUNDIALS                 (the goal's baseline)
     ref+opt  bc35120 with BUILD_DIR's bundled SUNDIALS (LD_LIBRARY_PATH):
              what the optimised build alone contributes (same steps)
     now-sys  this tree's driver with the system SUNDIALS (LD_LIBRARY_PATH
              to the directory of ref's libsundials_cvode, which precedes
              libtaper's RUNPATH): fewer steps alone, against ref
     now      BUILD_DIR/drivers/taper/taper (this tree, bundled SUNDIALS)
   CPU time is user + system of the process (os.wait4), so the other
   processes of a shared machine count less than in wall time.
3. The report: per configuration the median, min and max CPU seconds and
   the steps (per granule); per round the ratio ref/now and its factors
   ref/ref+opt (optimised build) and ref+opt/now (fewer steps and the rest),
   medians with min-max; the largest relative t_pass difference between
   now and ref over all granules.  --accuracy adds a run of this tree at
   rtol 1e-13, atol 1e-16 (the truth to ~1e-9; ~25 s at N = 1e5) and each
   run's own t_pass error against it, which is what decides whether
   "within 1e-8 of each other" can hold.  --big adds one run of this tree at
   N = 1e6 (CPU and wall seconds, peak memory).

Exit status 0 (the numbers are the output; it judges nothing), 2 on a setup
failure.  Standard library only; docs/benchmarks.md quotes its output.
"""
import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(SOURCE, "drivers", "tools"))
import compare_runs  # noqa: E402  (drivers/tools/compare_runs.py)

REF_COMMIT = "bc35120"


def die(msg):
    sys.stderr.write(f"goal: {msg}\n")
    sys.exit(2)


def build_reference(build):
    """bc35120's driver against the system SUNDIALS, built once."""
    cache = os.path.join(build, "goal-" + REF_COMMIT)
    binary = os.path.join(cache, "build", "drivers", "taper")
    if os.access(binary, os.X_OK):
        return binary
    src = os.path.join(cache, "src")
    shutil.rmtree(cache, ignore_errors=True)
    os.makedirs(src)
    print(f"goal: building {REF_COMMIT}'s driver against the system SUNDIALS in {cache}",
          file=sys.stderr)
    archive = subprocess.run(["git", "-C", SOURCE, "archive", REF_COMMIT],
                             stdout=subprocess.PIPE, check=False)
    if archive.returncode != 0:
        die(f"git archive {REF_COMMIT} failed (is {SOURCE} a clone with that commit?)")
    subprocess.run(["tar", "-x", "-C", src], input=archive.stdout, check=True)
    log = open(os.path.join(cache, "build.log"), "w")
    env = dict(os.environ)
    env.pop("CMAKE_PREFIX_PATH", None)
    for cmd in (["meson", "setup", os.path.join(cache, "build"), src, "-Dtests=false",
                 "-Dfortran=disabled"],
                ["meson", "compile", "-C", os.path.join(cache, "build"), "drivers/taper"]):
        if subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, env=env).returncode != 0:
            die(f"{' '.join(cmd)} failed: see {log.name}")
    return binary


def sundials_of(binary, env=None):
    """Where the binary's libsundials_cvode comes from (ldd)."""
    out = subprocess.run(["ldd", binary], stdout=subprocess.PIPE, text=True, env=env).stdout
    for line in out.splitlines():
        if "libsundials_cvode" in line and "=>" in line:
            return line.split("=>")[1].split()[0]
    return "?"


def run(binary, scene, outdir, env):
    """(CPU seconds user + sys, wall seconds, peak RSS MB) of one run."""
    shutil.rmtree(outdir, ignore_errors=True)
    t0 = time.monotonic()
    p = subprocess.Popen([binary, scene, "-o", outdir], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, env=env)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - t0
    err = p.stderr.read().decode(errors="replace")
    p.stderr.close()
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        die(f"{binary} {scene} exited {p.returncode}: {err.strip()}")
    return usage.ru_utime + usage.ru_stime, wall, usage.ru_maxrss / 1024.0


def write_scene(path, n, extra=""):
    with open(path, "w") as f:
        f.write(f"&chain profile = 'monodisperse', n_granules = {n} /\n")
        if extra:
            f.write(extra + "\n")
        f.write("&output progress = .false. /\n")


def t_pass_error(run_dir, ref_dir):
    _, _, a = compare_runs.read_run(run_dir)
    _, _, b = compare_runs.read_run(ref_dir)
    worst, at, _ = compare_runs.compare(a, b, "t_pass")
    return worst, at


def steps_of(run_dir):
    _, stats, _ = compare_runs.read_run(run_dir)
    return int(float(stats.get("steps", "nan")))


def spread(values):
    return f"{statistics.median(values):.3f} ({min(values):.3f}-{max(values):.3f})"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build", help="the build directory of this tree (sh share/setup.sh)")
    ap.add_argument("--ref", help=f"{REF_COMMIT}'s taper binary (default: build it)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--n", type=int, default=100000)
    ap.add_argument("--accuracy", action="store_true")
    ap.add_argument("--big", action="store_true")
    ap.add_argument("--keep", help="keep the runs' output directories here")
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    now_bin = os.path.join(build, "drivers", "taper", "taper")
    if not os.access(now_bin, os.X_OK):
        die(f"{now_bin}: not built (sh share/setup.sh)")
    ref_bin = os.path.abspath(a.ref) if a.ref else build_reference(build)
    bundled = os.path.join(build, "sundials", "lib")
    if not os.path.isdir(bundled):   # configured with -Dsundials_prefix=...
        out = subprocess.run(["meson", "introspect", "--buildoptions", build],
                             stdout=subprocess.PIPE, text=True).stdout
        import json
        prefix = next((o["value"] for o in json.loads(out or "[]")
                       if o["name"] == "sundials_prefix"), "")
        if prefix:
            bundled = os.path.join(prefix, "lib")

    base_env = {k: v for k, v in os.environ.items() if k != "LD_LIBRARY_PATH"}
    configs = [("ref", ref_bin, base_env)]
    if os.path.exists(os.path.join(bundled, "libsundials_cvode.so")):
        configs.append(("ref+opt", ref_bin, dict(base_env, LD_LIBRARY_PATH=bundled)))
    system_lib = os.path.dirname(sundials_of(ref_bin, base_env))
    if os.path.isdir(system_lib) and configs[-1][0] == "ref+opt":
        configs.append(("now-sys", now_bin, dict(base_env, LD_LIBRARY_PATH=system_lib)))
    configs.append(("now", now_bin, base_env))

    work = a.keep or tempfile.mkdtemp(prefix="taper-goal-")
    os.makedirs(work, exist_ok=True)
    scene = os.path.join(work, "mono.nml")
    write_scene(scene, a.n)
    print(f"# goal benchmark: monodisperse N = {a.n}, defaults; {a.repeats} rounds after a warm-up")
    for name, binary, env in configs:
        print(f"#   {name:8s} {binary}  (libsundials_cvode: {sundials_of(binary, env)})")

    cpu = {name: [] for name, _, _ in configs}
    wall = {name: [] for name, _, _ in configs}
    for r in range(a.repeats + 1):
        order = configs[r % len(configs):] + configs[:r % len(configs)]
        for name, binary, env in order:
            c, w, _ = run(binary, scene, os.path.join(work, name), env)
            if r > 0:
                cpu[name].append(c)
                wall[name].append(w)
    steps = {name: steps_of(os.path.join(work, name)) for name, _, _ in configs}

    print(f"\n| run | CPU s median (min-max) | wall s median | steps | steps/granule |")
    print("|---|---|---|---|---|")
    for name, _, _ in configs:
        print(f"| {name} | {spread(cpu[name])} | {statistics.median(wall[name]):.2f} | "
              f"{steps[name]} | {steps[name] / a.n:.1f} |")
    print("\nper round (CPU), median (min-max):")
    ratio = [x / y for x, y in zip(cpu["ref"], cpu["now"])]
    print(f"  ref / now       = {spread(ratio)}   <- the goal asks >= 2.5")
    if "ref+opt" in cpu:
        opt = [x / y for x, y in zip(cpu["ref"], cpu["ref+opt"])]
        rest = [x / y for x, y in zip(cpu["ref+opt"], cpu["now"])]
        print(f"  ref / ref+opt   = {spread(opt)}   (the optimised SUNDIALS build alone)")
        print(f"  ref+opt / now   = {spread(rest)}   (fewer steps and this tree's other changes)")
    if "now-sys" in cpu:
        steps_only = [x / y for x, y in zip(cpu["ref"], cpu["now-sys"])]
        build_only = [x / y for x, y in zip(cpu["now-sys"], cpu["now"])]
        print(f"  ref / now-sys   = {spread(steps_only)}   (this tree's changes on Debian's SUNDIALS)")
        print(f"  now-sys / now   = {spread(build_only)}   (the bundled build under this tree)")

    diff, at = t_pass_error(os.path.join(work, "now"), os.path.join(work, "ref"))
    print(f"\nt_pass, now vs ref: largest relative difference {diff:.2e} (granule {at})")
    if "ref+opt" in cpu:
        same, _ = t_pass_error(os.path.join(work, "ref+opt"), os.path.join(work, "ref"))
        print(f"t_pass, ref+opt vs ref: {same:.2e} (the same code on another build of 6.4.1)")
    if "now-sys" in cpu:
        same, _ = t_pass_error(os.path.join(work, "now-sys"), os.path.join(work, "now"))
        print(f"t_pass, now-sys vs now: {same:.2e} (Debian's 6.4.1 against the bundled one, which "
              "has the root-finding fix)")
    if a.accuracy:
        truth = os.path.join(work, "truth")
        tscene = os.path.join(work, "truth.nml")
        write_scene(tscene, a.n, "&solver rtol = 1e-13, atol = 1e-16 /")
        c, _, _ = run(now_bin, tscene, truth, base_env)
        print(f"reference run: this tree at rtol 1e-13, atol 1e-16 ({c:.1f} s CPU)")
        for name in ("ref", "now"):
            e, k = t_pass_error(os.path.join(work, name), truth)
            print(f"  t_pass error of {name:4s} against it: {e:.2e} (granule {k})")
    if a.big:
        big = os.path.join(work, "big.nml")
        write_scene(big, 1000000)
        c, w, mb = run(now_bin, big, os.path.join(work, "big"), base_env)
        print(f"\nN = 1e6, now: {c:.1f} s CPU, {w:.1f} s wall, {mb:.0f} MB peak "
              f"({steps_of(os.path.join(work, 'big'))} steps)   <- the goal asks < 60 s")
    if not a.keep:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
