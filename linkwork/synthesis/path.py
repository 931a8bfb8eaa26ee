r"""Path generation by a four-bar coupler point: global search, refinement, defect-free designs.

:func:`path` finds four-bars whose coupler point passes through target points, with or without
prescribed timing (the crank angles at the points), for open and closed paths, in the
literature's parametrisation (:mod:`linkwork.synthesis.design`: ``r1 r2 r3 r4 rcx rcy x0 y0
theta0 theta2``). The objective is the literature's [1]_ [2]_: the sum of squared distances
between the coupler point and the targets (optionally judged by forces as well,
:mod:`linkwork.synthesis.forces`).

Method
------
1. **Global search.** A scrambled Sobol sample of the free parameters within ``bounds`` (both
   assembly branches) is screened by the closed form broadcast over designs x crank angles, in
   chunks of bounded memory through :func:`linkwork.sweep.evaluate` (in-process or on a
   dask.distributed cluster); each chunk keeps only its best candidates. With free timing the
   coupler curve of each candidate is sampled at ``n_samples`` crank angles and the points are
   assigned to samples by dynamic programming in the task's order (in either direction of
   rotation, never across a position where the linkage cannot be assembled): the error of the
   best ordered timing on that curve. Candidates that cannot be defect-free (not a crank-rocker
   where one is asked, transmission angle below the limit over the turn, a point that cannot
   be assembled) are rejected and counted per defect.
2. **Refinement.** From the best distinct candidates, SciPy's ``least_squares`` (trust-region
   reflective, bounds) minimises the exact residuals (coupler point minus target, ``2 n``
   values) over the free parameters and, without timing, over the first crank angle and the
   non-negative increments between consecutive points (so the order cannot change); the
   constraints enter as penalty residuals that are zero where they hold.
3. **Defect checks.** Every refined design is checked (:func:`check_design`): each point
   assembles on the design's branch, the points come in the task's order within one turn
   (cyclically for a closed path), the engine tracked densely between consecutive points
   assembles everywhere on that branch (no toggle is passed: no branch defect) and gives the
   same coupler point at the targets (same circuit), the crank turns fully where asked
   (Grashof crank-rocker, ``r2`` the crank) and the transmission angle stays above the limit
   over the range the design runs. A defective design is never returned; how many were
   rejected for which defect is reported in the result.

References
----------
.. [1] Cabrera et al. 2002 and .. [2] Acharyya & Mandal 2009, as cited in
   :mod:`linkwork.synthesis.design`.
"""

from __future__ import annotations

import functools
import math
import sys
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite
from linkwork.errors import InfeasibleError, ParameterError
from linkwork.planar.kinematics import kinematics
from linkwork.sweep import Generated, check_client, evaluate, rich_progress
from linkwork.synthesis.design import (
    PARAMS,
    FourbarDesign,
    SynthesisResult,
    _kernel_jacobian,
    coupler_point,
)
from linkwork.synthesis.design import _kernel as _kernel
from linkwork.synthesis.forces import ForceModel, Objective, force_metrics, judge

__all__ = ["CONSTRAINTS", "DEFECTS", "MAX_CANDIDATES", "PathTask", "check_design",
           "coupler_point", "path", "task"]

TWO_PI = 2.0 * math.pi

#: Constraint names :func:`path` knows (a minimum transmission angle is given as
#: ``("transmission", angle [rad])``).
CONSTRAINTS = ("grashof", "order", "transmission")

#: Defects a candidate or a refined design is rejected for (keys of ``SynthesisResult.rejected``).
DEFECTS = ("assembly", "grashof", "transmission", "order", "branch", "circuit", "bounds")

#: Largest global sample (candidates): the screening keeps only the best of each chunk, so the
#: memory is bounded by the chunk, but the time grows with it (about 10 us per candidate and
#: target point on one core).
MAX_CANDIDATES = 2**22


# ---------------------------------------------------------------------------------------------
# the task
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PathTask:
    """A path-generation task, checked (SI, radians); built by :func:`task`."""

    points: np.ndarray
    timing: np.ndarray | None
    closed: bool
    lo: np.ndarray
    hi: np.ndarray
    theta2_bounds: tuple[float, float] | None
    grashof: bool
    order: bool
    mu_min: float | None
    scale: float
    free_start: bool = False
    #: Where ``theta0`` is in the parameter vector (8 of :data:`PARAMS`; the six-bar's 6).
    theta0_index: int = 8

    @property
    def free(self) -> np.ndarray:
        """Which of :data:`PARAMS` are free (the others fixed at ``lo == hi``)."""
        return self.hi > self.lo

    @property
    def n(self) -> int:
        return len(self.points)

    @property
    def theta0_periodic(self) -> bool:
        """The bounds of ``theta0`` span a full turn: it is searched as the angle it is (the
        refinement does not stop at 0 or 2 pi), and returned within the bounds."""
        i = self.theta0_index
        return bool(self.hi[i] - self.lo[i] >= TWO_PI * (1 - 1e-12))

    def angles(self, start: np.ndarray | float) -> np.ndarray:
        """Crank angles at the points of a task with timing, for the first crank angle
        ``start`` ((m,) -> (m, n)): the timing itself, or with :attr:`free_start` its advances
        from ``start``."""
        assert self.timing is not None
        if not self.free_start:
            return np.broadcast_to(self.timing, (*np.shape(start), self.n))
        return np.asarray(start)[..., None] + (self.timing - self.timing[0])

    def constraint_names(self) -> tuple[str, ...]:
        out = [k for k, on in (("grashof", self.grashof), ("order", self.order)) if on]
        if self.mu_min is not None:
            out.append(f"transmission >= {math.degrees(self.mu_min):.4g} deg")
        return tuple(out)


