# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.simulate(progress=True): the progress of a long run on stderr.

The extension calls a run's progress callable with (granules passed, target
granule, t, granules per second of wall time) every 0.1 s while the
integration runs, from the thread running it, the GIL held, and once more
where the run ended (_core.c, report_progress).  Bar is that callable for
``progress=True``: as the driver's progress line, it shows only where
someone watches, stderr a terminal or a notebook's, and only once a run has
lasted DELAY seconds, so that the many short runs of a loop draw nothing;
it draws a tqdm bar when tqdm is installed, else one line rewritten in
place, and clears it when the run ends."""

from __future__ import annotations

import sys
import time

#: Seconds a run lasts before its bar shows.
DELAY = 0.5


def watched() -> bool:
    """stderr is a terminal, or the notebook's (ipykernel's stream)."""
    err = sys.stderr
    if err is None:
        return False
    try:
        if err.isatty():
            return True
    except (AttributeError, ValueError):
        return False
    return "ipykernel" in sys.modules


class Bar:
    """The callable a run of simulate(progress=True) is given."""

    __slots__ = ("start", "tqdm", "line")

    def __init__(self) -> None:
        self.start = time.monotonic()
        self.tqdm = None   # the tqdm bar, once shown
        self.line = 0      # the length of the plain line on screen

    def __call__(self, passed: int, target: int, t: float, rate: float) -> None:
        if self.tqdm is None and not self.line and time.monotonic() - self.start < DELAY:
            return
        if self.tqdm is None and not self.line:
            try:
                from tqdm.auto import tqdm
            except ImportError:
                tqdm = None
            if tqdm is not None:
                self.tqdm = tqdm(total=target, unit="granule", leave=False, file=sys.stderr,
                                 desc="taper", dynamic_ncols=True)
        if self.tqdm is not None:
            self.tqdm.update(passed - self.tqdm.n)
            self.tqdm.set_postfix_str(f"t = {t:.6g}", refresh=False)
            return
        text = f"\rtaper: granule {passed}/{target}  t = {t:.6g}  {rate:.3g} granules/s"
        sys.stderr.write(text + " " * max(0, self.line - len(text)))
        sys.stderr.flush()
        self.line = len(text)

    def close(self) -> None:
        """Clears the bar or the line, if one was drawn."""
        if self.tqdm is not None:
            self.tqdm.close()
            self.tqdm = None
        elif self.line:
            sys.stderr.write("\r" + " " * self.line + "\r")
            sys.stderr.flush()
            self.line = 0
