"""The one number format of every table linkwork shows: printed, in reports and notebooks.

:func:`fmt` prints a value to a number of significant digits (or of decimals), prints
round-off as 0 and an undefined value (NaN) as ``-``. Round-off is a value whose magnitude is
below :data:`ROUND_OFF` times the scale of its quantity (e.g. the mean driving torque over a
closed cycle, 2.2e-16 N·m against a peak of 3.5 N·m, or the out-of-plane force of a planar
mechanism's joint, -7e-14 N against reactions of 80 N). The caller gives the scale: the largest
magnitude over the cycle of the quantities printed in the same unit. Only printing rounds:
CSV and JSON files keep every value at full precision (see ``docs/conventions.md``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["ROUND_OFF", "UNDEFINED", "fmt", "scale_of", "unit_label"]

#: A printed value whose magnitude is below this fraction of its quantity's scale is round-off
#: and prints as 0 (double precision carries about 16 digits; the tables show 4 or 5, and the
#: computations lose a few digits to cancellation; 1e-9 leaves a margin on both sides).
ROUND_OFF = 1e-9

#: How a value undefined at a position (NaN, e.g. 0/0) prints.
UNDEFINED = "-"


def fmt(value: Any, scale: float = 0.0, digits: int = 4, *, decimals: int | None = None
        ) -> str:
    """``value`` as printed in a table.

    Parameters
    ----------
    value : float
        The number (a Python or NumPy scalar).
    scale : float
        The scale of its quantity (the largest magnitude of the quantities of the same unit
        over the cycle); ``|value| < ROUND_OFF * |scale|`` prints as 0. 0: no round-off test.
    digits : int
        Significant digits (``format(value, ".{digits}g")``).
    decimals : int, optional
        Fixed decimals instead (``round`` then ``.{decimals}f``), e.g. ``0.000``.

    Returns
    -------
    str
        ``-`` for NaN (undefined); never ``-0``.
    """
    v = float(value)
    if math.isnan(v):
        return UNDEFINED
    if abs(v) < ROUND_OFF * abs(scale):
        v = 0.0
    if decimals is not None:
        return f"{round(v, decimals) + 0.0:.{decimals}f}"  # + 0.0: -0.0 -> 0.0
    return f"{v + 0.0:.{digits}g}"


def scale_of(*values: Any) -> float:
    """The scale of a quantity: the largest finite magnitude among ``values`` (numbers or
    arrays of any shape), 0 if there is none."""
    best = 0.0
    for v in values:
        arr = np.abs(np.asarray(v, dtype=float))
        arr = arr[np.isfinite(arr)]
        if arr.size:
            best = max(best, float(arr.max()))
    return best


def unit_label(unit: str) -> str:
    """A unit as printed in the tables: ``N*m`` -> ``N·m`` (files keep the SI strings of the
    results' ``units``, ``N*m``; see ``docs/conventions.md``)."""
    return unit.replace("*", "·")