def default_bounds(points: np.ndarray) -> dict[str, tuple[float, float]]:
    """Search bounds from the targets: link lengths from 2 % to 3 times the size ``L`` of the
    points' bounding box, coupler point within +-3 L, crank pivot within 3 L of the points'
    centre, any frame angle."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    L = float(np.hypot(*(hi - lo)))
    c = (lo + hi) / 2
    b = {k: (0.02 * L, 3.0 * L) for k in ("r1", "r2", "r3", "r4")}
    b |= {"rcx": (-3.0 * L, 3.0 * L), "rcy": (-3.0 * L, 3.0 * L),
          "x0": (c[0] - 3.0 * L, c[0] + 3.0 * L), "y0": (c[1] - 3.0 * L, c[1] + 3.0 * L),
          "theta0": (0.0, TWO_PI)}
    return b


def _parse_constraints(constraints: Any) -> tuple[bool, bool, float | None]:
    if constraints is None:
        return False, False, None
    if isinstance(constraints, str):
        constraints = (constraints,)
    items = list(constraints.items()) if isinstance(constraints, Mapping) else [
        (c, True) if isinstance(c, str) else tuple(c) for c in constraints]
    grashof = order = False
    mu: float | None = None
    for item in items:
        if len(item) != 2:
            raise ParameterError("constraints", item, 'items are "grashof", "order" or '
                                 '("transmission", minimum angle [rad])')
        name, val = item
        if name == "grashof":
            grashof = bool(val)
        elif name == "order":
            order = bool(val)
        elif name == "transmission":
            if val is None or val is False:
                continue
            mu = float(val)
            if not 0.0 < mu < math.pi / 2:
                raise ParameterError("constraints.transmission", val,
                                     "must be a minimum transmission angle in (0, 90 deg) "
                                     "given in radians")
        else:
            raise ParameterError("constraints", name, f"unknown; known: {', '.join(CONSTRAINTS)}")
    return grashof, order, mu


def check_bound(name: str, value: Any, length: bool) -> tuple[float, float]:
    """The bound ``(low, high)`` of parameter ``name``, checked: finite, low <= high, and for a
    ``length`` low > 0."""
    try:
        lo, hi = (float(x) for x in value)
    except (TypeError, ValueError):
        raise ParameterError(f"bounds[{name}]", value, "must be (low, high)") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
        raise ParameterError(f"bounds[{name}]", (lo, hi), "needs finite low <= high")
    if length and not lo > 0:
        raise ParameterError(f"bounds[{name}]", (lo, hi), "a link length needs low > 0")
    return lo, hi


def task(points: ArrayLike, *, timing: ArrayLike | None = None,
         bounds: Mapping[str, tuple[float, float]] | None = None,
         constraints: Any = ("grashof", "order"), closed: bool = False,
         free_start: bool = False) -> PathTask:
    """Check a path-generation task and return it (see :func:`path` for the arguments).

    Raises
    ------
    ParameterError
        Fewer than 3 points (or, with timing, fewer than 2), points not finite, timing of the
        wrong length, unknown bound names, ``low > high``, non-positive link-length bounds.
    """
    pts = require_finite("points", points)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ParameterError("points", np.shape(points), "must be a sequence of (x, y) [m]")
    need = 2 if timing is not None else 3
    if len(pts) < need:
        raise ParameterError("points", len(pts), f"too few: path generation needs at least "
                             f"{need} points ({'with' if timing is not None else 'without'} "
                             "prescribed timing); fewer leave the coupler point unconstrained")
    span = float(np.hypot(*(pts.max(axis=0) - pts.min(axis=0))))
    if not span > 0:
        raise ParameterError("points", pts[0].tolist(), "all points coincide: no path to follow")
    tim = None
    if timing is not None:
        tim = require_finite("timing", timing).astype(float).ravel()
        if len(tim) != len(pts):
            raise ParameterError("timing", len(tim), f"must give one crank angle per point "
                                 f"({len(pts)})")
    elif free_start:
        raise ParameterError("free_start", free_start, "needs timing (the crank's advances "
                             "between the points); without timing every crank angle is free")
    grashof, order, mu = _parse_constraints(constraints)
    base = default_bounds(pts)
    th2b: tuple[float, float] | None = None
    for k, v in (bounds or {}).items():
        if k == "theta2":
            lo_t, hi_t = (float(x) for x in v)
            if not lo_t <= hi_t:
                raise ParameterError("bounds[theta2]", tuple(v), "needs low <= high")
            th2b = None if hi_t - lo_t >= TWO_PI - 1e-12 else (lo_t, hi_t)
            continue
        if k not in PARAMS:
            raise ParameterError("bounds", k, f"unknown parameter; known: "
                                 f"{', '.join((*PARAMS, 'theta2'))}")
        base[k] = check_bound(k, v, k in ("r1", "r2", "r3", "r4"))
    lo_a = np.array([base[k][0] for k in PARAMS])
    hi_a = np.array([base[k][1] for k in PARAMS])
    return PathTask(points=pts.astype(float), timing=tim, closed=bool(closed), lo=lo_a, hi=hi_a,
                    theta2_bounds=th2b, grashof=grashof, order=order, mu_min=mu, scale=span,
                    free_start=bool(free_start) and tim is not None)


# ---------------------------------------------------------------------------------------------
# global search: screening of candidate chunks
# ---------------------------------------------------------------------------------------------
_R = {k: i for i, k in enumerate(DEFECTS)}


def _crank_rocker_margin(X: np.ndarray) -> np.ndarray:
    """max(r2 - min(r1, r3, r4), r2 + l - p - q) over designs X (..., 9): <= 0 for a Grashof
    crank-rocker with r2 the crank (l, p, q the other three lengths, l the longest)."""
    r1, r2, r3, r4 = X[..., 0], X[..., 1], X[..., 2], X[..., 3]
    others = np.stack([r1, r3, r4], axis=-1)
    mx = others.max(axis=-1)
    return np.maximum(r2 - others.min(axis=-1), r2 + 2 * mx - others.sum(axis=-1))


def _cos_mu_extremes(X: np.ndarray) -> np.ndarray:
    """Largest |cos mu| of a crank-rocker over a full turn (at theta2 = 0 and pi)."""
    r1, r2, r3, r4 = X[..., 0], X[..., 1], X[..., 2], X[..., 3]
    den = 2 * r3 * r4
    c1 = (r3 * r3 + r4 * r4 - (r1 - r2) ** 2) / den
    c2 = (r3 * r3 + r4 * r4 - (r1 + r2) ** 2) / den
    return np.maximum(np.abs(c1), np.abs(c2))


def _cols(X: np.ndarray) -> tuple[np.ndarray, ...]:
    return tuple(X[:, i][:, None] for i in range(9))


def _ordered(D: np.ndarray, valid: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """Best assignment of the points (axis 1) to curve samples (axis 2) in order, either
    direction, starting at the sample nearest the first point and never across an unassembled
    sample: (error, crank angles (C, n) unwrapped, monotone)."""
    C, n, M = D.shape
    j = np.arange(M)
    k0 = np.argmin(D[:, 0, :], axis=1)
    best = np.full(C, np.inf)
    best_th = np.zeros((C, n))
    rows = np.arange(C)
    for s in (1, -1):
        idx = (k0[:, None] + s * j[None, :]) % M
        Dr = np.take_along_axis(D, np.broadcast_to(idx[:, None, :], D.shape), axis=2)
        if valid is not None:
            pref = np.logical_and.accumulate(np.take_along_axis(valid, idx, axis=1), axis=1)
            Dr = np.where(pref[:, None, :], Dr, np.inf)
        cost = np.empty_like(Dr)
        cost[:, 0] = Dr[:, 0]
        for i in range(1, n):
            cost[:, i] = Dr[:, i] + np.minimum.accumulate(cost[:, i - 1], axis=1)
        js = np.empty((C, n), dtype=np.int64)
        js[:, -1] = np.argmin(cost[:, -1], axis=1)
        err = cost[rows, -1, js[:, -1]]
        for i in range(n - 2, -1, -1):
            js[:, i] = np.argmin(np.where(j[None, :] <= js[:, i + 1, None], cost[:, i], np.inf),
                                 axis=1)
        th = (TWO_PI / M) * (k0[:, None] + s * js)
        better = err < best
        best = np.where(better, err, best)
        best_th = np.where(better[:, None], th, best_th)
    return best, best_th


def _screen(chunk: dict[str, np.ndarray], *, tk: PathTask, n_samples: int, keep: int
            ) -> dict[str, np.ndarray]:
    """Screen one chunk of candidates; keep its ``keep`` best (bounded memory)."""
    X = np.asarray(chunk["X"], dtype=float)
    br = np.asarray(chunk["branch"], dtype=float)
    C = len(X)
    counts = np.zeros(len(DEFECTS))
    closest = np.full(len(DEFECTS), np.inf)
    ok = np.ones(C, dtype=bool)
    if tk.grashof or tk.closed:
        g = _crank_rocker_margin(X)
        bad = g > 0
        if bad.any():
            closest[_R["grashof"]] = min(closest[_R["grashof"]], float(g[bad].min()))
        counts[_R["grashof"]] += bad.sum()
        ok &= ~bad
        if tk.mu_min is not None:
            cm = _cos_mu_extremes(X)
            badm = ok & (cm > math.cos(tk.mu_min))
            counts[_R["transmission"]] += badm.sum()
            if badm.any():
                mu = np.arccos(np.clip(cm[badm], -1.0, 1.0))
                closest[_R["transmission"]] = min(closest[_R["transmission"]],
                                                  float(-mu.max()))
            ok &= ~badm
    Xo, bo = X[ok], br[ok]
    pts = tk.points
    if tk.timing is not None:
        th = tk.angles(np.asarray(chunk["start"], dtype=float)[ok] if tk.free_start
                       else np.zeros(len(Xo))).copy()
        x, y, h2, _ = _kernel(th, *_cols(Xo), bo[:, None])
        valid = (h2 >= 0).all(axis=1)
        err = ((x - pts[:, 0]) ** 2 + (y - pts[:, 1]) ** 2).sum(axis=1)
    else:
        ths = np.linspace(0.0, TWO_PI, n_samples, endpoint=False)
        x, y, h2, _ = _kernel(ths[None, :], *_cols(Xo), bo[:, None])
        vs = h2 >= 0
        D = ((x[:, None, :] - pts[None, :, 0, None]) ** 2
             + (y[:, None, :] - pts[None, :, 1, None]) ** 2)
        D = np.where(vs[:, None, :], D, np.inf)
        if tk.order:
            err, th = _ordered(D, None if vs.all() else vs)
        else:
            kk = np.argmin(D, axis=2)
            err = np.take_along_axis(D, kk[:, :, None], axis=2)[:, :, 0].sum(axis=1)
            th = kk * (TWO_PI / n_samples)
        valid = np.isfinite(err)
    counts[_R["assembly"]] += (~valid).sum()
    err = np.where(valid, err, np.inf)
    top = np.argsort(err, kind="stable")[:keep]
    top = top[np.isfinite(err[top])]
    return {"X": Xo[top], "branch": bo[top], "theta2": th[top], "err": err[top],
            "counts": counts[None, :], "closest": closest[None, :]}


def _keep_best(keep: int) -> Callable[[dict[str, np.ndarray], dict[str, np.ndarray]],
                                      dict[str, np.ndarray]]:
    def combine(acc: dict[str, np.ndarray], res: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        out = {k: np.concatenate([acc[k], res[k]]) for k in ("X", "branch", "theta2", "err")}
        top = np.argsort(out["err"], kind="stable")[:keep]
        out = {k: v[top] for k, v in out.items()}
        out["counts"] = acc["counts"] + res["counts"]
        out["closest"] = np.minimum(acc["closest"], res["closest"])
        return out

    return combine


def crank_rockers(X: np.ndarray, u: np.ndarray, tk: PathTask) -> None:
    """Crank-rockers by construction, in place: the crank ``r2`` (column 1 of ``X``, the links
    ``r1 r2 r3 r4`` its first columns) redrawn from ``u`` in [0, 1) below the largest value
    that keeps it the shortest link and r2 + l < p + q (the others as drawn); where even its
    lower bound breaks that, the candidate stays as drawn and is rejected by the screening."""
    others = X[:, [0, 2, 3]]
    cap = np.minimum(others.min(axis=1), others.sum(axis=1) - 2 * others.max(axis=1))
    ub = np.minimum(tk.hi[1], cap * (1 - 1e-9))
    ok = ub > tk.lo[1]
    X[ok, 1] = tk.lo[1] + u[ok] * (ub[ok] - tk.lo[1])


def _sobol_rows(dim: int, seed: int, start: int, stop: int) -> np.ndarray:
    """Points ``start .. stop-1`` of the scrambled Sobol sequence of ``dim`` dimensions seeded
    by ``seed``: the same numbers however the sequence is cut (fast-forwarded to ``start``)."""
    from scipy.stats import qmc

    sobol = qmc.Sobol(dim, scramble=True, seed=seed)
    if start == 0:  # a power of two drawn (the sequence's balance), the first ones kept
        return sobol.random_base2(max(4, math.ceil(math.log2(max(stop, 2)))))[:stop]
    sobol.fast_forward(start)
    return sobol.random(stop - start)


def _seed(seed: int | None) -> int:
    """``seed``, or one drawn from the system's entropy: one scramble for every chunk."""
    return int(np.random.SeedSequence().generate_state(1)[0]) if seed is None else int(seed)


