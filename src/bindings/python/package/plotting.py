"""taper.plotting -- the driver's figures with matplotlib (optional:
``pip install taper[plot]``).

The driver draws, per run, the theory as open circles and the numerics as
filled circles of one colour (share/scenes/paper/figure*.nml).  plot() does
the same for a Result or a list of them (a sweep):

    quantity  numerics    theory     against k
    "v"       v_peak      theory_v   pulse amplitude (Fig. 1)
    "T_res"   T_res       theory_T   residence time
    "t"       t_pass      theory_t   time the pulse passes k
"""

from __future__ import annotations

from typing import Any, Iterable, Optional, Sequence, Union

from .result import Result

__all__ = ["plot", "QUANTITIES"]

#: quantity -> (numerics column, theory column, axis label)
QUANTITIES = {
    "v": ("v_peak", "theory_v", "v"),
    "T_res": ("T_res", "theory_T", "T"),
    "t": ("t_pass", "theory_t", "t"),
}


def _label(r: Result) -> str:
    s = r.settings
    profile = s.get("profile", "")
    if "linear" in profile:
        return f"S = {s.get('s'):g}"
    if "exponential" in profile:
        return f"q = {s.get('q'):g}"
    return profile or r.source


def plot(results: Union[Result, Sequence[Result]], quantity: str = "v", *, ax: Any = None,
         x: str = "k", curves: str = "both", loglog: bool = True, every: int = 1,
         labels: Optional[Iterable[str]] = None) -> Any:
    """Draws `quantity` ("v", "T_res" or "t") against `x` (a column, "k" by
    default) for each result: numerics filled, theory open circles.

    curves: "both", "theory" or "numerics"; every: draw every n-th granule;
    loglog: logarithmic axes; labels: one legend entry per result (default:
    the swept parameter).  Returns the matplotlib Axes.
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
        xs = r[x][::every]
        label = labels[i] if i < len(labels) else None
        if curves in ("both", "theory") and th_col in r:
            ax.plot(xs, r[th_col][::every], "o", mfc="none", color=color,
                    label=f"{label} (theory)" if curves == "both" else label)
        if curves in ("both", "numerics") and num_col in r:
            ax.plot(xs, r[num_col][::every], "o", ms=3, color=color,
                    label=f"{label} (numerics)" if curves == "both" else label)
    if loglog:
        ax.set_xscale("log")
        ax.set_yscale("log")
    ax.set_xlabel(x)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize="small")
    return ax
