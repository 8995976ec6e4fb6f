# SPDX-License-Identifier: GPL-3.0-or-later
"""taper -- pulse propagation in tapered granular chains, from Python.

The full Hertzian dynamics of a chain (libtaper: SUNDIALS CVODE with exact
pulse events) next to the binary collision theory of Harbola, Rosas,
Esposito and Lindenberg, arXiv:0905.4512.  The library and the driver's
scene reader are compiled into the extension ``taper._core``; results come
back as numpy arrays.  (On PyPI the distribution is taper-chains.)

    import taper
    r = taper.simulate(profile="backward_linear", s=0.5, n_granules=200)
    r.v_peak, r.theory_v, r.t_pass          # numpy columns as in granules.tsv
    r.stats["steps"], r.energy_error, r.complete, r.pulse_speed()

    # real units: every dimensional input in SI, the results in SI
    si = taper.simulate(young=193e9, poisson=0.3, density=8000, radius=4.76e-3,
                        velocity=0.5, n_granules=50)
    si.t_pass, si.units["t_pass"]           # seconds, "s"
    si.to_pandas()                          # columns t_pass[s], v_peak[m/s], ...

    taper.theory(profile="backward_linear", s=0.5, n_granules=200)  # no integration
    taper.run_scene("share/scenes/backward_linear.nml")             # the driver's reader
    taper.read_granules("out/default/granules.tsv")                 # a driver's output
    taper.read_sweep("out/sweep")          # a sweep: a row per run (DataFrame with pandas)
    taper.variables()                      # every keyword: group, type, default, unit

    taper.chain(profile="backward_linear", s=0.5).mu   # R m X0, contact factors r, mu
    taper.taper_from_radii("backward_linear", 1.0, 5.0, 100)   # the s of R_N/R_1 = 5
    taper.asymptotic.exponent("v_of_t")               # the large-k laws (-15/23)
    taper.fit(r.k, r.v_peak, model="power", index_window=(100, None)).params  # (a, b)

    # settings fitted to measurements, and a design optimised (the driver's
    # &calibrate and &design: docs/calibration.md, docs/optimal-design.md)
    taper.calibrate("sensor.tsv", ["young", "damping"], young=193e9, ...).values
    taper.design("wall_peak_force_right", "log_radii(1)", lower=[-2], upper=[2], ...).values

Keyword arguments are the scene's variables, by their one name (a scene
file writes it in its group without the group's name in front:
``striker_radius`` is ``&striker radius``; taper.variables() lists them;
``inspect.signature(taper.simulate)`` and help() show them with their
defaults, types and units).  A call is a scene: checked by the driver's
scene reader as a file is, values left out (or None) are the defaults.  An
unknown keyword or a value of the wrong Python type raises TypeError naming
it; a value the scene or the library refuses raises InvalidArgumentError (a
ValueError) whose ``field`` is the keyword.  Runs release the GIL: threads
run chains in parallel.  Ctrl-C interrupts a run with KeyboardInterrupt.
See docs/python.md.
"""

from __future__ import annotations

import os
from typing import Any, List, Union

from . import _core, _progress, _signature
from ._build import build_info
from ._chain import CHAIN_COLUMNS, Chain
from ._chain import chain as _chain
from ._core import InvalidArgumentError, SceneError, TaperError, collision_time
from ._fit import FitResult, fit
from ._geometry import radii_from_taper, taper_from_radii
from ._optimise import Calibration, Design, calibrate, design
from ._sweep import SweepTable, read_sweep
from ._variables import Variable, variables
from .result import COLUMNS, THEORY_COLUMNS, Result, read_granules

__all__ = [
    "simulate", "theory", "run_scene", "read_granules", "read_sweep", "plot", "collision_time", "version",
    "build_info", "chain", "cite", "fit", "asymptotic", "variables", "taper_from_radii",
    "radii_from_taper", "calibrate", "design",
    "Result", "Chain", "FitResult", "Variable", "Calibration", "Design", "SweepTable",
    "TaperError",
    "InvalidArgumentError",
    "SceneError", "PROFILES", "METHODS", "STATISTICS", "OBSERVABLES", "THEORY_QUANTITIES",
    "LAWS", "FIT_MODELS", "COLUMNS", "THEORY_COLUMNS", "CHAIN_COLUMNS",
    "BOUNDARIES", "DISORDERS", "__version__",
]

