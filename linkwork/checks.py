"""Argument checks: the one module where linkwork checks what a caller passed.

Each check returns the value in the form the computation needs (a float array, a Python float,
an int branch) or raises :class:`~linkwork.errors.ParameterError` naming the parameter, its value
and the limit. Checked public functions call them at their boundary; kernels do not check again
(``docs/architecture.md``). For one design given in Python numbers the checks cost plain
comparisons and return Python floats (:func:`finite_value`, :func:`positive_value`,
:func:`require_branch`), so that closed forms called in tight loops check each argument once,
without a second "fast path" of their own; :func:`py_float` and :func:`all_finite` are the
plain-comparison pieces.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.errors import ParameterError

__all__ = [
    "all_finite",
    "common_shape",
    "finite_value",
    "per_position",
    "positive_value",
    "py_float",
    "require_branch",
    "require_finite",
    "require_in_range",
    "require_number",
    "require_pair",
    "require_point",
    "require_positive",
    "shapes_error",
]


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


def finite_value(name: str, value: Any) -> Any:
    """A finite number: a Python float for a Python int or float (what fast kernels take), else
    a float array (:func:`require_finite`)."""
    if type(value) is float or type(value) is int:
        if value != value or value in (math.inf, -math.inf):
            raise ParameterError(name, float(value), "must be finite")
        return float(value)
    return require_finite(name, value)


def positive_value(name: str, value: Any) -> Any:
    """A finite number > 0 (a length): a Python float for a Python int or float, else a float
    array (:func:`require_positive`)."""
    if type(value) is float or type(value) is int:
        if not (value > 0.0 and value != math.inf):  # also rejects NaN
            if value != value or value == math.inf:
                raise ParameterError(name, float(value), "must be finite")
            raise ParameterError(name, float(value), "must be > 0")
        return float(value)
    arr = require_finite(name, value)
    bad = arr <= 0.0
    if bad.any():
        raise ParameterError(name, arr[bad].flat[0], "must be > 0")
    return arr


def require_number(name: str, value: Any) -> float:
    """``value`` as a finite Python float (a single number, not an array)."""
    arr = require_finite(name, value)
    if arr.ndim:
        raise ParameterError(name, value, "must be a single number")
    return float(arr)


def require_point(name: str, value: Any) -> tuple[float, float]:
    """A point ``(x, y)`` [m] as two finite Python floats."""
    try:
        x, y = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, "must be a pair of numbers (x, y) [m]") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ParameterError(name, value, "must be finite")
    return (x, y)


def require_pair(name: str, value: Any) -> tuple[Any, Any]:
    """A pair ``(x, y)`` of finite numbers or arrays (:func:`finite_value` each, named
    ``name[0]``, ``name[1]``)."""
    try:
        n = len(value)
    except TypeError:
        n = -1
    if n != 2:
        raise ParameterError(name, value, "must be a pair (x, y)")
    return finite_value(name + "[0]", value[0]), finite_value(name + "[1]", value[1])


def require_branch(branch: Any, name: str = "branch") -> int:
    """An assembly branch: +1 or -1, one per call (an array, a string or a bool is named)."""
    if type(branch) is int and (branch == 1 or branch == -1):
        return branch
    if (np.ndim(branch) != 0 or isinstance(branch, str | bool)
            or branch not in (1, -1)):
        raise ParameterError(name, branch, "must be +1 or -1 (one branch per call)")
    return int(branch)


def per_position(name: str, value: ArrayLike, n: int) -> np.ndarray:
    """A finite scalar or an array of ``n`` values, as a float array of shape ``(n,)`` (e.g. a
    crank speed given once or per position)."""
    a = require_finite(name, value)
    try:
        return np.broadcast_to(a, (n,)).astype(float)
    except ValueError:
        raise ParameterError(name, a.shape, f"must be a scalar or have shape ({n},)") from None
