# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.fit(): least-squares fits of y(x) by the library (taper_fit)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional, Tuple, Union

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

from . import _core

__all__ = ["FitResult", "fit"]

Real = Union[int, float]


@dataclass(frozen=True)
class FitResult:
    """The outcome of taper.fit().

    Attributes:
        model: the model's name (one of taper.FIT_MODELS).
        params: the parameters in the model's order (taper.h, "Fits"):
            power and exponential ``(a, b)``; divergence_b ``(a, b, p)``;
            divergence_c ``(a, C, p)``; divergence_m ``(a, M, f)``.  The
            exponent p of divergence_b/_c is reported fixed or fitted.
        errors: their standard errors (0 for a fixed exponent).
        n_params: how many parameters were fitted (2 or 3).
        chi2: the sum of squared residuals of ln y.
        n_points: the points used; n_skipped: those in the window skipped
            (not finite, y <= 0, or x <= 0 for a power law).
        iterations: of the nonlinear solver (0 for the linear models).
    """

    model: str
    params: np.ndarray
    errors: np.ndarray
    n_params: int
    chi2: float
    n_points: int
    n_skipped: int
    iterations: int


def fit(x: npt.ArrayLike, y: npt.ArrayLike, *, model: str = "power",
        exponent: Optional[Real] = None,
        index_window: Optional[Tuple[int, Optional[int]]] = None,
        x_window: Optional[Tuple[Optional[Real], Optional[Real]]] = None,
        skip_invalid: Optional[bool] = None, max_iter: Optional[int] = None,
        xtol: Optional[Real] = None) -> FitResult:
    """Fits y(x) by least squares on ln y with libtaper (taper_fit; the
    models and their parameters are described in include/taper.h, "Fits"):

    * ``"power"``         y = a x^b
    * ``"exponential"``   y = a e^(b x)
    * ``"divergence_b"``  y = a (1 - b x)^-p, p given (default 3/2)
    * ``"divergence_c"``  y = a (1 - x/C)^-p, p given, or fitted (the default)
    * ``"divergence_m"``  y = a (1 + x/M)^-f, f fitted

    Every keyword is passed to the fit setter of its name
    (taper_fit_spec_set_<name>); left out (or None): the library's default.
    ``exponent`` is p (``float("nan")``: fit it, divergence_c only);
    ``index_window=(begin, end)`` the points begin <= i < end (end None or
    0: to the end); ``x_window=(x_min, x_max)`` the points with x_min <= x
    <= x_max (None: unbounded); ``skip_invalid`` (default True) skips points
    where a logarithm cannot be taken instead of refusing them;
    ``max_iter`` and ``xtol`` steer the nonlinear solver.

    Raises:
        InvalidArgumentError: a value the library refuses, ``.field`` naming
            the keyword (``model``, ``exponent``, ``index_window``, ...), x
            and y of different lengths (``y``), or too few usable points.
        TaperError: the nonlinear fit did not converge (status "solver").
        TypeError: an argument of the wrong type (named).
    """
    d = _core.fit(x, y, model=model, exponent=exponent, index_window=index_window,
                  x_window=x_window, skip_invalid=skip_invalid, max_iter=max_iter, xtol=xtol)
    return FitResult(**d)