def _candidates(tk: PathTask, n: int, seed: int, start: int = 0,
                stop: int | None = None) -> dict[str, np.ndarray]:
    """A scrambled Sobol sample of the free parameters (fixed ones at their value), the two
    branches alternating: its candidates ``start .. stop-1`` of ``n``, the same numbers however
    the sample is cut (the sequence fast-forwarded to ``start``, the halves and branches by the
    candidate's index), so that each worker of a cluster makes its own chunk."""
    stop = n if stop is None else stop
    free = tk.free
    k = int(free.sum())
    U = _sobol_rows(max(k + tk.free_start, 1), seed, start, stop)
    even = np.arange(start, stop) % 2 == 0
    # half the sample in the bounds cut to the targets' scale (default_bounds), where wide
    # bounds (the literature's 50 times the path) would leave few useful candidates; half in
    # the whole box, link lengths log-uniform where the bounds span more than a decade
    d = default_bounds(tk.points)
    near_lo = np.maximum(tk.lo, [d[k][0] for k in PARAMS])
    near_hi = np.minimum(tk.hi, [d[k][1] for k in PARAMS])
    near = (near_hi >= near_lo).all()
    lo = np.tile(tk.lo, (len(U), 1))
    hi = np.tile(tk.hi, (len(U), 1))
    if near:
        lo[even], hi[even] = near_lo, near_hi
    X = lo.copy()
    X[:, free] = lo[:, free] + U[:, :k] * (hi - lo)[:, free]
    logs = np.zeros(9, dtype=bool)
    logs[:4] = free[:4] & (tk.hi[:4] > 10 * tk.lo[:4])
    rows = ~even if near else np.ones(len(U), dtype=bool)
    for i in np.flatnonzero(logs):
        u = U[rows, int(free[:i].sum())]
        X[rows, i] = tk.lo[i] * (tk.hi[i] / tk.lo[i]) ** u
    if (tk.grashof or tk.closed) and free[1]:
        crank_rockers(X, U[:, int(free[:1].sum())], tk)
    br = np.where(even, 1.0, -1.0)
    if tk.free_start:  # the first crank angle of a timing given by its advances
        return {"X": X, "branch": br, "start": TWO_PI * U[:, k]}
    return {"X": X, "branch": br}