#: Profile names, in the library's order (taper_profile_name).
PROFILES = _core.PROFILES
#: Integration methods (taper_method_name).
METHODS = _core.METHODS
#: Names of the run statistics (taper_statistic_name): the keys of Result.stats.
STATISTICS = _core.STATISTICS
#: The observables of a run (taper_observable_name): granules.tsv's columns.
OBSERVABLES = _core.OBSERVABLES
#: The theory's quantities (taper_theory_quantity_name): "v", "mu", "T", "t";
#: a Result's columns are theory_v, theory_T, theory_t, Chain.mu is mu.
THEORY_QUANTITIES = _core.THEORY_QUANTITIES
#: The power laws of taper.asymptotic.exponent (taper_law_name).
LAWS = _core.LAWS
#: The models of taper.fit (taper_fit_model_name).
FIT_MODELS = _core.FIT_MODELS
#: What a chain end can be (taper_boundary_name): "free", "wall".
BOUNDARIES = _core.BOUNDARIES
#: What disorder perturbs (taper_disorder_name): "radius", "mass".
DISORDERS = _core.DISORDERS


def version() -> str:
    """The version of libtaper compiled into this package."""
    return _core.version()


__version__ = _core.version()


def __getattr__(name: str) -> Any:
    """taper.asymptotic and taper.plotting, imported when first used (they
    import numpy, and plotting matplotlib)."""
    if name in ("asymptotic", "plotting"):
        import importlib
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'taper' has no attribute {name!r}")


def __dir__() -> List[str]:
    return sorted(set(globals()) | {"asymptotic", "plotting"})


_RULE = """
    Keywords are the scene's variables by their one name, unique over the
    groups (listed below and by taper.variables() with their groups, types,
    defaults, units and ranges); a scene file writes a variable in its
    group without the group's name in front, if it has it:
    ``striker_radius`` is ``&striker radius``, ``left`` and
    ``left_compliance`` are ``&ends``'s, ``seed`` is ``&chain seed``,
    ``interval`` is ``&sensors interval``.  The call is a scene checked by
    the driver's scene reader exactly as a file is; left out (or None): the
    default.  Python values by the variable's type: a real takes int or
    float (numpy numbers too, never bool or str), an integer an int, a
    logical a bool, a string or choice a str, a real list a sequence of
    floats (an empty one: none).  A sweepable variable takes one value: a
    call runs one chain (a list is a TypeError; sweeps are
    taper.run_scene's).

    Real units: with the ``&material`` variables (``young``, ``poisson``,
    ``density``, ``radius``, ``velocity``, ...) every dimensional input is
    SI, in the unit shown below (``t_end`` and ``interval`` in s,
    ``damping`` in s, ``drag`` in kg/s, ``load`` in N, sizes in m), and the
    results are SI too (``units='rescaled'`` keeps them rescaled):
    ``Result.units`` names each column's, statistic's and sample's unit.
    Without ``&material`` everything is in the rescaled units of eq. (5).

    What a file would write elsewhere: ``&sensors interval`` > 0 fills
    ``Result.samples`` (the state of every granule at each sample, refused
    before the run beyond ``max_output`` bytes); ``&output columns`` and
    ``every`` choose the Result's columns and rows as they do
    granules.tsv's; ``max_energy_error`` and ``max_momentum_error`` set
    ``Result.untrusted``; ``units`` chooses the units.  The variables that
    only steer the driver's files and sweeps (``dir``, ``threads``, the
    sensors' ``granules`` and ``spacetime*``, ``&fit``, ``&table``,
    ``&figure``, ``&sweep``) are no keywords: TypeError says why.
"""


