"""taper.chain(): a chain's geometry as the library builds it, with the
reduced masses of its binary collisions (no theory times, no integration)."""

from __future__ import annotations

from typing import Any, Dict, Mapping, Optional, Sequence, Union

import numpy as np

from . import _core
from ._columns import Columns

__all__ = ["Chain", "chain", "CHAIN_COLUMNS"]

#: The columns of a Chain, in order.
CHAIN_COLUMNS = ("k", "R", "m", "X0", "r", "mu")

Real = Union[int, float]


class Chain(Columns):
    """A chain as taper_chain_alloc builds it.

    Columns (numpy arrays of length N, granule k at index k-1): ``k``
    (int64), ``R`` (radii R_k), ``m`` (masses m_k = R_k^3), ``X0`` (rest
    positions, X0(1) = 0), ``r`` (contact factors r_k =
    (2 R_k R_{k+1}/(R_k + R_{k+1}))^(1/2) of the pair (k, k+1)) and ``mu``
    (reduced masses mu_k = m_k m_{k+1}/(m_k + m_{k+1}), taper_theory_compute).
    ``r`` and ``mu`` belong to pairs: their last entry is NaN.  Read them as
    attributes (``c.mu``) or items (``c["mu"]``).

    Attributes:
        profile: the profile's name (one of taper.PROFILES).
        exponent: the contact exponent n.
        settings: the chain settings, every default filled in.
    """

    def __init__(self, columns: Mapping[str, np.ndarray], *, profile: str, exponent: float,
                 settings: Optional[Dict[str, Any]] = None) -> None:
        self._columns: Dict[str, np.ndarray] = {c: columns[c] for c in CHAIN_COLUMNS}
        self.profile = profile
        self.exponent = float(exponent)
        self.settings: Dict[str, Any] = dict(settings or {})

    def __repr__(self) -> str:
        return f"<taper.Chain {self.profile} N={len(self)} exponent={self.exponent:g}>"


def chain(*, profile: Optional[str] = None, s: Optional[Real] = None, q: Optional[Real] = None,
          n_granules: Optional[int] = None, exponent: Optional[Real] = None,
          radii: Optional[Sequence[float]] = None) -> Chain:
    """Builds a chain and returns its columns ``k R m X0 r mu`` (see Chain).
    Keywords as for taper.simulate()'s chain settings, each passed to the
    setter of its name; left out (or None): the library's default.

    Raises:
        InvalidArgumentError: a value or combination the library refuses
            (``.field`` names the argument), or a chain whose masses or
            theory leave double precision.
        TypeError: an argument of the wrong type (named).
    """
    kw = {k: v for k, v in dict(profile=profile, s=s, q=q, n_granules=n_granules,
                                exponent=exponent, radii=radii).items() if v is not None}
    d = _core.chain(**kw)
    return Chain(d["columns"], profile=d["profile"], exponent=d["exponent"],
                 settings=d["settings"])
