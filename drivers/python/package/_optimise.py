# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.calibrate() and taper.design(): a scene's settings fitted to
measurements, and a result of the run optimised over settings, by the
driver's own optimisers (drivers/scenes/optimise; docs/calibration.md,
docs/optimal-design.md).  A call is the scene of its keywords with
``&calibrate`` or ``&design``: the same runs, the same optimum, as
``taper SCENE.nml``, and nothing written."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Dict, Mapping, Optional, Sequence, Tuple, Union

from . import _core

if TYPE_CHECKING:  # numpy is imported on a call's first need (import taper stays cheap)
    import numpy as np

__all__ = ["Calibration", "Design", "calibrate", "design"]

Names = Union[str, Sequence[str]]
Reals = Union[float, Sequence[float]]


def _names(free: Names) -> str:
    """'young damping' or ['young', 'damping'] as the scene's one string."""
    if isinstance(free, str):
        return free
    names = list(free)
    for n in names:
        if not isinstance(n, str):
            raise TypeError(f"free: a setting's name is a str, not {type(n).__name__}")
    return " ".join(names)


def _reals(name: str, x: Optional[Reals]) -> Optional[Sequence[float]]:
    if x is None:
        return None
    if isinstance(x, (str, bytes)):
        return [x]
    try:
        return list(x)
    except TypeError:  # a number (a 0-d array too)
        return [x]


def _keywords(group: str, scene: Dict[str, Any], given: Mapping[str, Any]) -> Dict[str, Any]:
    """The group's variables under their scene names (calibrate_free, ...)
    added to the scene's keywords, each given once."""
    kw = dict(scene)
    for key, value in given.items():
        if value is None:
            continue
        name = f"{group}_{key}"
        if name in kw:
            raise TypeError(f"{group}() got {key!r} twice (as {key} and as {name})")
        kw[name] = value
    return kw


@dataclass(frozen=True)
class Calibration:
    """The outcome of taper.calibrate().

    Attributes:
        names: the free settings, in the order given.
        values: {name: the fitted value} in each setting's unit (SI with
            &material: units).
        errors: {name: standard error}; absolute when ``noise`` was given
            (``absolute_errors``), else scaled by sqrt(chi2/dof); NaN for a
            setting the data do not determine.
        correlation: their correlation matrix, in the order of names.
        at_bound: {name: "lower" or "upper"} for settings that ended at a
            bound (then ``converged`` is False).
        chi2, dof: the weighted sum of squared residuals, N - p.
        converged: the fit has an answer to trust; ``outcome`` ("converged",
            "not converged") and ``reason`` say how it ended.
        iterations, runs: trust-region iterations, runs of the scene made.
        t, granule, quantity, measured, fitted, weight: every measurement
            (t NaN in a per-granule table; granule 0 for a wall), the fitted
            run there and the residual's factor.
        scene: the scene at the fitted values as a namelist: written to a
            file, ``taper FILE`` reproduces the fitted run.
    """

    names: Tuple[str, ...]
    values: Dict[str, float]
    errors: Dict[str, float]
    units: Dict[str, Optional[str]]
    correlation: np.ndarray
    at_bound: Dict[str, str]
    chi2: float
    dof: int
    absolute_errors: bool
    converged: bool
    outcome: str
    reason: str
    iterations: int
    runs: int
    start: Dict[str, float]
    bounds: Dict[str, Tuple[float, float]]
    data: str
    si: bool
    t: np.ndarray
    granule: np.ndarray
    quantity: Tuple[str, ...]
    measured: np.ndarray
    fitted: np.ndarray
    weight: np.ndarray
    scene: Optional[str] = field(repr=False)

    @property
    def chi2_per_dof(self) -> float:
        return self.chi2 / self.dof if self.dof else float("nan")

    @property
    def residuals(self) -> np.ndarray:
        """fitted - measured, point by point."""
        return self.fitted - self.measured


@dataclass(frozen=True)
class Design:
    """The outcome of taper.design().

    Attributes:
        names: the free settings; values: {name: its value at the optimum}.
        objective: the objective there (``objective_name``, in
            ``objective_unit``); goal: "minimise" or "maximise".
        at_bound: {name: "lower" or "upper"} where the optimum lies on a
            bound (the best within them).
        converged, outcome, reason: how the optimiser ended.
        iterations, runs: of the optimiser (profile_runs: the profiles').
        evaluations: every run made, in order: {"status": [...], name:
            array, ..., objective_name: array}.
        profiles: {name: (values, objective)} along each setting through
            the optimum (``profile_points`` runs each).
        scene: the scene at the optimum as a namelist.
    """

    names: Tuple[str, ...]
    values: Dict[str, float]
    units: Dict[str, Optional[str]]
    objective: float
    objective_name: str
    objective_unit: Optional[str]
    goal: str
    at_bound: Dict[str, str]
    converged: bool
    outcome: str
    reason: str
    iterations: int
    runs: int
    profile_runs: int
    start: Dict[str, float]
    bounds: Dict[str, Tuple[float, float]]
    evaluations: Dict[str, Any] = field(repr=False)
    profiles: Dict[str, Tuple[np.ndarray, np.ndarray]] = field(repr=False)
    scene: Optional[str] = field(repr=False)


