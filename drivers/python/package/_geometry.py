# SPDX-License-Identifier: GPL-3.0-or-later
"""From the radii of a chain's ends to the paper's tapering parameter, and
back: taper.taper_from_radii(), taper.radii_from_taper().

The analytic profiles of arXiv:0905.4512 have R_1 = 1 (granule 1's radius
is the unit of length) and

    backward_linear       R_k = 1 + S (k-1)      (Sec. III A)
    forward_linear        R_k = 1 - S (k-1)      (Sec. IV A; N < 1 + 1/S)
    backward_exponential  R_k = (1-q)^(1-k)      (Sec. III B; q < 1)
    forward_exponential   R_k = (1+q)^(1-k)      (Sec. IV B)

so the ratio of the last radius to the first, R_N / R_1, gives S or q.
Both helpers check what they compute with the scene's own validation
(taper._core.check: the same ranges and messages as simulate() and a scene
file), and compute R_N as the library does (src/chain/chain.c)."""

from __future__ import annotations

import math

from . import _core

__all__ = ["taper_from_radii", "radii_from_taper", "TAPERED_PROFILES"]

#: The profiles with a tapering parameter, and its name.
TAPERED_PROFILES = {"backward_linear": "s", "forward_linear": "s",
                    "backward_exponential": "q", "forward_exponential": "q"}


def _refuse(field: str, message: str) -> None:
    error = _core.InvalidArgumentError(f"{field}: {message}")
    error.status, error.field, error.message = "invalid", field, message
    raise error


def _parameter_of(profile: str, n_granules: int) -> str:
    """The profile's parameter name, after the scene has checked profile
    and n_granules (InvalidArgumentError / TypeError as simulate())."""
    _core.check(n_granules=n_granules)
    name = TAPERED_PROFILES.get(profile) if isinstance(profile, str) else None
    if name is None:
        if not (isinstance(profile, str) and profile in _core.PROFILES):
            _core.check(profile=profile)  # the scene's own TypeError or InvalidArgumentError
        _refuse("profile", f"profile = {profile!r} has no tapering parameter: use one of "
                + ", ".join(repr(p) for p in TAPERED_PROFILES))
    return name


def _radius(field: str, value: float) -> float:
    if isinstance(value, (bool, str, bytes, complex)) or not hasattr(value, "__float__"):
        raise TypeError(f"{field} must be a real number, not {type(value).__name__}")
    x = float(value)
    if not (x > 0 and math.isfinite(x)):
        _refuse(field, f"{field} = {x!r}: a radius must be positive and finite")
    return x


def taper_from_radii(profile: str, first: float, last: float, n_granules: int) -> float:
    """The tapering parameter (``s`` of the linear profiles, ``q`` of the
    exponential ones) that gives a chain of `n_granules` granules of the
    `profile` the radii `first` (granule 1) and `last` (granule N), in any
    one unit: only last/first matters, since R_1 is the unit of length.

        s = taper.taper_from_radii("backward_linear", 2e-3, 8e-3, 50)   # 3/49
        r = taper.simulate(profile="backward_linear", s=s, n_granules=50)
        # with &material, granule 1's radius is radius= (SI): radius=2e-3

    Backward profiles grow (last > first), forward ones shrink.  The value
    is checked as a keyword of simulate() is (the scene's ranges, and
    forward_linear's N < 1 + 1/S); the library refuses, when it builds the
    chain, masses m_k = R_k^3 beyond double precision (taper.chain() says
    so).

    Raises:
        TypeError: a value of the wrong Python type.
        InvalidArgumentError: a profile without tapering parameter, radii
            not positive and finite, radii that shrink along a backward
            profile (or grow along a forward one), or an `s` or `q` the
            scene refuses (``field`` names the argument at fault).
    """
    name = _parameter_of(profile, n_granules)
    ratio = _radius("last", last) / _radius("first", first)
    backward = profile.startswith("backward")
    if (ratio <= 1.0) if backward else (ratio >= 1.0):
        _refuse("last", f"{profile} radii {'grow' if backward else 'shrink'} along the chain: "
                f"last = {last!r} must be {'larger' if backward else 'smaller'} than first = "
                f"{first!r} (equal radii: profile = 'monodisperse'; the other direction: "
                f"{'forward' if backward else 'backward'}{profile[profile.index('_'):]})")
    km1 = n_granules - 1
    if profile == "backward_linear":          # R_N = 1 + S (N-1)
        value = (ratio - 1.0) / km1
    elif profile == "forward_linear":         # R_N = 1 - S (N-1)
        value = (1.0 - ratio) / km1
    elif profile == "backward_exponential":   # R_N = (1-q)^(1-N)
        value = -math.expm1(-math.log(ratio) / km1)
    else:                                     # R_N = (1+q)^(1-N)
        value = math.expm1(-math.log(ratio) / km1)
    try:
        _core.check(profile=profile, n_granules=n_granules, **{name: value})
    except _core.InvalidArgumentError as e:
        _refuse(e.field or name, f"last/first = {ratio!r} over {n_granules} granules needs "
                f"{name} = {value!r}: {e.message}")
    return value


def radii_from_taper(profile: str, value: float, n_granules: int,
                     first: float = 1.0) -> tuple[float, float]:
    """The radii ``(first, last)`` of granules 1 and N of a chain of the
    `profile` with tapering parameter `value` (its ``s`` or ``q``):
    the inverse of taper_from_radii, `first` the radius of granule 1 in
    the unit you want (1: the paper's rescaled unit).  The values are
    checked as keywords of simulate() are; R_N is computed as the library
    computes it (so last == taper.chain(...).R[-1] * first).

    Raises:
        TypeError, InvalidArgumentError: as taper_from_radii.
    """
    name = _parameter_of(profile, n_granules)
    first = _radius("first", first)
    _core.check(profile=profile, n_granules=n_granules, **{name: value})
    km1 = float(n_granules - 1)
    if profile == "backward_linear":
        last = 1.0 + value * km1
    elif profile == "forward_linear":
        last = 1.0 - value * km1
    elif profile == "backward_exponential":
        last = math.exp(-km1 * math.log1p(-value))
    else:
        last = math.exp(-km1 * math.log1p(value))
    return first, first * last
