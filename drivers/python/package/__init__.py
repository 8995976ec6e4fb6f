"""taper -- pulse propagation in tapered granular chains, from Python.

The full Hertzian dynamics of a chain (libtaper: SUNDIALS CVODE with exact
pulse events) next to the binary collision theory of Harbola, Rosas,
Esposito and Lindenberg, arXiv:0905.4512.  The library is compiled into
the extension ``taper._core``; results come back as numpy arrays.

    import taper
    r = taper.simulate(profile="backward_linear", s=0.5, n_granules=200)
    r.v_peak, r.theory_v, r.t_pass          # numpy columns as in granules.tsv
    r.stats["steps"], r.energy_error, r.complete

    taper.theory(profile="backward_linear", s=0.5, n_granules=200)  # no integration
    taper.run_scene("share/scenes/backward_linear.nml")             # the driver's reader
    taper.read_granules("out/default/granules.tsv")                 # a driver's output

    taper.chain(profile="backward_linear", s=0.5).mu   # R m X0, contact factors r, mu
    taper.asymptotic.exponent("v_of_t")               # the large-k laws (-15/23)
    taper.fit(r.k, r.v_peak, model="power", index_window=(100, None)).params  # (a, b)

Keyword arguments are the scene variables (docs/scene.md); values left out
(or None) are the library's defaults.  A value the library refuses raises
InvalidArgumentError (a ValueError) whose ``field`` names the argument; a
wrong type raises TypeError naming it.  Runs release the GIL: threads run
chains in parallel.  Ctrl-C interrupts a run with KeyboardInterrupt.
See docs/python.md.
"""

from __future__ import annotations

import os
from typing import Any, List, Optional, Sequence, Union

from . import _core, asymptotic
from ._build import build_info
from ._chain import BEYOND_PAPER, CHAIN_COLUMNS, Chain, chain
from ._core import InvalidArgumentError, SceneError, TaperError, collision_time
from ._fit import FitResult, fit
from .result import COLUMNS, THEORY_COLUMNS, Result, read_granules