# ---------------------------------------------------------------------------------------------
# refinement
# ---------------------------------------------------------------------------------------------
def _unpack(V: np.ndarray, x9: np.ndarray, free: np.ndarray, tk: PathTask, s: float
            ) -> tuple[np.ndarray, np.ndarray]:
    """Parameters (m, 9; the six-bar's 15) and crank angles (m, n) of refinement vectors
    ``V`` (m, nv)."""
    X = np.tile(x9, (len(V), 1))
    k = int(free.sum())
    X[:, free] = V[:, :k]
    if tk.timing is not None:
        return X, tk.angles(V[:, k] if tk.free_start else np.zeros(len(V)))
    inc = np.concatenate([np.zeros((len(V), 1)), np.cumsum(V[:, k + 1:], axis=1)], axis=1)
    return X, V[:, k:k + 1] + s * inc


@dataclass(frozen=True)
class _Judged:
    """The refinement's objective judged by forces: the point residuals (and the penalties)
    times ``point`` = sqrt(w_error / ref_error), then one residual sqrt(w_k m_k / ref_k) per
    metric of ``terms`` (``(metric, w_k / ref_k)``; the transmission angle enters as
    (pi/2) / mu_min), the metrics by :func:`~linkwork.synthesis.forces.force_metrics`."""

    model: ForceModel
    point: float
    terms: tuple[tuple[str, float], ...]

    def rows(self, X: np.ndarray, br: float, th: np.ndarray, tk: PathTask) -> np.ndarray:
        rotates = (_crank_rocker_margin(X) < 0) | tk.closed
        m = force_metrics(X, np.full(len(X), br), th, rotates, self.model)
        out = []
        for k, c in self.terms:
            v = m[k] if k != "min_transmission_angle" else (math.pi / 2) / np.maximum(
                m[k], 1e-9)
            out.append(np.sqrt(np.where(np.isfinite(v), c * v, 1e6)))
        return np.stack(out, axis=1)


def _residuals(V: np.ndarray, x9: np.ndarray, free: np.ndarray, tk: PathTask, s: float,
               br: float, weight: float, judged: _Judged | None = None) -> np.ndarray:
    """Residuals of refinement vectors ``V`` (m, nv), one row each: coupler point minus
    target (x then y), then the penalties (zero where the constraints hold), then with
    ``judged`` the forces' residuals (the others scaled, see :class:`_Judged`)."""
    X, th = _unpack(V, x9, free, tk, s)
    x, y, h2, cos_mu = _kernel(th, *(X[:, i:i + 1] for i in range(9)), br)
    L = tk.scale
    wl = weight * L
    pen: list[np.ndarray] = [wl * np.maximum(-h2, 0.0)]
    if tk.grashof or tk.closed:
        pen.append(weight * np.maximum(_crank_rocker_margin(X) + 1e-7 * L, 0.0)[:, None])
        if tk.mu_min is not None:
            pen.append(wl * np.maximum(_cos_mu_extremes(X) - math.cos(tk.mu_min) + 1e-7,
                                       0.0)[:, None])
    elif tk.mu_min is not None:
        pen.append(wl * np.maximum(np.abs(cos_mu) - math.cos(tk.mu_min) + 1e-9, 0.0))
    if tk.timing is None:
        k = int(free.sum())
        pen.append(wl * np.maximum(V[:, k + 1:].sum(axis=1) - (TWO_PI - 1e-6), 0.0)[:, None])
        if tk.theta2_bounds is not None:
            lo, hi = tk.theta2_bounds
            pen.append(wl * (np.maximum(lo - th, 0.0) + np.maximum(th - hi, 0.0)))
    R = np.concatenate([x - tk.points[:, 0], y - tk.points[:, 1], *pen], axis=1)
    if judged is None:
        return R
    return np.concatenate([judged.point * R, judged.rows(X, br, th, tk)], axis=1)


