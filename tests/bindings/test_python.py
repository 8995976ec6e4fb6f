#!/usr/bin/env python3
"""test_python.py BUILD_DIR SOURCE_DIR -- src/bindings/python/taper.py (ctypes)
against the C driver: the same chain run through Python and through
drivers/taper (scene file -> granules.tsv) gives the same numbers, bit for
bit (same library, same default solver), and library errors arrive as
taper.TaperError carrying the library's message."""

import math
import os
import subprocess
import sys
import tempfile

build, source = sys.argv[1], sys.argv[2]
os.environ["TAPER_LIBRARY"] = os.path.join(build, "src", "libtaper.so")
sys.path.insert(0, os.path.join(source, "src", "bindings", "python"))
import taper  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def same(a, b):
    return (math.isnan(a) and math.isnan(b)) or a == b


SCENE = """! test_python: a short backward linear chain
&chain
  profile = 'backward_linear'
  s = 0.2
  n_granules = 40
/
&output
  progress = .false.
/
"""


def driver_table(tmp):
    scene = os.path.join(tmp, "pytest.nml")
    with open(scene, "w") as f:
        f.write(SCENE)
    out = os.path.join(tmp, "out")
    proc = subprocess.run([os.path.join(build, "drivers", "taper", "taper"), scene, "-o", out],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        sys.exit("driver failed (%d): %s" % (proc.returncode, proc.stderr))
    rows = [line.rstrip("\n").split("\t")
            for line in open(os.path.join(out, "granules.tsv")) if not line.startswith("#")]
    header, rows = rows[0], rows[1:]
    return {name: [float(r[i]) for r in rows] for i, name in enumerate(header)}


with tempfile.TemporaryDirectory() as tmp:
    table = driver_table(tmp)

check(taper.version() == "0.1.0" or taper.version().count(".") == 2, "version")
chain = taper.Chain("backward_linear", n_granules=40, s=0.2)
check(len(chain) == 40 and chain.profile == "backward_linear", "chain")
sim = taper.Sim(chain)
check(sim.run() == 0, "run status")
th = taper.theory(chain)
columns = {"t_pass": sim.t_pass, "v_peak": sim.v_peak, "t_peak": sim.t_peak,
           "X_pass": sim.x_pass, "T_res": sim.t_res, "R": chain.radius, "m": chain.mass,
           "X0": chain.rest_position, "theory_v": th["v"], "theory_T": th["T"],
           "theory_t": th["t"]}
for name, values in columns.items():
    ref = table[name]
    check(len(values) == len(ref), "%s: %d values, driver %d" % (name, len(values), len(ref)))
    bad = [k + 1 for k, (a, b) in enumerate(zip(values, ref)) if not same(float(a), b)]
    check(not bad, "%s differs from the driver at granules %s (e.g. %r vs %r)" % (
        name, bad[:5], values[bad[0] - 1] if bad else None, ref[bad[0] - 1] if bad else None))
check(math.isnan(sim.t_pass[-1]), "t_pass of the last granule is NaN")
stats = sim.stats
check(stats["complete"] == 1 and stats["granule_reached"] == 39, "stats %r" % stats)
x, v = sim.state()
check(len(x) == 40 and len(v) == 40, "state")
check(taper.asymptotic_exponent("v_of_k") == -1.5, "asymptotic_exponent")

# Errors carry the library's status and message.
try:
    taper.Chain("forward_linear", n_granules=100, s=0.5)
    check(False, "forward_linear N > 1 + 1/S accepted")
except taper.TaperError as e:
    check(e.status == 1 and e.name == "TAPER_EINVAL" and len(e.message) > 10, "chain error %r" % e)
try:
    taper.Sim(chain, rtol=-1)
    check(False, "rtol = -1 accepted")
except taper.TaperError as e:
    check(e.status == 1 and "rtol" in e.message, "rtol error %r" % e)
partial = taper.Sim(chain, max_steps=10)
try:
    partial.run()
    check(False, "max_steps = 10 did not stop the run")
except taper.TaperError as e:
    check(e.name == "TAPER_ELIMIT" and "max_steps" in e.message, "limit error %r" % e)
check(partial.status == 6 and partial.stats["complete"] == 0, "partial status")
check(len(partial.t_pass) == 40, "partial observables readable")
check(taper.Sim(chain, max_steps=10).run(check=False) == 6, "run(check=False)")

seen = []
stopper = taper.Sim(chain, monitor=lambda p: seen.append(p["granule"]) or len(seen) >= 3)
check(stopper.run(check=False) == 5 and len(seen) == 3, "monitor stop: %r" % seen)
try:
    taper.Sim(chain, method="rk4")
    check(False, "unknown method accepted")
except ValueError:
    pass

# Lists without numpy, numpy arrays with it.
if taper._np is not None:
    check(isinstance(sim.t_pass, taper._np.ndarray), "numpy array expected")
    saved, taper._np = taper._np, None
    check(isinstance(sim.t_pass, list) and isinstance(taper.theory(chain)["v"], list), "lists")
    taper._np = saved
else:
    check(isinstance(sim.t_pass, list), "list expected without numpy")

if failures:
    print("\n".join(failures), file=sys.stderr)
    sys.exit(1)
print("python: %d columns equal to the driver's granules.tsv bit for bit; errors raise "
      "TaperError (numpy: %s)" % (len(columns), "yes" if taper._np is not None else "no"))
