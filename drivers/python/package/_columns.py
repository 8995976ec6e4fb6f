# SPDX-License-Identifier: GPL-3.0-or-later
"""Per-granule columns read as attributes or items: what Chain and Result
share (one place for the access rules)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Dict, Iterator, List, Tuple

if TYPE_CHECKING:
    import numpy


class _Numpy:
    """numpy, imported when first used (``np.array_equal`` ...), so that
    ``import taper`` does not import it: numpy's import is most of the
    package's (docs/python.md, "Overheads")."""

    __slots__ = ()

    def __getattr__(self, name: str):
        import numpy
        return getattr(numpy, name)


np = _Numpy()


class Columns:
    """Numpy columns of length N, granule k at index k-1, in ``self._columns``
    (set by the subclass), read as ``obj.name`` or ``obj["name"]``."""

    _columns: Dict[str, "numpy.ndarray"]

    @property
    def columns(self) -> Tuple[str, ...]:
        """The names of the columns, in order."""
        return tuple(self._columns)

    def __getitem__(self, name: str) -> "numpy.ndarray":
        return self._columns[name]

    def __getattr__(self, name: str) -> "numpy.ndarray":
        columns = self.__dict__.get("_columns")
        if columns is not None and name in columns:
            return columns[name]
        raise AttributeError(f"{type(self).__name__} has no column or attribute {name!r}")

    def __contains__(self, name: object) -> bool:
        return name in self._columns

    def __iter__(self) -> Iterator[str]:
        return iter(self._columns)

    def __len__(self) -> int:
        """N, the number of granules."""
        return len(self._columns["k"]) if "k" in self._columns else 0

    @property
    def n_granules(self) -> int:
        return len(self)

    def __dir__(self) -> List[str]:
        return sorted(set(super().__dir__()) | set(self._columns))