def _jacobian(v: np.ndarray, *args: Any) -> np.ndarray:
    """Jacobian of :func:`_residuals`: the coupler-point rows exact
    (:func:`~linkwork.synthesis.design._kernel_jacobian`, chained through the refinement
    vector), the penalty rows by forward differences, all columns in one vectorised call."""
    x9, free, tk, s, br = args[:5]
    h = 1.5e-8 * np.maximum(np.abs(v), 1.0)
    V = np.vstack([v, v + np.diag(h)])
    R = _residuals(V, *args)
    J = ((R[1:] - R[0]) / h[:, None]).T
    X, th = _unpack(v[None, :], x9, free, tk, s)
    dx, dy = _kernel_jacobian(th[0], *X[0], br)
    n, k = tk.n, int(free.sum())
    dth = np.zeros((n, len(v) - k))  # d theta2_i / d (the angle entries of v)
    if tk.timing is None:
        dth[:, 0] = 1.0
        dth[:, 1:] = s * np.tri(n, n - 1, -1)
    elif tk.free_start:
        dth[:, 0] = 1.0
    c = args[6].point if len(args) > 6 and args[6] is not None else 1.0
    J[:n, :k], J[n:2 * n, :k] = c * dx[:, :9][:, free], c * dy[:, :9][:, free]
    J[:n, k:], J[n:2 * n, k:] = c * dx[:, 9:] * dth, c * dy[:, 9:] * dth
    return J


def _refine(x9: np.ndarray, br: float, th: np.ndarray, tk: PathTask, max_nfev: int,
            judged: _Judged | None = None) -> tuple[np.ndarray, np.ndarray, int]:
    """Refine one start; returns (parameters, crank angles, residual evaluations, counting
    each finite-difference column as one)."""
    from scipy.optimize import least_squares

    free = tk.free
    v, s, blo, bhi = refinement_start(x9, th, tk)
    nfev = 0
    for weight in (1e2, 1e4):
        args = (x9, free, tk, s, br, weight, judged)
        res = least_squares(lambda u, *a: _residuals(u[None, :], *a)[0], v, jac=_jacobian,
                            bounds=(blo, bhi), method="trf", x_scale="jac",
                            max_nfev=max_nfev, args=args, ftol=1e-15, xtol=1e-15, gtol=1e-15,
                            callback=exact_stop(tk))
        nfev += int(res.nfev) + int(res.njev or 0) * len(v)
        v = res.x
        R = _residuals(v[None, :], *args)[0]
        pen = R[2 * tk.n:len(R) - (len(judged.terms) if judged else 0)]
        if not np.any(pen > 0):
            break
    X, th_r = _unpack(v[None, :], x9, free, tk, s)
    if tk.theta0_periodic:  # searched unbounded: back within the bounds, the same linkage
        wrap_theta0(X, tk)
    return X[0], th_r[0].copy(), nfev


def refinement_start(x: np.ndarray, th: np.ndarray, tk: PathTask
                     ) -> tuple[np.ndarray, float, np.ndarray, np.ndarray]:
    """The refinement vector of a start (:func:`_vector`), its sense of rotation and bounds
    (:func:`_vector_bounds`), the vector moved just inside them."""
    v, s = _vector(x, th, tk, pad=1e-6)
    blo, bhi = _vector_bounds(tk)
    fin = np.isfinite(blo) & np.isfinite(bhi)
    span = np.where(fin, bhi - blo, 0.0)
    v = np.clip(v, np.where(fin, blo + 1e-12 * span, blo), np.where(fin, bhi - 1e-12 * span, bhi))
    return v, s, blo, bhi


def exact_stop(tk: PathTask) -> Callable[..., bool]:
    """A ``least_squares`` callback that stops a refinement once its residuals are exact to
    round-off (an RMS of 1e-13 of the targets' size: ``ftol`` cannot see that, the cost
    falling towards 0 relative to itself)."""
    tol = tk.n * (1e-13 * tk.scale) ** 2

    def stop(intermediate_result: Any) -> bool:
        return bool(2.0 * intermediate_result.cost <= tol)

    return stop


def wrap_theta0(X: np.ndarray, tk: PathTask) -> None:
    """Frame angles of designs ``X`` (m, k) back within their bounds (a full turn), in place."""
    i = tk.theta0_index
    X[:, i] = tk.lo[i] + np.mod(X[:, i] - tk.lo[i], TWO_PI)


def _vector(x9: np.ndarray, th: np.ndarray, tk: PathTask, pad: float = 0.0
            ) -> tuple[np.ndarray, float]:
    """The refinement vector of a design (parameters ``x9``, crank angles ``th``): its free
    parameters, then without timing the first crank angle and the increments between
    consecutive points (their absolute values plus ``pad``: the sense of rotation ``s``,
    returned, stays fixed), or with a timing of free start the first crank angle."""
    parts = [x9[tk.free]]
    s = 1.0
    if tk.timing is None:
        d = np.diff(th)
        s = 1.0 if d.sum() >= 0 else -1.0
        parts += [[th[0]], np.abs(d) + pad]
    elif tk.free_start:
        parts.append([th[0]])
    return np.concatenate(parts).astype(float), s


