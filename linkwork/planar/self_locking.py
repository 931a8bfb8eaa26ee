"""Self-locking as a working range over a design parameter.

:func:`~linkwork.planar.dynamics.inverse_dynamics` flags the positions of one mechanism where
friction locks it (``Dynamics.locked``: no finite driving load moves it there,
``docs/friction.md``). A designer asks the next question: over which values of a design
parameter (a slot's inclination, a guide's length, a friction coefficient, a crank radius) does
the mechanism run over its whole working cycle? :func:`working_range` answers it for any
parameter of any engine mechanism: it scans the parameter, then bisects every change between
"runs" and "does not run" down to a tolerance.

Paper 000's sine press is the reference: its inclined slot works only for
``rho1 + rho2 < alpha < 180 deg - (rho1 + rho2)`` (:func:`linkwork.models.sine.working_range`),
which this function reproduces from the engine to 1e-9 rad
(``tests/planar/test_self_locking.py``).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite, require_number
from linkwork.errors import ParameterError
from linkwork.planar.dynamics import inverse_dynamics
from linkwork.planar.kinematics import Kinematics, kinematics
from linkwork.planar.model import Mechanism

__all__ = ["MAX_SCAN", "WorkingRange", "working_range"]

#: scan points at most (each is a kinematic and kinetostatic analysis over the cycle)
MAX_SCAN = 10_000

Loads = Sequence[Any] | Callable[[Kinematics], Sequence[Any]]


@dataclass(frozen=True)
class WorkingRange:
    """Where a mechanism runs over its cycle, as a function of one design parameter.

    Attributes
    ----------
    intervals : list of (float, float)
        The parameter's intervals (low, high) in which the mechanism assembles at every
        position and self-locks at none; each limit found by bisection to ``tol`` (a limit
        equal to a bound of the search is that bound).
    values : ndarray (scan,)
        The scanned parameter values.
    locked : ndarray of int (scan,)
        Self-locking positions at each scanned value (``-1``: the mechanism does not
        assemble at some position there).
    kappa_min : ndarray (scan,)
        The smallest self-locking indicator ``kappa`` over the cycle at each scanned value
        (NaN where it does not assemble or locks): how close to locking it runs (1: no
        friction effect on the drive; towards 0: the driving load grows like ``1/kappa``).
    tol : float
        The bisection tolerance [the parameter's unit].
    evaluations : int
        Analyses over the cycle run (scan and bisection).
    """

    intervals: list[tuple[float, float]]
    values: np.ndarray
    locked: np.ndarray
    kappa_min: np.ndarray
    tol: float
    evaluations: int

    def runs(self, value: float) -> bool:
        """``value`` lies in one of the working intervals."""
        return any(a <= value <= b for a, b in self.intervals)


def working_range(make: Callable[[float], Mechanism], bounds: tuple[float, float],
                  phi1: ArrayLike, *, loads: Loads = (), gravity: ArrayLike | None = None,
                  omega1: ArrayLike | None = None, eps1: ArrayLike | None = None,
                  scan: int = 64, tol: float | None = None) -> WorkingRange:
    """The values of a design parameter for which a mechanism runs over its cycle.

    Parameters
    ----------
    make : callable
        ``make(p) -> Mechanism``: the mechanism for the parameter value ``p`` (its friction
        coefficients, geometry, ...). It may raise a :class:`~linkwork.errors.LinkworkError`
        for a value that gives no mechanism (counted as "does not run").
    bounds : (float, float)
        The search interval of the parameter, ``low < high``.
    phi1 : array_like
        The driver positions of the working cycle [rad, or m for a linear driver].
    loads : sequence or callable
        The loads (:class:`~linkwork.planar.PointForce`, :class:`~linkwork.planar.BodyTorque`)
        of :func:`~linkwork.planar.inverse_dynamics`, or ``loads(kin) -> sequence`` for loads
        that depend on the motion (a technological force against the slide's velocity).
    gravity, omega1, eps1
        As for :func:`~linkwork.planar.inverse_dynamics` / :func:`~linkwork.planar.kinematics`
        (``omega1`` default: the driver's own speed).
    scan : int
        Evenly spaced values scanned over ``bounds`` (2 to ``MAX_SCAN``); a working interval
        narrower than the scan's step may be missed.
    tol : float, optional
        Bisection tolerance of each limit [the parameter's unit]; default ``1e-9`` of the
        interval's width.

    Returns
    -------
    WorkingRange

    Examples
    --------
    The inclined slot of paper 000's sine press with f = 0.12 in the slot and 0.10 in the
    ram's guide runs for 12.553 deg < alpha < 167.447 deg (``tests/planar/test_self_locking.py``
    builds the mechanism ``make(alpha)`` and the load against the ram's motion).
    """
    lo = require_number("bounds[0]", bounds[0])
    hi = require_number("bounds[1]", bounds[1])
    if not (np.isfinite(lo) and np.isfinite(hi)) or not lo < hi:
        raise ParameterError("bounds", (lo, hi), "must be finite with low < high")
    n_scan = require_number("scan", scan)
    if n_scan != int(n_scan) or not 2 <= n_scan <= MAX_SCAN:
        raise ParameterError("scan", scan, f"must be an integer from 2 to {MAX_SCAN}")
    eps = 1e-9 * (hi - lo) if tol is None else require_number("tol", tol)
    if not eps > 0:
        raise ParameterError("tol", tol, "must be > 0")
    phi = require_finite("phi1", phi1)
    if phi.ndim != 1 or phi.size == 0:
        raise ParameterError("phi1", phi1, "must be a 1-D array of driver positions")
    count = [0]

    def state(p: float) -> tuple[int, float]:
        """(locked positions or -1 if it does not assemble or build, smallest kappa)."""
        count[0] += 1
        try:
            mech = make(p)
        except ValueError:  # the parameter gives no mechanism: it does not run
            return -1, float("nan")
        kin = kinematics(mech, phi, omega1=omega1, eps1=eps1, on_failure="nan")
        if not np.all(kin.valid):
            return -1, float("nan")
        dyn = inverse_dynamics(kin, gravity=gravity,
                               loads=loads(kin) if callable(loads) else loads)
        k = int(np.sum(dyn.locked))
        return k, float(np.min(dyn.kappa)) if k == 0 else float("nan")

    values = np.linspace(lo, hi, int(n_scan))
    states = [state(float(p)) for p in values]
    locked = np.array([s[0] for s in states])
    kappa = np.array([s[1] for s in states])
    ok = locked == 0
    limits: list[float] = []
    for i in range(len(values) - 1):
        if ok[i] != ok[i + 1]:
            a, b = float(values[i]), float(values[i + 1])
            runs_a = bool(ok[i])
            while b - a > eps:
                m = 0.5 * (a + b)
                if not a < m < b:  # adjacent floats: a tol below their spacing is reached
                    break
                if (state(m)[0] == 0) == runs_a:
                    a = m
                else:
                    b = m
            limits.append(0.5 * (a + b))
    # the working intervals: from each change (or a bound) where it starts to run to the next
    edges = [lo, *limits, hi]
    running = bool(ok[0])
    intervals = []
    for a, b in itertools.pairwise(edges):
        if running:
            intervals.append((a, b))
        running = not running
    return WorkingRange(intervals, values, locked, kappa, eps, count[0])