def _result(cls, d: Dict[str, Any]):
    d = dict(d)
    d["converged"] = d["outcome"] == "converged"
    if "quantity" in d:
        d["quantity"] = tuple(d["quantity"])
    return cls(**d)


def calibrate(data: str, free: Names, *, start: Optional[Reals] = None,
              lower: Optional[Reals] = None, upper: Optional[Reals] = None,
              columns: Optional[Names] = None, noise: Optional[Reals] = None,
              weights: Optional[Reals] = None, max_iter: Optional[int] = None,
              xtol: Optional[float] = None, **scene: Any) -> Calibration:
    """Fits the free settings of the scene of ``scene``'s keywords to the
    measurements in ``data`` (&calibrate; docs/calibration.md):

        fit = taper.calibrate("sensor.tsv", ["young", "damping"], start=[150e9, 2e-7],
                              n_granules=8, right="wall", striker_radius=2.38e-3,
                              young=193e9, poisson=0.3, density=8000,
                              radius=2.38e-3, velocity=0.5)
        fit.values["young"], fit.errors["young"], fit.chi2_per_dof

    ``data``: a table in the form of taper's sensors.tsv, walls.tsv or
    granules.tsv, units in its header (SI with &material, or none); ``free``:
    the settings fitted, names as taper.variables() gives them (or
    GROUP.KEY, NAME(i) for an element of a list); ``start``, ``lower``,
    ``upper``: one value per setting (left out: the scene's value, the
    variable's range); ``columns``: the measured columns to fit (default:
    all); ``noise`` (each column's noise in its unit: absolute errors) or
    ``weights``; ``max_iter``, ``xtol``: the trust region's.  Every other
    keyword is a scene variable, as for taper.simulate() (``threads``: runs
    at once).  A fit without an answer to trust (not converged, a setting
    at its bound or undetermined) is returned with ``converged`` False and
    ``reason``.

    Raises:
        InvalidArgumentError: a problem of the keywords or of the data
            (.field the scene variable: calibrate_data, calibrate_free, ...;
            the message names FILE:LINE:COLUMN for the data).
        TaperError: the fit failed (the run at the start failed).
        KeyboardInterrupt: Ctrl-C (every run stops).
    """
    given = {"data": data, "free": _names(free), "start": _reals("start", start),
             "lower": _reals("lower", lower), "upper": _reals("upper", upper),
             "columns": None if columns is None else _names(columns),
             "noise": _reals("noise", noise), "weights": _reals("weights", weights),
             "max_iter": max_iter, "xtol": xtol}
    return _result(Calibration, _core.calibrate(**_keywords("calibrate", scene, given)))


def design(objective: str, free: Names, *, goal: Optional[str] = None,
           start: Optional[Reals] = None, lower: Optional[Reals] = None,
           upper: Optional[Reals] = None, method: Optional[str] = None,
           grid: Optional[int] = None, tolerance: Optional[float] = None,
           max_runs: Optional[int] = None, hold: Optional[str] = None,
           log_radii: Optional[Reals] = None, profile_points: Optional[int] = None,
           **scene: Any) -> Design:
    """Optimises ``objective``, a result of the run, over the free settings
    of the scene of ``scene``'s keywords (&design; docs/optimal-design.md):

        d = taper.design("wall_peak_force_right", "log_radii(1)", log_radii=[0],
                         lower=[-2], upper=[2], hold="length", n_granules=20,
                         right="wall", striker_radius=2.38e-3, t_end=1e-3,
                         young=193e9, poisson=0.3, density=8000,
                         radius=2.38e-3, velocity=0.5)
        d.values, d.objective, d.runs

    ``objective``: a statistic of granules.tsv's header (taper.STATISTICS)
    or a granule's observable NAME(k); ``goal``: "minimise" (default) or
    "maximise"; ``free``, ``start``, ``lower``, ``upper``: as for
    calibrate(), the bounds finite; ``method``: "nelder_mead" (default),
    "bfgs" or "grid" (a scan); ``grid``: points per setting of the coarse
    grid run first; ``tolerance``, ``max_runs``; ``hold``: "length" or
    "mass" kept fixed (with &material); ``log_radii``: the coefficients of
    a smooth chain, ln(R_k/R_1) = sum c_j x^j; ``profile_points``: runs
    along each setting through the optimum.  Every other keyword is a scene
    variable.

    Raises:
        InvalidArgumentError: a problem of the keywords (.field the scene
            variable: design_objective, design_free, ...).
        TaperError: no run succeeded.
        KeyboardInterrupt: Ctrl-C.
    """
    given = {"objective": objective, "free": _names(free), "goal": goal,
             "start": _reals("start", start), "lower": _reals("lower", lower),
             "upper": _reals("upper", upper), "method": method, "grid": grid,
             "tolerance": tolerance, "max_runs": max_runs, "hold": hold,
             "log_radii": _reals("log_radii", log_radii), "profile_points": profile_points}
    return _result(Design, _core.design(**_keywords("design", scene, given)))
