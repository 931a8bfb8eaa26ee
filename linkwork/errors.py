"""The exception hierarchy of linkwork.

Every error linkwork raises on purpose derives from :class:`LinkworkError` and from the builtin
that matches its meaning, so callers can catch either ``LinkworkError`` or, say, ``ValueError``.
Messages name the parameter, its value and the limit, or the crank-angle ranges where a mechanism
cannot be assembled.

The ``require_*`` helpers are the one place where argument checks are written; models call them
instead of ``assert`` or ad-hoc ``if`` blocks.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "AssemblyError",
    "ConvergenceError",
    "FileFormatError",
    "InfeasibleError",
    "LinkworkError",
    "ParameterError",
    "StructureError",
    "angle_ranges",
    "format_angle_ranges",
    "require_finite",
    "require_in_range",
    "require_positive",
]


class LinkworkError(Exception):
    """Base class of every error raised by linkwork on purpose."""


class ParameterError(LinkworkError, ValueError):
    """A parameter value makes the request impossible.

    Parameters
    ----------
    parameter : str
        Name of the parameter, as in the call (``"lambda2"``, ``"alpha"``).
    value : object
        The offending value (a scalar, or the worst element of an array).
    limit : str
        The limit it violates, in words (``"must be > 0"``, ``">= |lambda_e| + 1 = 1.3"``).
    """

    def __init__(self, parameter: str, value: Any, limit: str, detail: str = "") -> None:
        self.parameter = parameter
        self.value = value
        self.limit = limit
        msg = f"{parameter} = {_fmt(value)} is invalid: {limit}"
        if detail:
            msg += f" ({detail})"
        super().__init__(msg)


class AssemblyError(LinkworkError, ValueError):
    """The mechanism cannot be assembled at some driver positions.

    Attributes
    ----------
    ranges : list of (float, float)
        Driver-position ranges [rad or m] where assembly fails (closed intervals of the sampled
        positions).
    """

    def __init__(self, message: str, ranges: Sequence[tuple[float, float]] = (),
                 driver: str = "phi1", unit: str = "rad") -> None:
        self.ranges = [(float(a), float(b)) for a, b in ranges]
        self.driver = driver
        if self.ranges:
            message += f"; cannot assemble at {driver} in {format_angle_ranges(self.ranges, unit)}"
        super().__init__(message)


class StructureError(LinkworkError, ValueError):
    """A mechanism description is structurally wrong (locked, under-driven, unsolvable group)."""


class FileFormatError(LinkworkError, ValueError):
    """A mechanism or study file is missing, unreadable or invalid.

    The message names the file, the key (dotted path) and the problem.
    """

    def __init__(self, file: str, key: str | None, problem: str) -> None:
        self.file = file
        self.key = key
        self.problem = problem
        where = f"{file}: {key}" if key else str(file)
        super().__init__(f"{where}: {problem}")


class ConvergenceError(LinkworkError, RuntimeError):
    """An iterative solve did not converge."""


class InfeasibleError(LinkworkError, ValueError):
    """A synthesis or optimisation request cannot be met.

    Attributes
    ----------
    constraint : str
        The constraint that cannot be met.
    closest : object
        The closest achievable value of that constraint's quantity.
    """

    def __init__(self, constraint: str, closest: Any, detail: str = "") -> None:
        self.constraint = constraint
        self.closest = closest
        msg = f"cannot satisfy {constraint}; closest achievable: {_fmt(closest)}"
        if detail:
            msg += f" ({detail})"
        super().__init__(msg)


def _fmt(value: Any) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, float | np.floating):
        return f"{float(value):.6g}"
    if isinstance(value, np.ndarray) and value.size == 1 and value.dtype.kind in "iuf":
        return f"{float(value.reshape(())):.6g}"
    return repr(value)


_INT_MAX = 2**1023  # Python ints of this size or more do not convert to float
_F64 = np.dtype(float)


def require_finite(name: str, value: ArrayLike) -> np.ndarray:
    """Return ``value`` as a float array, or raise :class:`ParameterError` if any is NaN/inf."""
    tp = type(value)
    if tp is np.ndarray and value.dtype is _F64:  # type: ignore[union-attr]
        if np.isfinite(value).all():  # the common case of arrays: no conversion, no copy
            return value  # type: ignore[return-value]
    elif tp is float or (tp is int and -_INT_MAX < value < _INT_MAX):  # type: ignore[operator]
        if math.isfinite(value):  # type: ignore[arg-type]
            return np.asarray(value, dtype=float)
        raise ParameterError(name, value, "must be finite")
    try:
        if value is None:  # np.asarray(None, dtype=float) is NaN
            raise TypeError
        kind = np.asarray(value).dtype.kind
        if kind not in "bc":  # True would be 1.0; a complex array would lose its imaginary part
            arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        if isinstance(value, int):  # an int beyond the float range
            raise ParameterError(name, value, "must be finite (beyond the float range)") from None
        raise ParameterError(name, value, "must be a number or an array of numbers") from None
    if kind in "bc":
        raise ParameterError(name, value, "must be a real number or an array of real numbers, "
                             f"not {'a boolean' if kind == 'b' else 'complex'}")
    if not np.isfinite(arr).all():
        raise ParameterError(name, arr[~np.isfinite(arr)].flat[0], "must be finite")
    return arr


def py_float(value: Any) -> float | None:
    """``value`` as a float if it is a Python float or an int within the float range, else None.

    For fast paths that check one design with plain comparisons and leave everything else
    (arrays, numpy scalars, strings, bad values) to the named checks of the general path.
    """
    tp = type(value)
    if tp is float:
        return value
    if tp is int and -_INT_MAX < value < _INT_MAX:
        return float(value)
    return None


_isfinite = np.isfinite
_and_reduce = np.logical_and.reduce


def all_finite(arr: np.ndarray) -> bool:
    """Whether every element of a float array is finite (no NaN, no inf); no checks of type."""
    return bool(_and_reduce(_isfinite(arr), axis=None))


def require_positive(name: str, value: ArrayLike, *, allow_zero: bool = False) -> np.ndarray:
    """Return ``value`` as a float array, or raise if any element is not > 0 (>= 0)."""
    tp = type(value)
    if (tp is float or (tp is int and -_INT_MAX < value < _INT_MAX)) and (  # type: ignore[operator]
            0 < value < math.inf or (allow_zero and value == 0)):  # type: ignore[operator]
        return np.asarray(value, dtype=float)
    arr = require_finite(name, value)
    bad = arr < 0 if allow_zero else arr <= 0
    if bad.any():
        limit = "must be >= 0" if allow_zero else "must be > 0"
        raise ParameterError(name, arr[bad].flat[0], limit)
    return arr


def shapes_error(shapes: dict[str, Any]) -> ParameterError:
    """The error for arguments whose shapes do not broadcast (``shapes``: name -> shape)."""
    return ParameterError("shapes", shapes, "must broadcast against each other (designs "
                          "(m, 1) against positions (n,))")


def common_shape(**arrays: np.ndarray) -> tuple[int, ...]:
    """The broadcast shape of ``arrays``, or a :func:`shapes_error` naming every shape."""
    try:
        return np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        raise shapes_error({k: a.shape for k, a in arrays.items()}) from None


def require_in_range(name: str, value: ArrayLike, lo: float | None = None, hi: float | None = None,
                     *, lo_open: bool = False, hi_open: bool = False, unit: str = "",
                     scale: float = 1.0) -> np.ndarray:
    """Return ``value`` as a float array, or raise if any element leaves [lo, hi].

    ``scale`` and ``unit`` only change how the message shows numbers (e.g. ``scale=180/pi``,
    ``unit="deg"`` for angles given in radians).
    """
    arr = require_finite(name, value)
    bad = np.zeros(arr.shape, dtype=bool)
    if lo is not None:
        bad |= arr <= lo if lo_open else arr < lo
    if hi is not None:
        bad |= arr >= hi if hi_open else arr > hi
    if bad.any():
        v = arr[bad].flat[0]
        lo_s = "-inf" if lo is None else f"{lo * scale:.6g}"
        hi_s = "inf" if hi is None else f"{hi * scale:.6g}"
        interval = f"{'(' if lo_open else '['}{lo_s}, {hi_s}{')' if hi_open else ']'}"
        shown = f"{v * scale:.6g}{(' ' + unit) if unit else ''}"
        suffix = f" {unit}" if unit else ""
        raise ParameterError(name, shown if unit else v, f"must lie in {interval}{suffix}")
    return arr


def angle_ranges(angles: ArrayLike, mask: ArrayLike) -> list[tuple[float, float]]:
    """Contiguous ranges of ``angles`` (1-D, ordered) where ``mask`` is true.

    ``mask`` may have more dimensions than ``angles`` (designs on the leading axes, positions on
    the last one); a position counts as bad if it is bad for any design.
    """
    a = np.asarray(angles, dtype=float).ravel()
    m: np.ndarray = np.asarray(mask, dtype=bool)
    if m.ndim > 1:  # positions on the last axis, designs before it
        m = np.asarray(m.reshape(-1, m.shape[-1]).any(axis=0))
    m = np.broadcast_to(m, a.shape)
    ranges: list[tuple[float, float]] = []
    start = None
    for i, bad in enumerate(m):
        if bad and start is None:
            start = i
        if not bad and start is not None:
            ranges.append((a[start], a[i - 1]))
            start = None
    if start is not None:
        ranges.append((a[start], a[-1]))
    return ranges


def format_angle_ranges(ranges: Sequence[tuple[float, float]], unit: str = "rad") -> str:
    """Format driver ranges for a message: angles in degrees, lengths as given."""
    rs = [(float(lo), float(hi)) for lo, hi in ranges]
    if unit == "rad" and len(rs) >= 2 and abs(rs[-1][1] - rs[0][0] - 2 * np.pi) < 1e-9:
        # the last range runs into the first across 0 = 360 deg: one range, e.g. [-30, 30 deg]
        rs = [(rs[-1][0] - 2 * np.pi, rs[0][1]), *rs[1:-1]]
    parts = []
    for lo, hi in rs[:8]:
        if unit == "rad":
            lo_s, hi_s = f"{np.degrees(lo):.4g}", f"{np.degrees(hi):.4g} deg"
        else:
            lo_s, hi_s = f"{lo:.6g}", f"{hi:.6g} {unit}"
        parts.append(hi_s if lo == hi else f"[{lo_s}, {hi_s}]")  # a single position
    more = f" and {len(rs) - 8} more" if len(rs) > 8 else ""
    return ", ".join(parts) + more