def simulate(**variables: Any) -> Result:
    """Builds the scene of the keywords, integrates its chain and returns a
    Result: the columns of granules.tsv (bit for bit what the driver writes
    for the same scene), the statistics, conservation errors, status, the
    samples of ``interval`` and the settings.
    {rule}
    A run that ends early (solver failure, t_max, max_steps) is returned
    with ``complete`` False, ``status`` and ``message`` saying why.

    Raises:
        TypeError: an unknown keyword (with the nearest name), a value of
            the wrong Python type, a list for a sweepable variable, one of
            the driver's own variables.
        InvalidArgumentError: a value or combination the scene or the
            library refuses (``.field`` is the keyword, ``.message`` the
            scene's or the library's message).
        KeyboardInterrupt: Ctrl-C during the run (nothing is returned); an
            exception raised by a progress callable propagates the same way.
    {parameters}
    """
    if not _DRIVER_ONLY.isdisjoint(variables):
        _signature.refuse_driver_only("simulate", variables)
    bar = None
    if variables.get("progress", True) is True and _progress.watched():
        bar = variables["progress"] = _progress.Bar()
    try:
        d = _core.simulate(**variables)
    finally:
        if bar is not None:
            bar.close()
    return _from_core(d)


def theory(**variables: Any) -> Result:
    """The binary collision approximation of the scene's chain, without
    integrating (the scene with ``numerics = .false.``): columns ``k R m X0
    theory_v theory_T theory_t`` (v_k of eq. (9), T_k of eq. (18), t_k of
    eq. (19) of arXiv:0905.4512), in the scene's units.  Keywords as for
    simulate() (solver settings are checked and kept, as in a file);
    ``numerics`` is not one.  Where the binary collision approximation does
    not describe the chain (e.g. with damping) the theory columns are NaN
    and ``Result.theory_note`` says why.
    {parameters}
    """
    if not _DRIVER_ONLY.isdisjoint(variables):
        _signature.refuse_driver_only("theory", variables)
    return _from_core(_core.theory(**variables))


def chain(**variables: Any) -> Chain:
    if not _DRIVER_ONLY.isdisjoint(variables):
        _signature.refuse_driver_only("chain", variables)
    return _chain(**variables)


def cite(**variables: Any) -> str:
    """BibTeX for what a run of the scene of the keywords uses, as
    ``taper --cite`` prints it: taper, the paper (Harbola, Rosas, Esposito
    and Lindenberg, Phys. Rev. E 80, 031303 (2009), arXiv:0905.4512), and
    SUNDIALS where CVODE integrates (methods adams, bdf), GSL where the
    theory, rk8 or a fit runs, and the papers of the contact models the
    scene switches on (viscoelastic damping, a static load, the decorated
    chains' effective chain).  ``taper.cite()``: the defaults'.  Nothing is
    run.  Keywords as for simulate().
    {parameters}
    """
    if not _DRIVER_ONLY.isdisjoint(variables):
        _signature.refuse_driver_only("cite", variables)
    return _core.cite(**variables)


def run_scene(path: Union[str, "os.PathLike[str]"]) -> List[Result]:
    """Runs a scene file as the driver ``taper`` does: read and validated by
    the driver's own scene reader (compiled into this package), one Result per
    point of its sweep (one for a scene without sweep), in order, each in the
    scene's units (SI with &material) with the samples of its ``&sensors``
    interval.  With ``&solver numerics = .false.`` the results hold the
    theory alone.  Writes no files (``&output dir``, ``&fit``, ``&table``,
    ``&figure`` are the driver's business).

    Raises:
        SceneError: the scene is invalid; the message is the reader's
            diagnostics, as the driver prints them (FILE:LINE: &group key: ...).
    """
    return [_from_core(d) for d in _core.run_scene(path)]


def plot(result, quantity: str = "v", *, ax=None, **kwargs):
    """Draws a Result (or a list of them) as the driver's figures do; see
    taper.plotting.plot.  Needs matplotlib."""
    from .plotting import plot as _plot
    return _plot(result, quantity, ax=ax, **kwargs)


# The signatures and the parameter lists of the docstrings, from the scene's
# table (taper._signature).
_from_core = Result._from_core
_TABLE = _core.variables()
_DRIVER_ONLY = frozenset(_signature.driver_only(_TABLE))
chain.__doc__ = (_chain.__doc__ or "") + "    {parameters}\n    "
for _func, _returns in ((simulate, Result), (theory, Result), (chain, Chain), (cite, str)):
    _func.__signature__ = _signature.signature(_TABLE, _func.__name__, _returns)
    _func.__doc__ = (_func.__doc__ or "").replace("{rule}", _RULE).replace(
        "{parameters}", "\n    Keyword-only parameters (name: type = default  [SI unit with "
        "&material]):\n" + _signature.parameter_doc(_TABLE, _func.__name__))
del _func, _returns
