"""The exception hierarchy of linkwork.

Every error linkwork raises on purpose derives from :class:`LinkworkError` and from the builtin
that matches its meaning, so callers can catch either ``LinkworkError`` or, say, ``ValueError``.
Messages name the parameter, its value and the limit, or the crank-angle ranges where a mechanism
cannot be assembled.

Argument checks (``require_*``) live in :mod:`linkwork.checks`; their former names here still
work, with a DeprecationWarning.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "AssemblyError",
    "ConvergenceError",
    "DriveError",
    "FileFormatError",
    "InfeasibleError",
    "LinkworkError",
    "MissingExtraError",
    "ParameterError",
    "StallError",
    "StructureError",
    "angle_ranges",
    "format_angle_ranges",
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


class DriveError(LinkworkError, ValueError):
    """A motor cannot drive a machine as asked: it cannot carry the mean load at any stable
    speed, the crank stops within a cycle or during start-up, or no flywheel reaches the
    speed fluctuation asked. The message names the value and the limit it exceeds."""


class StallError(DriveError):
    """The crank stops: the motor cannot carry the machine over its peak load with the inertia
    it has (within a cycle, or during start-up). The message names where and the torques."""


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


class ExternalToolError(LinkworkError, RuntimeError):
    """An external program linkwork runs (ffmpeg, for an MP4) failed; the message names it and
    the last line it printed."""

class MissingExtraError(LinkworkError, ImportError):
    """An optional dependency is not installed; the message names the install command.

    ``what`` needs ``package``, installed by ``install`` (e.g. ``pip install 'linkwork[dask]'``).
    """

    def __init__(self, what: str, package: str, install: str) -> None:
        self.what = what
        self.package = package
        self.install = install
        super().__init__(f"{what} needs {package}: {install}", name=package)


def _fmt(value: Any) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, float | np.floating):
        return f"{float(value):.6g}"
    if isinstance(value, np.ndarray) and value.size == 1 and value.dtype.kind in "iuf":
        return f"{float(value.reshape(())):.6g}"
    return repr(value)


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


_MOVED_TO_CHECKS = frozenset({"require_finite", "require_positive", "require_in_range", "py_float",
                              "all_finite", "common_shape", "shapes_error"})


def __getattr__(name: str) -> Any:
    """The argument checks that lived here before :mod:`linkwork.checks` (deprecated)."""
    if name in _MOVED_TO_CHECKS:
        import linkwork.checks  # the one deprecated upward edge (ignored by import-linter)
        from linkwork.deprecation import warn_renamed

        warn_renamed(f"linkwork.errors.{name}", f"linkwork.checks.{name}")
        return getattr(linkwork.checks, name)
    raise AttributeError(f"module 'linkwork.errors' has no attribute {name!r}")
