# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.asymptotic -- the large-k laws of the binary collision theory
(arXiv:0905.4512, Secs. III-IV), for any contact exponent n > 1.

Thin wrappers over the C functions ``taper_asymptotic_*`` of include/taper.h,
which state each formula, its equation number and its domain; the values are
the library's.  Every function returns NaN outside its domain (NaN
arguments, n <= 1 or infinite, q or S out of range) and raises only for
arguments of the wrong type (TypeError naming the argument) or, for
:func:`exponent`, an unknown law (:class:`taper.InvalidArgumentError`, a
ValueError, with ``field == "law"``).

Each function takes numbers or array-likes (numpy broadcasting rules) and
returns a float for numbers, a float64 array otherwise::

    import numpy as np, taper
    taper.asymptotic.exponent("v_of_t")            # -15/23 for n = 5/2
    q = np.linspace(0.01, 0.5, 50)
    taper.asymptotic.f(q)                          # v ~ t^-f (Table III)

Exponential chains use the paper's signed q: q > 0 is the backward chain
R_k = (1-q)^(1-k); a forward chain R_k = (1+q)^(1-k) of parameter q is
evaluated at -q, as the paper does in Sec. IV B.
"""

from __future__ import annotations

from typing import Any, Callable, Union

import numpy as np
import numpy.typing as npt

from . import _core

__all__ = ["LAWS", "exponent", "A", "lnA", "eta", "f", "position_exponent", "speed_exponent",
           "timescale", "M", "C0", "C", "forward_linear_b"]

#: The power laws, by taper_law_name in enum order: "v_of_k" (v_k ~ k^-3/2,
#: eq. (22)), "t_res_of_k" (eq. (25)), "t_of_k" (eq. (26)), "k_of_t"
#: (Table I), "v_of_t" (eq. (27)), "x_of_t" (eq. (30)), "c_of_t" (eq. (31)),
#: and the forward linear divergence laws "fwd_v_of_k" (eq. (50)),
#: "fwd_t_of_k" (eq. (51)), "fwd_v_of_t" (eq. (53)).
LAWS = _core.LAWS

#: A number or an array-like of numbers (numpy broadcasting).
Values = npt.ArrayLike
#: float for numbers, a float64 array for array-likes.
FloatOrArray = Union[float, "npt.NDArray[np.float64]"]


def _apply(fn: Callable[..., float], *args: Any) -> Any:
    """fn on numbers, or element-wise on array-likes (as a float64 array)."""
    if all(np.ndim(a) == 0 and not isinstance(a, np.ndarray) for a in args):
        return fn(*args)
    return np.vectorize(fn, otypes=[np.float64])(*args)


def exponent(law: str, n: Values = 2.5) -> FloatOrArray:
    """The exponent p of the power law `law` (a name of :data:`LAWS`) for
    contact exponent n (taper_asymptotic_exponent).  With beta = 3/2 -
    1/(2n): v_of_k -3/2, t_res_of_k beta, t_of_k beta+1, k_of_t 1/(beta+1),
    v_of_t -3/2/(beta+1), x_of_t 2/(beta+1), c_of_t 2/(beta+1) - 1, and the
    forward linear fwd_v_of_k -3/2, fwd_t_of_k beta+1, fwd_v_of_t
    -3/2/(beta+1).  For n = 5/2: -3/2, 13/10, 23/10, 10/23, -15/23, 20/23,
    -3/23, -3/2, 23/10, -15/23."""
    return _apply(lambda nn: _core.asymptotic_exponent(law, nn), n)


def A(q: Values) -> FloatOrArray:
    """A(q) = [1 + (1-q)^-3] / 2, eq. (35): v_{k+1} = v_k / A in a backward
    exponential chain.  Domain q < 1."""
    return _apply(lambda a: _core.asymptotic("A", a), q)


def lnA(q: Values) -> FloatOrArray:
    """ln A(q), accurate for small |q|: the decay rate of v_k in k (Table
    II); a forward chain's growth rate is -lnA(-q) (Table IV).  Domain q < 1."""
    return _apply(lambda a: _core.asymptotic("lnA", a), q)


def eta(q: Values, n: Values = 2.5) -> FloatOrArray:
    """eta(q) = ln(T_{k+1}/T_k) = (1 - 2/n) ln A - (5/(2n)) ln(1-q), exact for
    every k; n = 5/2 gives eq. (39), ln(A^(1/5)/(1-q)).  Domain q < 1, n > 1."""
    return _apply(lambda a, b: _core.asymptotic("eta", a, b), q, n)


def f(q: Values, n: Values = 2.5) -> FloatOrArray:
    """f(q) = ln A / eta, eq. (41): v ~ t^-f (backward chains, Table III) and
    v ~ (1 + t/M)^-f(-q) (forward, Table V).  Domain q < 1, q != 0, n > 1."""
    return _apply(lambda a, b: _core.asymptotic("f", a, b), q, n)


def position_exponent(q: Values, n: Values = 2.5) -> FloatOrArray:
    """Backward exponential chains: X ~ t^p with p = -ln(1-q)/eta, which is
    1 - f/5 for n = 5/2, eq. (44).  Domain 0 < q < 1."""
    return _apply(lambda a, b: _core.asymptotic("position_exponent", a, b), q, n)


def speed_exponent(q: Values, n: Values = 2.5) -> FloatOrArray:
    """Backward exponential chains: c = dX/dt ~ t^(p-1), -f/5 for n = 5/2,
    eq. (45).  Domain 0 < q < 1."""
    return _apply(lambda a, b: _core.asymptotic("speed_exponent", a, b), q, n)


def timescale(q: Values, n: Values = 2.5) -> FloatOrArray:
    """tau(q) = T_1 / (e^eta - 1), T_1 the first residence time: the exact
    theory obeys t_k = tau (e^(k eta) - 1) and v_k = (1 + t_{k-1}/tau)^-f
    for every k (eqs. (40), (56)).  tau > 0 for backward chains (q > 0),
    < 0 for forward ones (q < 0).  Domain q < 1, q != 0, n > 1."""
    return _apply(lambda a, b: _core.asymptotic("timescale", a, b), q, n)


def M(q: Values, n: Values = 2.5) -> FloatOrArray:
    """M(q) of eq. (57) for a forward exponential chain of parameter q > 0:
    timescale(-q, n) < 0; v diverges as t -> -M.  (The paper's printed M(q)
    is wrong: docs/paper.md.)"""
    return _apply(lambda a, b: _core.asymptotic("M", a, b), q, n)


def C0(S: Values, n: Values = 2.5) -> FloatOrArray:
    """Forward linear chains, 0 < S < 1: the leading order of the divergence
    time, sqrt(pi) Gamma(1+1/n)/Gamma(1/n+1/2) (n/4)^(1/n) / ((beta+1) S)."""
    return _apply(lambda a, b: _core.asymptotic("C0", a, b), S, n)


def C(S: Values, n: Values = 2.5) -> FloatOrArray:
    """Forward linear chains, 0 < S < 1: the divergence time C(S) = C0 (1 +
    c1 S) (c1 = 57/130 for n = 5/2), relative error O(S^2)."""
    return _apply(lambda a, b: _core.asymptotic("C", a, b), S, n)


def forward_linear_b(S: Values) -> FloatOrArray:
    """b = S/(1+S): v_k ~ (1 - b k)^-3/2 diverges at k = 1/b (Fig. 8 inset).
    Domain 0 < S < 1."""
    return _apply(lambda a: _core.asymptotic("forward_linear_b", a), S)
