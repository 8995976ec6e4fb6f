# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.plotting -- the driver's figures with matplotlib (optional:
``pip install taper-chains[plot]``).

The driver draws, per run, the theory as open circles and the numerics as
filled circles of one colour (share/scenes/paper/fig*.nml).  plot() does
the same for a Result or a list of them (a sweep):

    quantity  numerics    theory     against k
    "v"       v_peak      theory_v   pulse amplitude (Fig. 1)
    "T_res"   T_res       theory_T   residence time
    "t"       t_pass      theory_t   time the pulse passes k
"""

from __future__ import annotations

from typing import Any, Iterable, Optional, Sequence, Union

import numpy as np

from .result import Result

__all__ = ["plot", "QUANTITIES"]

#: quantity -> (numerics column, theory column, axis label)
QUANTITIES = {
    "v": ("v_peak", "theory_v", "pulse amplitude $v_k$"),
    "T_res": ("T_res", "theory_T", "residence time $T_k$"),
    "t": ("t_pass", "theory_t", "time the pulse passes, $t_k$"),
}

#: What a column is, for an axis drawn against it.
COLUMN_LABELS = {
    "k": "granule $k$", "R": "radius $R_k$", "m": "mass $m_k$", "X0": "rest position $X_k$",
    "t_pass": "time the pulse passes, $t_k$", "T_res": "residence time $T_k$",
    "v_peak": "pulse amplitude $v_k$", "t_peak": "time of the peak velocity",
    "X_pass": "position where the pulse passes, $X_k$", "theory_v": "pulse amplitude $v_k$",
    "theory_T": "residence time $T_k$", "theory_t": "time the pulse passes, $t_k$",
}


def axis_label(quantity: str, column: str, results: Sequence[Result]) -> str:
    """"quantity [unit]": the SI unit the results give the column (all the
    same, else none is claimed), "(rescaled, eq. (5))" for a dimensional
    column of rescaled results, nothing for k."""
    if column == "k":
        return quantity
    units = {r.units.get(column) for r in results}
    if len(units) == 1 and None not in units:
        return f"{quantity} [{units.pop()}]"
    if units == {None}:
        return f"{quantity} (rescaled units, eq. (5))"
    return quantity


def _label(r: Result) -> str:
    s = r.settings
    profile = s.get("profile", "")
    if "linear" in profile:
        return f"S = {s.get('s'):g}"
    if "exponential" in profile:
        return f"q = {s.get('q'):g}"
    return profile or r.source


def _thin(n: int, every: Optional[int], geometric: bool) -> np.ndarray:
    """The granules drawn: every n-th, or on log axes (every None) about 40
    per decade of k, as the driver's figures (results/plot.c)."""
    if every is not None:
        return np.arange(0, n, max(int(every), 1))
    if not geometric:
        return np.arange(n)
    keep, kept = [], 0
    for i in range(n):
        if i > 0 and i + 1 < 1.06 * kept:
            continue
        kept = i + 1
        keep.append(i)
    return np.asarray(keep, dtype=np.intp)


def plot(results: Union[Result, Sequence[Result]], quantity: str = "v", *, ax: Any = None,
         x: str = "k", curves: str = "both", loglog: bool = True, every: Optional[int] = None,
         labels: Optional[Iterable[str]] = None) -> Any:
    """Draws `quantity` ("v", "T_res" or "t") against `x` (a column, "k" by
    default) for each result: numerics filled, theory open circles.

    curves: "both", "theory" or "numerics"; loglog: logarithmic axes; every:
    draw every n-th granule (default: all on linear axes, about 40 per decade
    of k on log axes, as the driver); labels: one legend entry per result
    (default: the swept parameter).  Returns the matplotlib Axes.
    """
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - depends on the installation
        raise ImportError("taper.plot needs matplotlib: pip install matplotlib") from e
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {sorted(QUANTITIES)}, not {quantity!r}")
    if curves not in ("both", "theory", "numerics"):
        raise ValueError(f"curves must be 'both', 'theory' or 'numerics', not {curves!r}")
    if isinstance(results, Result):
        results = [results]
    labels = list(labels) if labels is not None else [_label(r) for r in results]
    num_col, th_col, ylabel = QUANTITIES[quantity]
    if ax is None:
        _, ax = plt.subplots()
    for i, r in enumerate(results):
        color = f"C{i % 10}"
        idx = _thin(len(r), every, loglog)
        xs = r[x][idx]
        label = labels[i] if i < len(labels) else None
        if curves in ("both", "theory") and th_col in r:
            ax.plot(xs, r[th_col][idx], "o", mfc="none", color=color,
                    label=f"{label} (theory)" if curves == "both" else label)
        if curves in ("both", "numerics") and num_col in r:
            ax.plot(xs, r[num_col][idx], "o", ms=3, color=color,
                    label=f"{label} (numerics)" if curves == "both" else label)
    if loglog:
        ax.set_xscale("log")
        ax.set_yscale("log")
    ax.set_xlabel(axis_label(COLUMN_LABELS.get(x, x), x, results))
    drawn = num_col if curves != "theory" and any(num_col in r for r in results) else th_col
    ax.set_ylabel(axis_label(ylabel, drawn, results))
    ax.legend(fontsize="small")
    return ax