__all__ = [
    "simulate", "theory", "run_scene", "read_granules", "plot", "collision_time", "version",
    "build_info",
    "chain", "fit", "asymptotic",
    "Result", "Chain", "FitResult", "TaperError", "InvalidArgumentError", "SceneError",
    "PROFILES", "METHODS", "STATISTICS", "OBSERVABLES", "THEORY_QUANTITIES", "LAWS",
    "FIT_MODELS", "COLUMNS", "THEORY_COLUMNS", "CHAIN_COLUMNS", "BEYOND_PAPER",
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

Real = Union[int, float]


def version() -> str:
    """The version of libtaper compiled into this package."""
    return _core.version()


__version__ = _core.version()


def _given(**kw: object) -> dict:
    return {k: v for k, v in kw.items() if v is not None}


def _beyond_paper(kw: dict, func: str) -> dict:
    """The chain settings of BEYOND_PAPER among kw; any other name is a
    TypeError, as for a missing keyword."""
    for k in kw:
        if k not in BEYOND_PAPER:
            raise TypeError(f"{func}() got an unexpected keyword argument '{k}'")
    return kw


def simulate(*, profile: Optional[str] = None, s: Optional[Real] = None,
             q: Optional[Real] = None, n_granules: Optional[int] = None,
             exponent: Optional[Real] = None, radii: Optional[Sequence[float]] = None,
             method: Optional[str] = None, rtol: Optional[Real] = None,
             atol: Optional[Real] = None, window: Optional[bool] = None,
             last_granule: Optional[int] = None, max_order: Optional[int] = None,
             t_max: Optional[Real] = None, max_steps: Optional[int] = None,
             t_end: Optional[Real] = None, sample_interval: Optional[Real] = None,
             **beyond_paper: Any) -> Result:
    """Builds a chain, integrates its dynamics and returns a Result.

    Chain (``&chain`` of a scene): ``profile`` (one of PROFILES, default
    "monodisperse"), ``s`` (linear profiles), ``q`` (exponential profiles),
    ``n_granules`` (N, default 100; with ``radii`` it may be left out),
    ``exponent`` (contact exponent n, default 5/2), ``radii`` (custom profile:
    R_1..R_N, R_1 = 1).

    Solver (``&solver``): ``method`` ("adams" or "bdf"), ``rtol``, ``atol``
    (in units of each granule's binary-collision scale), ``window`` (integrate
    only the granules that can move; exact), ``last_granule`` (stop once its
    observables are known; 0: the whole chain), ``max_order``, ``t_max`` and
    ``max_steps`` (0: no limit; reaching one gives a partial result),
    ``t_end`` (go on integrating until t_end after every observable is
    known, e.g. to follow a reflection from a wall; 0: stop then),
    ``sample_interval`` (> 0: the state at t = 0, dt, 2 dt, ... while the
    run lasts, in ``Result.samples``: ``t``, ``x`` and ``v`` (samples x N),
    ``force`` (samples x (N + 1): force[:, 0] on granule 1 from the left,
    force[:, k] of the contact (k, k+1), force[:, N] from the right);
    interpolated by CVODE without stopping it; memory 3 N + 2 doubles per
    sample).

    Beyond the paper (taper.h, docs/physics.md; every default is the
    paper's chain), named as the library's fields (see BEYOND_PAPER):
    ``left_end``/``right_end`` ("free" or "wall"),
    ``left_wall_compliance``/``right_wall_compliance`` (a wall's (1-nu^2)/E
    relative to granule 1's, 0: rigid), ``striker_radius`` (0: the impulse
    v_1 = 1), ``striker_density``, ``striker_compliance``, ``load`` (static
    force F0), ``damping`` (Kuwabara-Kono time), ``drag`` (force -drag v),
    ``pattern`` (the radii of one period of the "decorated" profile),
    ``materials`` (a pair (density, compliance) of N values each, relative
    to granule 1's), ``disorder`` ("radius" or "mass"),
    ``disorder_amplitude`` (0 <= a < 1), ``disorder_seed``,
    ``piston_duration`` (a piston pushing granule 1 at unit velocity for
    that long, ``math.inf``: for ever; 0: none) and ``piston_compliance``
    (its face's, as a wall's; docs/physics.md, "Piston").  The energy
    budget is in ``stats`` (energy_initial, energy_dissipated,
    energy_transmitted, energy_reflected, energy_in_chain) with the wall
    forces (wall_peak_force_left, ...).

    Returns the columns of granules.tsv (bit for bit what the driver writes
    for the same scene), the statistics, conservation errors and status.  A
    run that ends early (solver failure, t_max, max_steps) is returned with
    ``complete`` False, ``status`` and ``message`` saying why.

    Raises:
        InvalidArgumentError: a value or combination the library refuses
            (``.field`` names the argument, the message is the library's).
        TypeError: an argument of the wrong type (named).
        KeyboardInterrupt: Ctrl-C during the run (nothing is returned).
    """
    d = _core.simulate(**_given(profile=profile, s=s, q=q, n_granules=n_granules,
                                exponent=exponent, radii=radii, method=method, rtol=rtol,
                                atol=atol, window=window, last_granule=last_granule,
                                max_order=max_order, t_max=t_max, max_steps=max_steps,
                                t_end=t_end, sample_interval=sample_interval,
                                **_beyond_paper(beyond_paper, "simulate")))
    return Result._from_core(d, "simulate")


def theory(*, profile: Optional[str] = None, s: Optional[Real] = None,
           q: Optional[Real] = None, n_granules: Optional[int] = None,
           exponent: Optional[Real] = None,
           radii: Optional[Sequence[float]] = None, **beyond_paper: Any) -> Result:
    """The binary collision approximation of a chain, without integrating:
    columns ``k R m X0 theory_v theory_T theory_t`` (v_k of eq. (9), T_k of
    eq. (18), t_k of eq. (19) of arXiv:0905.4512).  Chain keywords as for
    simulate(), those beyond the paper included (where the binary collision
    approximation does not describe the chain, e.g. with damping, the theory
    columns are NaN: taper_chain_theory_note)."""
    d = _core.theory(**_given(profile=profile, s=s, q=q, n_granules=n_granules,
                              exponent=exponent, radii=radii,
                              **_beyond_paper(beyond_paper, "theory")))
    return Result._from_core(d, "theory")


def run_scene(path: Union[str, "os.PathLike[str]"]) -> List[Result]:
    """Runs a scene file as the driver ``taper`` does: read and validated by
    the driver's own scene reader (compiled into this package), one Result per
    value of a swept variable (one for a scene without sweep), in order.  With
    ``&solver numerics = .false.`` the results hold the theory alone.  Writes
    no files (&output, &fit, &table, &figure are the driver's business).

    Raises:
        SceneError: the scene is invalid; the message is the reader's
            diagnostics, as the driver prints them (FILE:LINE: &group key: ...).
    """
    return [Result._from_core(d, os.fspath(path)) for d in _core.run_scene(path)]


def plot(result, quantity: str = "v", *, ax=None, **kwargs):
    """Draws a Result (or a list of them) as the driver's figures do; see
    taper.plotting.plot.  Needs matplotlib."""
    from .plotting import plot as _plot
    return _plot(result, quantity, ax=ax, **kwargs)
