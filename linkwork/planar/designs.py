"""Designs in batches: a mechanism's numbers given as arrays over m designs.

Every number of a mechanism's description that is a dimension or a mass property -- a body's
points, centre of mass, mass, inertia and guess pose, a guide's or slot's angle and point, a
prismatic pair's relative angle, a group's assembly branch -- may be given as a number (the same
for every design) or as a 1-D array of m values, one per design. A mechanism with such arrays is
a **batch** of m designs of one structure (``Mechanism.n_designs`` is m; ``None`` for one
design): :func:`~linkwork.planar.kinematics.kinematics` and
:func:`~linkwork.planar.dynamics.inverse_dynamics` evaluate all of them in one call, with arrays
of shape ``(..., m, n)`` (designs, then positions last).

The solvers see one design at a time or a block of designs flattened with the positions: the
compiled plan (:class:`~linkwork.planar.structure.Plan`) is *picked* for a design (every array
replaced by its value there, a Python float: the one-design computation exactly) or for a block
of flattened (design, position) elements (every array replaced by its values at the elements'
designs: the same arithmetic, element by element). This module holds the checks of per-design
values and the picking.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Iterable
from typing import Any

import numpy as np

from linkwork.checks import require_finite
from linkwork.errors import ParameterError

__all__ = ["branch_value", "column", "count_designs", "design_point", "design_value",
           "is_batched", "pick", "pick_fields"]

Index = int | np.ndarray


def design_value(name: str, value: Any) -> Any:
    """A finite number as a Python float, or a 1-D array of finite numbers (one per design) as
    a read-only float array; raises ParameterError otherwise (naming the value)."""
    if type(value) is float or type(value) is int:
        v = float(value)
        if not math.isfinite(v):
            raise ParameterError(name, v, "must be finite")
        return v
    arr = require_finite(name, value)
    if arr.ndim == 0:
        return float(arr)
    if arr.ndim == 1 and arr.size:
        out = np.array(arr, dtype=float)
        out.flags.writeable = False
        return out
    raise ParameterError(name, arr.shape, "must be a single number or a 1-D array of numbers, "
                         "one per design")


def design_point(name: str, value: Any) -> tuple[Any, Any]:
    """A point ``(x, y)`` [m] whose coordinates are each a number or a 1-D array over the
    designs (:func:`design_value`); two Python floats for one design."""
    if type(value) is tuple and len(value) == 2 and type(value[0]) is float \
            and type(value[1]) is float and math.isfinite(value[0]) \
            and math.isfinite(value[1]):
        return value  # the common case: a checked point again
    try:
        n = len(value)
    except TypeError:
        n = -1
    if n != 2 or isinstance(value, str):
        raise ParameterError(name, value, "must be a pair (x, y) [m] of numbers or of arrays "
                             "over the designs")
    return design_value(f"{name}[0]", value[0]), design_value(f"{name}[1]", value[1])


def branch_value(name: str, value: Any) -> Any:
    """An assembly branch: +1 or -1 (a Python int), or a 1-D array of them, one per design (a
    read-only int array)."""
    if type(value) is int and (value == 1 or value == -1):
        return value
    if isinstance(value, np.ndarray | list | tuple) and np.ndim(value) == 1:
        arr = np.asarray(value)
        if arr.size and arr.dtype.kind in "iuf" and np.isin(arr, (1, -1)).all():
            out = arr.astype(np.int64)
            out.flags.writeable = False
            return out
        bad = arr[~np.isin(arr, (1, -1))] if arr.dtype.kind in "iuf" else arr
        raise ParameterError(name, bad.flat[0].item() if bad.size else value,
                             "must be +1 or -1 (per design: an array of them)")
    if isinstance(value, bool | str) or np.ndim(value) != 0 or value not in (1, -1):
        raise ParameterError(name, value, "must be +1 or -1")
    return int(value)


def is_batched(value: Any) -> bool:
    """Whether a checked value (or a tuple of them) varies over the designs."""
    if isinstance(value, np.ndarray):
        return True
    if isinstance(value, tuple):
        return any(is_batched(v) for v in value)
    return False


def count_designs(values: Iterable[tuple[str, Any]]) -> int | None:
    """The number of designs of checked values ``(name, value)`` (numbers, arrays over the
    designs, tuples of them): None if none is an array; a ParameterError naming two values of
    different lengths."""
    m: int | None = None
    first = ""
    for name, v in values:
        for arr in _arrays(v):
            if m is None:
                m, first = arr.shape[0], name
            elif arr.shape[0] != m:
                raise ParameterError(name, f"{arr.shape[0]} designs", f"must hold as many designs "
                                     f"as {first} ({m}): every per-design value has one entry "
                                     "per design")
    return m


def _arrays(v: Any) -> Iterable[np.ndarray]:
    if isinstance(v, np.ndarray):
        yield v
    elif isinstance(v, tuple):
        for x in v:
            yield from _arrays(x)


def pick(value: Any, index: Index) -> Any:
    """``value`` at the designs ``index``: an array over the designs becomes its value at a
    design (a Python float, for an int ``index``) or its values at the designs of an index
    array; tuples are picked element by element; anything else is returned as it is."""
    if isinstance(value, np.ndarray):
        if isinstance(index, int):
            return float(value[index])
        return value[index]
    if type(value) is tuple and any(is_batched(v) for v in value):
        return tuple(pick(v, index) for v in value)
    return value


def pick_fields(obj: Any, index: Index) -> Any:
    """A shallow copy of the frozen dataclass ``obj`` whose fields that vary over the designs
    are picked at ``index`` (no validation again: the values were checked as given)."""
    changed = {f.name: pick(getattr(obj, f.name), index) for f in dataclasses.fields(obj)
               if is_batched(getattr(obj, f.name))}
    if not changed:
        return obj
    out = copy.copy(obj)
    for k, v in changed.items():
        object.__setattr__(out, k, v)
    return out


def column(value: Any) -> Any:
    """An array over the designs as a column ``(m, 1)`` (against arrays ``(m, n)`` of a batch's
    positions); a number as it is."""
    return value[:, None] if isinstance(value, np.ndarray) and value.ndim == 1 else value
