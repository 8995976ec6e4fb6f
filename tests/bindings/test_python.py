#!/usr/bin/env python3
"""test_python.py BUILD_DIR SOURCE_DIR -- src/bindings/python/taper.py (ctypes)
against the C driver: the same chain run through Python and through
drivers/taper (scene file -> granules.tsv) gives the same numbers, bit for
bit (same library, same default solver), statistics by the library's names
equal the driver's header, and library errors arrive as taper.TaperError
carrying the library's message and the setting at fault (.field).  The
binding keeps no list of its own: profile, method, fit model and statistic
names come from the library."""

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
    """The driver's granules.tsv: its columns, and its '# name = value'
    header lines (the statistics among them)."""
    scene = os.path.join(tmp, "pytest.nml")
    with open(scene, "w") as f:
        f.write(SCENE)
    out = os.path.join(tmp, "out")
    proc = subprocess.run([os.path.join(build, "drivers", "taper", "taper"), scene, "-o", out],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        sys.exit("driver failed (%d): %s" % (proc.returncode, proc.stderr))
    lines = open(os.path.join(out, "granules.tsv")).read().splitlines()
    rows = [line.split("\t") for line in lines if not line.startswith("#")]
    header, rows = rows[0], rows[1:]
    values = dict(line[2:].split(" = ", 1) for line in lines
                  if line.startswith("# ") and " = " in line and not line.startswith("#  "))
    return {name: [float(r[i]) for r in rows] for i, name in enumerate(header)}, values


with tempfile.TemporaryDirectory() as tmp:
    table, header = driver_table(tmp)

check(taper.version() == "0.2.0", "version %s" % taper.version())
check(taper.PROFILES == ("monodisperse", "backward_linear", "forward_linear",
                         "backward_exponential", "forward_exponential", "custom"),
      "profiles from the library: %r" % (taper.PROFILES,))
check(taper.METHODS == ("adams", "bdf"), "methods %r" % (taper.METHODS,))
check(len(taper.STATISTICS) == 14 and taper.STATISTICS[0] == "steps"
      and taper.STATISTICS[-1] == "complete", "statistics %r" % (taper.STATISTICS,))
chain = taper.Chain("backward_linear", n_granules=40, s=0.2)
check(len(chain) == 40 and chain.profile == "backward_linear", "chain")
sim = taper.Sim(chain)
check(sim.run() == 0, "run status")
th = taper.theory(chain)
for key in taper.THEORY:  # the sim's theory, computed once, is theory(chain)'s
    check(all(same(float(a), float(b)) for a, b in zip(sim.theory[key], th[key])),
          "Sim.theory[%r] differs from theory(chain)" % key)
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
for name, value in stats.items():  # the driver's header prints the same statistics
    if name not in header:
        continue  # 'complete' is a line of its own
    ref = header[name]
    ok = ("%.4g" % value == ref) if name.endswith("_error") else (float(ref) == value)
    check(ok, "statistic %s = %r, driver %s" % (name, value, ref))
check(all(name in header for name in taper.STATISTICS if name != "complete"),
      "statistics missing from the driver's header: %r"
      % [n for n in taper.STATISTICS if n not in header])
x, v = sim.state()
check(len(x) == 40 and len(v) == 40, "state")
check(taper.asymptotic_exponent("v_of_k") == -1.5, "asymptotic_exponent")

# Errors carry the library's status, message and the setting at fault.
def refused(field, make, status=1):
    try:
        make()
        check(False, "%s: accepted" % field)
    except taper.TaperError as e:
        check(e.status == status and e.name == taper.STATUS[status] and e.field == field
              and len(e.message) > 10, "%s: error %r (field %r)" % (field, e, e.field))


refused("n_granules", lambda: taper.Chain("forward_linear", n_granules=100, s=0.5))
refused("rtol", lambda: taper.Sim(chain, rtol=-1))
refused("atol", lambda: taper.Sim(chain, atol=0.5))
refused("s", lambda: taper.Chain("backward_linear", s=float("nan")))
refused("n_granules", lambda: taper.Chain("monodisperse", n_granules=1))
refused("n_granules", lambda: taper.Chain("monodisperse", n_granules=-3))
refused("exponent", lambda: taper.Chain("monodisperse", exponent=1.0))
refused("radii", lambda: taper.Chain(radii=[1.0, -1.0, 1.0]))
refused("radii", lambda: taper.Chain("custom", n_granules=3))
refused("profile", lambda: taper.Chain("no_such_profile"))
refused("method", lambda: taper.Sim(chain, method="rk4"))
refused("last_granule", lambda: taper.Sim(chain, last_granule=41))
refused("max_order", lambda: taper.Sim(chain, method="bdf", max_order=6))
refused("xtol", lambda: taper.fit("power", [1, 2, 3], [1, 2, 3], xtol=0))
try:
    taper.Sim(chain, no_such_setting=1)
    check(False, "unknown keyword accepted")
except TypeError:
    pass
custom = taper.Chain(radii=[1.0, 1.5, 2.0, 2.5])
check(custom.profile == "custom" and len(custom) == 4 and float(custom.radius[3]) == 2.5, "custom")
f = taper.fit("power", [1.0, 2.0, 4.0, 8.0], [1.0, 0.25, 0.0625, 0.015625])
check(f["model"] == "power" and abs(f["params"][1] + 2.0) < 1e-12 and f["n_points"] == 4,
      "fit %r" % f)
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