def _vector_bounds(tk: PathTask) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of the refinement vector (:func:`_vector`); a frame angle free over a whole turn
    and the first crank angle are unbounded (angles)."""
    lo, hi = tk.lo[tk.free].copy(), tk.hi[tk.free].copy()
    i = tk.theta0_index
    if tk.theta0_periodic and tk.free[i]:
        j = int(tk.free[:i].sum())  # theta0's place among the free parameters
        lo[j], hi[j] = -np.inf, np.inf
    vlo, vhi = [lo], [hi]
    if tk.timing is None:
        vlo += [[-np.inf], np.zeros(tk.n - 1)]
        vhi += [[np.inf], np.full(tk.n - 1, TWO_PI)]
    elif tk.free_start:
        vlo.append([-np.inf])
        vhi.append([np.inf])
    return np.concatenate(vlo).astype(float), np.concatenate(vhi).astype(float)


# ---------------------------------------------------------------------------------------------
# defect checks
# ---------------------------------------------------------------------------------------------
#: Positions per radian of the dense tracking between consecutive points (about 1 deg).
TRACK_DENSITY = 60


def check_design(params: Mapping[str, Any], branch: int, tk: PathTask
                 ) -> tuple[str | None, dict[str, Any]]:
    """Check one design against the task's defects.

    Returns ``(defect, checks)``: ``defect`` is None for a defect-free design, else the first
    defect found (one of :data:`DEFECTS`); ``checks`` holds what was measured (see
    :class:`~linkwork.synthesis.design.FourbarDesign`). The crank angles ``params["theta2"]``
    are taken as they run: their order along the crank's rotation is checked on the angles
    modulo a turn.
    """
    X = np.array([float(params[k]) for k in PARAMS])
    th = np.asarray(params["theta2"], dtype=float)
    checks: dict[str, Any] = {}
    margin = float(_crank_rocker_margin(X))
    r = sorted(X[:4])
    cls = ("I" if r[0] + r[3] < r[1] + r[2] - 1e-12 * r[3] else
           "III" if abs(r[0] + r[3] - r[1] - r[2]) <= 1e-12 * r[3] else "II")
    checks["grashof"] = cls
    checks["crank_rotates"] = bool(margin < 0)
    if (tk.grashof or tk.closed) and not margin < 0:
        return "grashof", checks
    x, y, h2, _ = _kernel(th, *X, float(branch))
    if np.any(h2 < 0):
        return "assembly", checks
    dev = np.hypot(x - tk.points[:, 0], y - tk.points[:, 1])
    checks["max_deviation"] = float(dev.max())
    if tk.timing is None and tk.theta2_bounds is not None:
        lo, hi = tk.theta2_bounds
        if np.any(th < lo - 1e-9) or np.any(th > hi + 1e-9):
            return "bounds", checks
    if np.any(X < tk.lo - 1e-9 * tk.scale) or np.any(X > tk.hi + 1e-9 * tk.scale):
        return "bounds", checks
    # order: the crank runs in one direction through the points within one turn (the angles
    # are read modulo a turn; the direction is the one that needs the smaller rotation)
    d = np.diff(th)
    fwd, bwd = np.mod(d, TWO_PI), np.mod(-d, TWO_PI)
    s = 1.0 if fwd.sum() <= bwd.sum() else -1.0
    steps = fwd if s > 0 else bwd
    checks["direction"] = int(s)
    if tk.order and steps.sum() > TWO_PI + 1e-9:
        return "order", checks
    # dense tracking through the engine between consecutive points (and back to the first)
    arcs = [th[i] + s * np.linspace(0.0, steps[i], max(2, int(steps[i] * TRACK_DENSITY) + 2))
            for i in range(len(th) - 1)]
    rotates = bool(margin < 0)
    if tk.closed or rotates:
        back = TWO_PI - steps.sum()
        arcs.append(th[-1] + s * np.linspace(0.0, back, max(2, int(back * TRACK_DENSITY) + 2)))
    dense = np.concatenate(arcs) if arcs else th
    design = FourbarDesign(params=dict(params), branch=int(branch), error=0.0,
                           points=tk.points, closed=tk.closed)
    mech = design.mechanism()
    t0 = float(params["theta0"])
    kin = kinematics(mech, np.concatenate([th, dense]) + t0, on_failure="nan")
    n = len(th)
    ok = np.asarray(kin.valid)
    if not ok[:n].all():
        return "circuit", checks
    P = kin.point("coupler", "P")
    checks["engine_deviation"] = float(np.max(np.hypot(P.x[:n] - x, P.y[:n] - y)))
    if checks["engine_deviation"] > 1e-9 * tk.scale:
        return "circuit", checks
    if not ok[n:].all():
        return "branch", checks
    # transmission angle over what the design runs (a toggle in between is a branch defect)
    i3, i4 = mech.index["coupler"], mech.index["rocker"]
    mu = np.abs(np.mod(kin.theta[i3, n:] - kin.theta[i4, n:] + math.pi, TWO_PI) - math.pi)
    mu = np.minimum(mu, math.pi - mu)
    mu_min = float(mu.min())
    if rotates:  # a crank-rocker's extremes are at theta2 = 0 and pi: exact, not sampled
        mu_min = min(mu_min, float(np.arccos(min(float(_cos_mu_extremes(X)), 1.0))))
    checks["min_transmission_angle"] = mu_min
    if not mu_min > 1e-6:
        return "branch", checks
    if tk.mu_min is not None and mu_min < tk.mu_min:
        return "transmission", checks
    return None, checks


# ---------------------------------------------------------------------------------------------
# the search
# ---------------------------------------------------------------------------------------------
@contextmanager
def _progress_bar(progress: Any, description: str) -> Iterator[Any]:
    if callable(progress):
        yield progress
    elif progress and sys.stderr.isatty():
        with rich_progress(description, transient=True) as bar:
            yield bar
    else:
        yield None


def _distinct(X: np.ndarray, idx: Sequence[int], span: np.ndarray, n: int,
              tol: float = 1e-3) -> list[int]:
    keep: list[int] = []
    sp = np.where(span > 0, span, 1.0)
    for i in idx:
        if all(np.max(np.abs(X[i] - X[j]) / sp) > tol for j in keep):
            keep.append(int(i))
        if len(keep) == n:
            break
    return keep


def _wrap_theta2(th: np.ndarray) -> list[float]:
    return [float(v) for v in np.mod(th, TWO_PI)]


def path(points: ArrayLike, *, timing: ArrayLike | None = None,
         bounds: Mapping[str, tuple[float, float]] | None = None,
         constraints: Any = ("grashof", "order"), objective: Any = "sum_squares",
         closed: bool = False, free_start: bool = False, seed: int | None = None,
         client: Any = None, progress: Any = True, n_candidates: int = 2**16,
         n_samples: int = 120,
         n_refine: int = 24, n_designs: int = 5, chunk_size: int = 2048,
         max_nfev: int = 1000) -> SynthesisResult:
    """Four-bars whose coupler point passes through ``points``, defect-free, best first.

    Parameters
    ----------
    points : sequence of (x, y)
        Target points [m], in the order the coupler point is to reach them.
    timing : sequence of float, optional
        Crank angles at the points [rad], measured from the frame line O2 -> O4 as the
        literature measures them (the parameter ``theta2``); None: free (found by the search).
    bounds : mapping, optional
        Name -> (low, high) for ``r1 r2 r3 r4 rcx rcy x0 y0`` [m], ``theta0`` and ``theta2``
        [rad]; equal values fix a parameter. Defaults: :func:`default_bounds`.
    constraints : sequence
        ``"grashof"`` (a Grashof crank-rocker, ``r2`` the crank, turning fully), ``"order"``
        (the points reached in the given order, cyclically for a closed path) and
        ``("transmission", mu_min)`` (the transmission angle stays >= mu_min [rad] over the
        range the design runs).
    objective : str or Objective
        ``"sum_squares"`` (the literature's: the sum of squared distances); or an
        :class:`~linkwork.synthesis.forces.Objective` that also judges the designs by forces
        (weighted, or a Pareto set of accuracy against dynamics).
    closed : bool
        A closed path: the crank turns fully and the points are reached cyclically.
    free_start : bool
        With ``timing``: only the crank's advances between the points are prescribed
        (``timing - timing[0]``); the first crank angle is searched (as in the literature's
        18-point closed path, the crank 20 deg between points from a free start).
    seed : int, optional
        Seed of the Sobol sample (the search is reproducible with a seed).
    client : dask.distributed.Client or str, optional
        Screen the candidates on a dask.distributed cluster (see :func:`linkwork.sweep.evaluate`).
    progress : bool or callable
        A progress bar on a terminal's stderr (True), none (False), or a callback
        ``progress(done, total)``.
    n_candidates, n_samples, n_refine, n_designs, chunk_size, max_nfev
        Size of the global sample (at most :data:`MAX_CANDIDATES`), crank-angle samples per
        coupler curve (free timing), refinements started, designs returned, candidates per
        chunk, residual evaluations per refinement.

    Returns
    -------
    SynthesisResult

    Raises
    ------
    ParameterError
        Bad points, timing, bounds or constraints.
    InfeasibleError
        No defect-free design found: names what cannot be met and the closest value reached.
    """
    t_start = time.perf_counter()
    tk = task(points, timing=timing, bounds=bounds, constraints=constraints, closed=closed,
              free_start=free_start)
    obj = Objective.parse(objective)
    for name, val, least in (("n_candidates", n_candidates, 1), ("n_samples", n_samples, 8),
                             ("n_refine", n_refine, 1), ("n_designs", n_designs, 1),
                             ("chunk_size", chunk_size, 1), ("max_nfev", max_nfev, 10)):
        if isinstance(val, bool) or int(val) != val or val < least:
            raise ParameterError(name, val, f"must be an integer >= {least}")
    if n_candidates > MAX_CANDIDATES:
        raise ParameterError("n_candidates", n_candidates, f"must be at most {MAX_CANDIDATES} "
                             "(2^22); more refinements, not more candidates, sharpen the optimum")
    check_client(client)
    # the candidates made chunk by chunk (on a cluster, by the worker: nothing but the chunk's
    # bounds travels with a task)
    cands = Generated(int(n_candidates), functools.partial(_candidates, tk, int(n_candidates),
                                                           _seed(seed)))
    keep = max(4 * n_refine, 64)
    screen = functools.partial(_screen, n_samples=int(n_samples), keep=keep)
    with _progress_bar(progress, "screening candidates") as bar:
        res = evaluate(screen, cands, chunk_size=int(chunk_size), client=client, progress=bar,
                       combine=_keep_best(keep), shared={"tk": tk})
    t_global = time.perf_counter() - t_start
    counts = {k: int(v) for k, v in zip(DEFECTS, res["counts"].sum(axis=0), strict=True)}
    closest = dict(zip(DEFECTS, res["closest"].min(axis=0), strict=True))
    n_eval = int(n_candidates)
    if len(res["err"]) == 0:
        raise _infeasible_screen(tk, counts, closest, n_eval)
    span = tk.hi - tk.lo
    starts = _distinct(res["X"], range(len(res["err"])), span, int(n_refine))
    pool: list[FourbarDesign] = []
    rejected_refined = dict.fromkeys(DEFECTS, 0)
    last_checks: list[tuple[str, dict[str, Any]]] = []
    scales = _scales(res, tk, obj)
    judged = _judged(obj, scales, tk) if obj.kind == "weighted" else None
    refined, nres = _refine_starts(res, starts, tk, int(max_nfev), judged)
    if obj.kind == "pareto":  # accuracy traded for dynamics by growing weights on them
        base = refined[:max(2, int(n_refine) // 6)]
        for lam in PARETO_WEIGHTS:
            judged = _judged(obj, scales, tk, lam)
            for X, th, br in base:
                Xr, thr, nf = _refine(X, br, th, tk, int(max_nfev), judged)
                nres += nf
                refined.append((Xr, thr, br))
    for X, th, br in refined:
        params: dict[str, Any] = {k: float(v) for k, v in zip(PARAMS, X, strict=True)}
        params["theta2"] = [float(v) for v in th]
        defect, checks = check_design(params, int(br), tk)
        if defect is not None:
            rejected_refined[defect] += 1
            last_checks.append((defect, checks))
            continue
        x, y, _ = coupler_point(th, params, int(br))
        err = float(np.sum((x - tk.points[:, 0]) ** 2 + (y - tk.points[:, 1]) ** 2))
        params["theta2"] = _wrap_theta2(th)
        pool.append(FourbarDesign(params=params, branch=int(br), error=err, points=tk.points,
                                  closed=tk.closed, checks=checks))
    for k, v in rejected_refined.items():
        counts[k] += v
    if not pool:
        raise _infeasible_refined(tk, rejected_refined, last_checks, len(starts))
    pool.sort(key=lambda d: d.error)
    Xp = np.array([[d.params[k] for k in PARAMS] + [d.branch] for d in pool])
    order = _distinct(Xp, range(len(pool)), np.append(span, 2.0), len(pool))
    pool = [pool[i] for i in order]
    designs, pareto = judge(pool, obj, int(n_designs), scales)
    return SynthesisResult(designs=tuple(designs), points=tk.points, timing=tk.timing,
                           closed=tk.closed, constraints=tk.constraint_names(),
                           n_evaluated=n_eval, rejected=counts, n_refined=len(starts),
                           n_residual_evaluations=nres, time=time.perf_counter() - t_start,
                           time_global=t_global, objective=obj.kind, pareto=pareto,
                           scales=scales)


#: The weights on the dynamics (each normalised, the error by n (0.01 L)^2) of the refinements
#: that trace a Pareto set, continued from the most accurate designs.
PARETO_WEIGHTS = (1e-3, 1e-2, 1e-1, 1.0, 10.0)


def _refine_starts(res: Mapping[str, np.ndarray], starts: Sequence[int], tk: PathTask,
                   max_nfev: int, judged: _Judged | None
                   ) -> tuple[list[tuple[np.ndarray, np.ndarray, float]], int]:
    """Successive halving: every start refined briefly, the better third then to
    convergence; the refined (parameters, crank angles, branch), best first, and the
    residual evaluations."""
    nres = 0
    first = []
    for i in starts:
        br = float(res["branch"][i])
        X, th, nf = _refine(res["X"][i], br, res["theta2"][i], tk, max(max_nfev // 4, 10),
                            judged)
        nres += nf
        vec, sense = _vector(X, th, tk)
        r = _residuals(vec[None, :], X, tk.free, tk, sense, br, 1e4, judged)
        first.append((float(np.sum(r ** 2)), X, th, br))
    first.sort(key=lambda f: f[0])
    keep_n = max(3, len(first) // 3)
    refined = []
    for _, X, th, br in first[:keep_n]:
        X, th, nf = _refine(X, br, th, tk, max_nfev, judged)
        nres += nf
        refined.append((X, th, br))
    return refined + [(X, th, br) for _, X, th, br in first[keep_n:]], nres


def _scales(res: Mapping[str, np.ndarray], tk: PathTask, obj: Objective) -> dict[str, float]:
    """What the metrics are measured against when judged by forces: the error against
    n (0.01 L)^2 (an RMS deviation of 1 % of the targets' size L), each force against its
    median over the screened candidates (:func:`~linkwork.synthesis.forces.force_metrics`),
    the transmission angle as (pi/2) / mu_min against 1. Empty for the literature's objective."""
    if obj.kind == "sum_squares":
        return {}
    out = {"error": tk.n * (0.01 * tk.scale) ** 2, "min_transmission_angle": 1.0}
    X = np.asarray(res["X"])
    rotates = (_crank_rocker_margin(X) < 0) | tk.closed
    m = force_metrics(X, np.asarray(res["branch"]), np.asarray(res["theta2"]), rotates,
                      obj.forces)
    for k in ("peak_torque", "peak_bearing", "rms_shaking"):
        v = m[k][np.isfinite(m[k]) & (m[k] > 0)]
        out[k] = float(np.median(v)) if len(v) else 1.0
    return out


def _judged(obj: Objective, scales: Mapping[str, float], tk: PathTask,
            lam: float | None = None) -> _Judged:
    """The refinement's objective of a weighted search (``obj.weights``, the error's weight 1
    when not given), or of a Pareto search with the weight ``lam`` on each metric but the
    error."""
    if lam is None:
        w = dict(obj.weights) or {"peak_torque": 1.0}
    else:
        w = {k: lam for k in obj.metrics if k != "error"}
    we = w.pop("error", 1.0)
    terms = tuple((k, v / scales[k]) for k, v in w.items() if v > 0)
    return _Judged(model=obj.forces, point=math.sqrt(we / scales["error"]), terms=terms)


def _infeasible_screen(tk: PathTask, counts: Mapping[str, int], closest: Mapping[str, float],
                       n_eval: int) -> InfeasibleError:
    # the screening filters in this order: the stage after which none was left is the culprit
    left = n_eval - counts["grashof"]
    worst = "grashof" if left <= 0 else (
        "transmission" if left - counts["transmission"] <= 0 else "assembly")
    detail = (f"all {n_eval} candidates within the bounds rejected: "
              + ", ".join(f"{v} {k}" for k, v in counts.items() if v))
    if worst == "grashof":
        return InfeasibleError("a Grashof crank-rocker (r2 the crank) within the bounds",
                               f"r2 + l - p - q (or r2 - shortest) = "
                               f"{closest['grashof']:.6g} m, must be < 0", detail)
    if worst == "transmission":
        mu = -closest["transmission"]
        assert tk.mu_min is not None
        return InfeasibleError(f"minimum transmission angle >= {math.degrees(tk.mu_min):.4g} deg",
                               f"{math.degrees(mu):.4g} deg", detail)
    return InfeasibleError("a linkage within the bounds that assembles at every target point "
                           "(with its timing)" if tk.timing is not None else
                           "a linkage within the bounds whose coupler curve reaches the points "
                           "in order on one circuit", "no candidate assembles", detail)


def _infeasible_refined(tk: PathTask, rejected: Mapping[str, int],
                        checks: list[tuple[str, dict[str, Any]]], n: int) -> InfeasibleError:
    worst = max(rejected, key=lambda k: rejected[k])
    detail = (f"all {n} refined designs defective: "
              + ", ".join(f"{v} {k}" for k, v in rejected.items() if v))
    if worst == "transmission" and tk.mu_min is not None:
        mus = [c.get("min_transmission_angle", 0.0) for d, c in checks if d == "transmission"]
        return InfeasibleError(f"minimum transmission angle >= {math.degrees(tk.mu_min):.4g} deg",
                               f"{math.degrees(max(mus)):.4g} deg", detail)
    what = {"assembly": "assembly at every target point", "grashof": "a Grashof crank-rocker",
            "order": "the points in the given order within one turn",
            "branch": "no toggle between consecutive points (branch defect)",
            "circuit": "all points on one assembly circuit", "bounds": "the bounds"}[worst]
    devs = [c.get("max_deviation", math.inf) for _, c in checks]
    return InfeasibleError(what, f"best defective design deviates {min(devs):.6g} m at most "
                           "from the targets", detail)


