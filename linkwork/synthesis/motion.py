r"""Motion generation: four-bars whose coupler passes through given poses (Burmester theory).

A pose ``(x, y, theta)`` places the coupler's own frame: a point ``m`` of the coupler (its
coordinates in that frame) is at ``T_j m = d_j + R(theta_j) m`` in pose j. A **dyad** is a
fixed pivot ``c`` (centre point) and a moving pivot ``m`` (circle point) whose positions keep
one distance from ``c`` in every pose:

.. math::

    |T_j m - c|^2 - |T_1 m - c|^2 = 0, \qquad j = 2 \dots N,

which is linear in ``m`` for a given ``c`` (rows ``2 (R_j^T (d_j - c) - R_1^T (d_1 - c)) . m =
|d_1 - c|^2 - |d_j - c|^2``) and linear in ``c`` for a given ``m`` (``c`` is the centre of the
circle through the ``T_j m``). Hence (Burmester; McCarthy & Soh [1]_, Ch. 4; Sandor & Erdman
[2]_, Ch. 3):

* **3 poses**: every ``m`` gives one ``c`` (the circumcentre) and every ``c`` one ``m``:
  :func:`dyad_for_fixed_pivot`, :func:`dyad_for_moving_pivot`.
* **4 poses**: ``c`` must make the 3 x 3 matrix ``[rows | rhs]`` singular: a cubic, the
  **centre-point curve**, which passes through the poles ``P_ij``; each of its points gives
  one ``m`` (the **circle-point curve**). Traced here exactly along lines through a pole: on
  the line ``c = P + s u`` the cubic is ``s (alpha s^2 + beta s + gamma)``, so each line gives
  up to two centre points by the quadratic formula (:func:`centre_point_curve`).
* **5 poses**: the centre points common to the curves of poses (1, 2, 3, 4) and (1, 2, 3, 5)
  other than their shared poles: at most four real **Burmester points**, found along the
  first curve by sign changes of the second cubic, polished by Newton (least_squares) on the
  four dyad equations (:func:`burmester_points`).

Two dyads make a four-bar (:func:`combine`); one of them is the crank. A combination is kept
only if the linkage passes through the poses **in order, on one circuit, without passing a
toggle between them**: checked by :func:`linkwork.synthesis.path.check_design` (the poses'
reference points as coupler-point targets, the crank angles at the poses as timing: dense engine
tracking between consecutive poses), with the coupler's angle at each pose compared as well.

References
----------
.. [1] J. M. McCarthy, G. S. Soh, *Geometric Design of Linkages*, 2nd ed., Springer, 2011.
.. [2] G. N. Sandor, A. G. Erdman, *Advanced Mechanism Design*, vol. 2, Prentice-Hall, 1984.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite
from linkwork.errors import InfeasibleError, ParameterError
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import Mechanism
from linkwork.results import Result
from linkwork.synthesis.design import FourbarDesign
from linkwork.synthesis.path import check_design, task

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["Dyad", "MotionDesign", "MotionResult", "burmester_points", "centre_point_curve",
           "combine", "dyad_for_fixed_pivot", "dyad_for_moving_pivot", "motion", "poles"]

TWO_PI = 2 * math.pi


@dataclass(frozen=True)
class Dyad:
    """A fixed pivot ``c`` [m] (task frame) and a moving pivot ``m`` [m] (coupler frame)."""

    c: np.ndarray
    m: np.ndarray


def _poses(poses: ArrayLike) -> np.ndarray:
    P = require_finite("poses", poses).astype(float)
    if P.ndim != 2 or P.shape[1] != 3:
        raise ParameterError("poses", np.shape(poses), "must be a sequence of (x [m], y [m], "
                             "theta [rad])")
    return P


def _R(t: Any) -> np.ndarray:
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s], [s, c]])


def place(poses: np.ndarray, m: ArrayLike) -> np.ndarray:
    """Positions ``T_j m`` (N, 2) of a coupler point ``m`` in every pose [m]."""
    m_ = np.asarray(m, dtype=float)
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    return np.c_[poses[:, 0] + c * m_[0] - s * m_[1], poses[:, 1] + s * m_[0] + c * m_[1]]


def _rows(poses: np.ndarray, c: np.ndarray, js: Sequence[int]) -> np.ndarray:
    """Rows ``[a_j, b_j]`` of the dyad equations linear in m, for centre points ``c`` (..., 2):
    shape (..., len(js), 3)."""
    d1 = poses[0, :2]
    t1 = poses[0, 2]
    out = []
    for j in js:
        dj, tj = poses[j, :2], poses[j, 2]
        vj = dj - c
        v1 = d1 - c
        # R^T v = (c v_x + s v_y, -s v_x + c v_y)
        aj = np.stack([math.cos(tj) * vj[..., 0] + math.sin(tj) * vj[..., 1],
                       -math.sin(tj) * vj[..., 0] + math.cos(tj) * vj[..., 1]], axis=-1)
        a1 = np.stack([math.cos(t1) * v1[..., 0] + math.sin(t1) * v1[..., 1],
                       -math.sin(t1) * v1[..., 0] + math.cos(t1) * v1[..., 1]], axis=-1)
        a = 2 * (aj - a1)
        b = np.sum(v1 * v1, axis=-1) - np.sum(vj * vj, axis=-1)
        out.append(np.concatenate([a, b[..., None]], axis=-1))
    return np.stack(out, axis=-2)


def dyad_for_fixed_pivot(poses: ArrayLike, c: ArrayLike) -> Dyad:
    """The dyad with the fixed pivot ``c`` through 3 poses (least squares beyond 3)."""
    P = _poses(poses)
    if len(P) < 3:
        raise ParameterError("poses", len(P), "too few: a dyad needs at least 3 poses")
    c_ = np.asarray(c, dtype=float)
    M = _rows(P, c_, range(1, len(P)))
    sol, *_ = np.linalg.lstsq(M[:, :2], M[:, 2], rcond=None)
    if np.linalg.matrix_rank(M[:, :2]) < 2:
        raise InfeasibleError("a moving pivot for this fixed pivot",
                              "none: the fixed pivot is a pole of the poses")
    return Dyad(c_, sol)


def dyad_for_moving_pivot(poses: ArrayLike, m: ArrayLike) -> Dyad:
    """The dyad with the moving pivot ``m`` (coupler frame) through 3 poses: ``c`` is the
    centre of the circle through its positions (least squares beyond 3)."""
    P = _poses(poses)
    if len(P) < 3:
        raise ParameterError("poses", len(P), "too few: a dyad needs at least 3 poses")
    Q = place(P, m)
    A = 2 * (Q[1:] - Q[0])
    b = np.sum(Q[1:] ** 2, axis=1) - np.sum(Q[0] ** 2)
    if np.linalg.matrix_rank(A) < 2:
        raise InfeasibleError("a fixed pivot for this moving pivot",
                              "none: its positions lie on a line (a slider, not a crank)")
    c, *_ = np.linalg.lstsq(A, b, rcond=None)
    return Dyad(c, np.asarray(m, dtype=float))


def poles(poses: ArrayLike) -> dict[tuple[int, int], np.ndarray]:
    """Displacement poles ``P_ij`` (0-based i < j) of the poses that rotate."""
    P = _poses(poses)
    out = {}
    for i, j in itertools.combinations(range(len(P)), 2):
        dt = P[j, 2] - P[i, 2]
        if abs(math.sin(dt / 2)) < 1e-12:
            continue
        R = _R(dt)
        t = P[j, :2] - R @ P[i, :2]
        out[(i, j)] = np.linalg.solve(np.eye(2) - R, t)
    return out


def _det3(M: np.ndarray) -> np.ndarray:
    """Determinants of 3 x 3 matrices; NaN where a row is undefined (a root off the curve)."""
    good = np.all(np.isfinite(M), axis=(-2, -1))
    out = np.full(M.shape[:-2], np.nan)
    out[good] = np.linalg.det(M[good])
    return out


def centre_point_curve(poses: ArrayLike, n: int = 720) -> tuple[np.ndarray, np.ndarray]:
    """Centre points (k, 2) on the centre-point curve of 4 poses and the matching circle points
    (k, 2, coupler frame), along ``n`` lines through a pole (two per line at most)."""
    P = _poses(poses)
    if len(P) != 4:
        raise ParameterError("poses", len(P), "the centre-point curve needs exactly 4 poses")
    pl = poles(P)
    if not pl:
        raise InfeasibleError("a rotating displacement among the poses",
                              "all poses have the same angle (pure translation)")
    base = pl[min(pl)]
    L = float(np.hypot(*np.ptp(P[:, :2], axis=0))) or 1.0
    t = np.linspace(0.0, math.pi, int(n), endpoint=False)
    u = np.c_[np.cos(t), np.sin(t)]
    ss = np.array([-L, L, 2 * L])
    F = np.stack([_det3(_rows(P, base + s * u, (1, 2, 3))) / s for s in ss], axis=-1)
    V = np.c_[ss ** 2, ss, np.ones(3)]
    coef = np.linalg.solve(V, F.T).T  # (n, 3): alpha, beta, gamma
    al, be, ga = coef[:, 0], coef[:, 1], coef[:, 2]
    disc = be * be - 4 * al * ga
    cs, ms = [], []
    for sgn in (1.0, -1.0):
        with np.errstate(invalid="ignore", divide="ignore"):
            s = (-be + sgn * np.sqrt(disc)) / (2 * al)
        ok = (disc >= 0) & np.isfinite(s) & (np.abs(s) < 1e3 * L)
        c = base + s[:, None] * u
        cs.append(c[ok])
    C = np.concatenate(cs) if cs else np.zeros((0, 2))
    # circle points: least squares of the (consistent) 3 x 2 systems; drop the poles
    near = np.zeros(len(C), dtype=bool)
    for p in pl.values():
        near |= np.hypot(*(C - p).T) < 1e-6 * L
    C = C[~near]
    M = _rows(P, C, (1, 2, 3))
    for M_i in M:
        ms.append(np.linalg.lstsq(M_i[:, :2], M_i[:, 2], rcond=None)[0])
    return C, np.array(ms).reshape(-1, 2)


def burmester_points(poses: ArrayLike, n: int = 2880) -> list[Dyad]:
    """The dyads through 5 poses (at most 4 real Burmester points; an empty list when none)."""
    from scipy.optimize import brentq, least_squares

    P = _poses(poses)
    if len(P) != 5:
        raise ParameterError("poses", len(P), "Burmester points need exactly 5 poses")
    pl = poles(P)
    if not pl:
        raise InfeasibleError("a rotating displacement among the poses",
                              "all poses have the same angle (pure translation)")
    L = float(np.hypot(*np.ptp(P[:, :2], axis=0))) or 1.0
    ss = np.array([-L, L, 2 * L])
    V = np.c_[ss ** 2, ss, np.ones(3)]
    found: list[np.ndarray] = []
    # traced from two poles shared by both cubics (P12, P13), so that a root near where one
    # tracing switches between its two branches is found by the other
    for key in [k for k in ((0, 1), (0, 2), (1, 2)) if k in pl][:2]:
        found += _trace_roots(P, pl[key], L, ss, V, n, brentq)
    return _polish(P, found, pl, L, least_squares)


def _trace_roots(P: np.ndarray, base: np.ndarray, L: float, ss: np.ndarray, V: np.ndarray,
                 n: int, brentq: Any) -> list[np.ndarray]:
    """Centre points of poses (1, 2, 3, 4) along lines through ``base`` where the cubic of
    poses (1, 2, 3, 5) changes sign."""

    def centres(t: float | np.ndarray, sgn: float) -> np.ndarray:
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        u = np.c_[np.cos(tt), np.sin(tt)]
        F = np.stack([_det3(_rows(P, base + s * u, (1, 2, 3))) / s for s in ss], axis=-1)
        co = np.linalg.solve(V, F.T).T
        disc = co[:, 1] ** 2 - 4 * co[:, 0] * co[:, 2]
        with np.errstate(invalid="ignore", divide="ignore"):
            s_ = (-co[:, 1] + sgn * np.sqrt(disc)) / (2 * co[:, 0])
        return base + s_[:, None] * u

    def second(t: float | np.ndarray, sgn: float) -> np.ndarray:
        c = centres(t, sgn)
        return _det3(_rows(P, c, (1, 2, 4))) / L ** 3

    t = np.linspace(0.0, math.pi, int(n), endpoint=False)
    found: list[np.ndarray] = []
    for sgn in (1.0, -1.0):
        g = second(t, sgn)
        for k in np.flatnonzero(np.isfinite(g[:-1]) & np.isfinite(g[1:])
                                & (np.sign(g[:-1]) != np.sign(g[1:]))):
            try:
                tk = brentq(lambda x, s=sgn: float(second(x, s)[0]), t[k], t[k + 1],
                            xtol=1e-14)
            except ValueError:
                continue
            c = centres(tk, sgn)[0]
            if np.all(np.isfinite(c)) and np.hypot(*(c - base)) < 1e3 * L:
                found.append(c)
    return found


def _polish(P: np.ndarray, found: list[np.ndarray], pl: dict[tuple[int, int], np.ndarray],
            L: float, least_squares: Any) -> list[Dyad]:
    """Newton-polished, distinct dyads of the centre points found (poles dropped)."""
    dyads: list[Dyad] = []
    for c in found:
        if any(np.hypot(*(c - p)) < 1e-5 * L for p in pl.values()):
            continue
        M = _rows(P, c, (1, 2, 3, 4))
        m = np.linalg.lstsq(M[:, :2], M[:, 2], rcond=None)[0]

        def eqs(v: np.ndarray) -> np.ndarray:
            Q = place(P, v[2:])
            r2 = np.sum((Q - v[:2]) ** 2, axis=1)
            return (r2[1:] - r2[0]) / (L * L)

        sol = least_squares(eqs, np.r_[c, m], xtol=1e-15, ftol=1e-15, gtol=1e-15,
                            method="lm")
        if np.max(np.abs(eqs(sol.x))) > 1e-10:
            continue
        cc, mm = sol.x[:2], sol.x[2:]
        if any(np.hypot(*(cc - d.c)) < 1e-7 * L for d in dyads):
            continue
        if any(np.hypot(*(cc - p)) < 1e-5 * L for p in pl.values()):
            continue
        dyads.append(Dyad(cc, mm))
    return dyads


@dataclass(frozen=True)
class MotionDesign:
    """A four-bar through the poses: the crank dyad ``(c1, m1)``, the rocker dyad ``(c2, m2)``
    (``m`` in the coupler frame), and the same linkage as a
    :class:`~linkwork.synthesis.design.FourbarDesign` (the coupler point P is the coupler
    frame's origin, the poses' reference point; ``theta2`` the crank angles at the poses)."""

    c1: np.ndarray
    m1: np.ndarray
    c2: np.ndarray
    m2: np.ndarray
    fourbar: FourbarDesign
    pose_error: float

    def mechanism(self, omega1: float = 1.0) -> Mechanism:
        """The engine model (see :meth:`FourbarDesign.mechanism`)."""
        return self.fourbar.mechanism(omega1=omega1)

    def to_toml(self, path: str | Path, **kw: Any) -> Path:
        """A ``planar`` file of the four-bar (``linkwork analyze`` reads it)."""
        return self.fourbar.to_toml(path, **kw)


@dataclass(frozen=True)
class MotionResult(Result):
    """Four-bars through the poses, best first, with the dyads they were combined from.

    ``centre_points``/``circle_points``: the centre-point curve and circle points (4 poses),
    the Burmester points (5 poses) or the given pivots (3 poses); ``n_dyads``, ``n_pairs``:
    dyads considered and four-bars checked; ``rejected``: four-bars rejected per defect.
    """

    poses: np.ndarray
    designs: tuple[MotionDesign, ...]
    centre_points: np.ndarray
    circle_points: np.ndarray
    n_dyads: int
    n_pairs: int
    rejected: dict[str, int]

    units: ClassVar[dict[str, str]] = {"rank": "", "pose_error": "m",
                                       "min_transmission_angle": "rad"}
    position_field: ClassVar[str] = "rank"

    @property
    def rank(self) -> np.ndarray:
        return np.arange(1, len(self.designs) + 1)

    @property
    def best(self) -> MotionDesign:
        return self.designs[0]

    def columns(self) -> dict[str, np.ndarray]:
        cols: dict[str, np.ndarray] = {"rank": self.rank}
        for name, get in (("c1x", lambda d: d.c1[0]), ("c1y", lambda d: d.c1[1]),
                          ("m1x", lambda d: d.m1[0]), ("m1y", lambda d: d.m1[1]),
                          ("c2x", lambda d: d.c2[0]), ("c2y", lambda d: d.c2[1]),
                          ("m2x", lambda d: d.m2[0]), ("m2y", lambda d: d.m2[1])):
            cols[name] = np.array([float(get(d)) for d in self.designs])
        for k in ("r1", "r2", "r3", "r4"):
            cols[k] = np.array([float(d.fourbar.params[k]) for d in self.designs])
        cols["pose_error"] = np.array([d.pose_error for d in self.designs])
        cols["min_transmission_angle"] = np.array(
            [float(d.fourbar.checks.get("min_transmission_angle", math.nan))
             for d in self.designs])
        return cols

    def _unit_of(self, column: str) -> str:
        return self.units.get(column, "m")

    def scalars(self) -> dict[str, Any]:
        return {"n_poses": len(self.poses), "n_dyads": self.n_dyads, "n_pairs": self.n_pairs,
                "rejected": dict(self.rejected)}

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """Poses, centre and circle points, the first four-bar: 1 axes."""
        from linkwork.plot.synthesis import motion_figure

        return motion_figure(self, ax=ax, **kw)


def combine(poses: ArrayLike, crank: Dyad, rocker: Dyad, *, grashof: bool = False,
            mu_min: float | None = None) -> tuple[MotionDesign | None, str | None]:
    """The four-bar of two dyads (``crank`` driven) through the poses, or the defect that
    rejects it: ``(design, None)`` or ``(None, defect)``."""
    P = _poses(poses)
    A = place(P, crank.m)
    B = place(P, rocker.m)
    c1, c2 = crank.c, rocker.c
    r1 = float(np.hypot(*(c2 - c1)))
    r2 = float(np.mean(np.hypot(*(A - c1).T)))
    r3 = float(np.hypot(*(crank.m - rocker.m)))
    r4 = float(np.mean(np.hypot(*(B - c2).T)))
    if min(r1, r2, r3, r4) < 1e-9 * max(r1, r2, r3, r4, 1e-300):
        return None, "assembly"
    side = np.sign((c2[0] - A[:, 0]) * (B[:, 1] - A[:, 1])
                   - (c2[1] - A[:, 1]) * (B[:, 0] - A[:, 0]))
    if not (np.all(side == side[0]) and side[0] != 0):
        return None, "circuit"
    L = float(np.hypot(*np.ptp(P[:, :2], axis=0))) or 1.0
    t0 = math.atan2(c2[1] - c1[1], c2[0] - c1[0])
    th2 = np.arctan2(A[:, 1] - c1[1], A[:, 0] - c1[0]) - t0
    e3 = (B[0] - A[0]) / r3
    rel = P[0, :2] - A[0]
    params: dict[str, Any] = {"r1": r1, "r2": r2, "r3": r3, "r4": r4,
                              "rcx": float(rel @ e3), "rcy": float(rel @ np.r_[-e3[1], e3[0]]),
                              "x0": float(c1[0]), "y0": float(c1[1]), "theta0": t0,
                              "theta2": [float(v) for v in th2]}
    cons: list[Any] = ["order"] + (["grashof"] if grashof else [])
    if mu_min is not None:
        cons.append(("transmission", mu_min))
    wide = {k: (v * 1e-3, v * 1e3) for k, v in params.items() if k in ("r1", "r2", "r3", "r4")}
    big = 1e3 * (L + max(r1, r2, r3, r4))
    wide |= {k: (params[k] - big, params[k] + big) for k in ("rcx", "rcy", "x0", "y0")}
    wide["theta0"] = (t0 - 1.0, t0 + 1.0)
    tk = task(P[:, :2], timing=th2, constraints=tuple(cons), bounds=wide)
    defect, checks = check_design(params, int(side[0]), tk)
    if defect is not None:
        return None, defect
    # the coupler's angle at each pose, through the engine
    fb = FourbarDesign(params=params, branch=int(side[0]), error=0.0, points=P[:, :2],
                       checks=checks)
    kin = kinematics(fb.mechanism(), th2 + t0)
    ang = kin.angle("coupler")
    off = math.atan2(e3[1], e3[0]) - P[0, 2]
    dth = np.mod(ang - off - P[:, 2] + math.pi, TWO_PI) - math.pi
    Pp = kin.point("coupler", "P")
    err = float(max(np.max(np.hypot(Pp.x - P[:, 0], Pp.y - P[:, 1])), np.max(np.abs(dth)) * L))
    if err > 1e-9 * L:
        return None, "circuit"
    fb = FourbarDesign(params=params, branch=int(side[0]), error=float(
        np.sum((Pp.x - P[:, 0]) ** 2 + (Pp.y - P[:, 1]) ** 2)), points=P[:, :2], checks=checks)
    return MotionDesign(c1, np.asarray(crank.m), c2, np.asarray(rocker.m), fb, err), None


def _in_region(c: np.ndarray, region: Any) -> np.ndarray:
    if region is None:
        return np.ones(len(c), dtype=bool)
    (x0, x1), (y0, y1) = region
    return (c[:, 0] >= x0) & (c[:, 0] <= x1) & (c[:, 1] >= y0) & (c[:, 1] <= y1)


def motion(poses: ArrayLike, *, fixed_pivots: Sequence[ArrayLike] | None = None,
           moving_pivots: Sequence[ArrayLike] | None = None,
           pivot_region: tuple[tuple[float, float], tuple[float, float]] | None = None,
           grashof: bool = False, mu_min: float | None = None, n_curve: int = 360,
           n_designs: int = 5, max_pairs: int = 2000) -> MotionResult:
    """Four-bars whose coupler passes through 3, 4 or 5 poses in order, on one circuit.

    Parameters
    ----------
    poses : sequence of (x, y, theta)
        Coupler poses [m, m, rad]: the coupler frame's origin and angle, in order.
    fixed_pivots, moving_pivots : two points each, optional
        3 poses: the two fixed pivots (task frame) or the two moving pivots (coupler frame) of
        the dyads; one of them is needed (3 poses leave them free).
    pivot_region : ((xmin, xmax), (ymin, ymax)), optional
        4 or 5 poses: fixed pivots only inside this box [m] (a fixed-pivot constraint).
    grashof : bool
        Only crank-rockers with a fully turning crank.
    mu_min : float, optional
        Minimum transmission angle over the motion [rad].
    n_curve : int
        Lines traced through the centre-point curve (4 poses).
    n_designs : int
        Four-bars returned.
    max_pairs : int
        Largest number of dyad pairs checked (4 poses: the dyads are thinned evenly and the
        pairs taken in a fixed pseudo-random order, until ``10 n_designs`` four-bars pass).

    Raises
    ------
    ParameterError
        Fewer than 3 or more than 5 poses, missing pivots for 3 poses.
    InfeasibleError
        "the 5 poses have no real Burmester pair", no dyads in the pivot region, or no
        combination free of defects (naming the most frequent defect).
    """
    P = _poses(poses)
    if not 3 <= len(P) <= 5:
        raise ParameterError("poses", len(P), "too few" if len(P) < 3 else "too many: motion "
                             "generation by a four-bar takes 3, 4 or 5 poses (Burmester)")
    dyads: list[Dyad] = []
    C = np.zeros((0, 2))
    Mc = np.zeros((0, 2))
    if len(P) == 3:
        if fixed_pivots is not None:
            dyads = [dyad_for_fixed_pivot(P, c) for c in fixed_pivots]
        elif moving_pivots is not None:
            dyads = [dyad_for_moving_pivot(P, m) for m in moving_pivots]
        else:
            raise ParameterError("fixed_pivots", None, "3 poses leave the pivots free: give "
                                 "two fixed pivots or two moving pivots")
        if len(dyads) != 2:
            raise ParameterError("fixed_pivots" if fixed_pivots is not None else
                                 "moving_pivots", len(dyads), "must give two pivots")
        C = np.array([d.c for d in dyads])
        Mc = np.array([d.m for d in dyads])
    elif len(P) == 4:
        C, Mc = centre_point_curve(P, n_curve)
        keep = _in_region(C, pivot_region)
        C, Mc = C[keep], Mc[keep]
        if len(C) < 2:
            raise InfeasibleError("two fixed pivots on the centre-point curve inside the "
                                  "pivot region", f"{len(C)} centre points there")
        step = max(1, math.ceil(len(C) / math.sqrt(2 * max_pairs)))
        dyads = [Dyad(c, m) for c, m in zip(C[::step], Mc[::step], strict=True)]
    else:
        dyads = burmester_points(P)
        if pivot_region is not None:
            dyads = [d for d in dyads if _in_region(d.c[None, :], pivot_region)[0]]
        if len(dyads) < 2:
            raise InfeasibleError("two real Burmester points" + (
                " inside the pivot region" if pivot_region is not None else ""),
                f"{len(dyads)} real Burmester point{'s' if len(dyads) != 1 else ''}",
                "the 5 poses have no real Burmester pair")
        C = np.array([d.c for d in dyads])
        Mc = np.array([d.m for d in dyads])
    rejected: dict[str, int] = {}
    found: list[MotionDesign] = []
    pairs = 0
    L = float(np.hypot(*np.ptp(P[:, :2], axis=0))) or 1.0
    order = list(itertools.permutations(range(len(dyads)), 2))
    if len(order) > 2 * max_pairs or len(P) == 4:  # a deterministic spread over the curve
        order = [order[k] for k in np.random.default_rng(0).permutation(len(order))]
    for i, j in order:
        if np.hypot(*(dyads[i].c - dyads[j].c)) < 1e-6 * L:
            continue
        if len(found) >= 10 * n_designs:
            break
        pairs += 1
        des, defect = combine(P, dyads[i], dyads[j], grashof=grashof, mu_min=mu_min)
        if des is None:
            rejected[defect or "?"] = rejected.get(defect or "?", 0) + 1
        else:
            found.append(des)
        if pairs >= 2 * max_pairs:
            break
    if not found:
        worst = max(rejected, key=lambda k: rejected[k]) if rejected else "assembly"
        raise InfeasibleError("a four-bar through the poses in order on one circuit"
                              + (" (crank-rocker)" if grashof else ""),
                              f"none of {pairs} dyad pairs: " + ", ".join(
                                  f"{v} {k}" for k, v in rejected.items()),
                              f"most frequent defect: {worst}")
    found.sort(key=lambda d: (-d.fourbar.checks.get("min_transmission_angle", 0.0),
                              max(d.fourbar.params[k] for k in ("r1", "r2", "r3", "r4"))))
    return MotionResult(poses=P, designs=tuple(found[:n_designs]), centre_points=C,
                        circle_points=np.array([place(P[:1], m)[0] for m in Mc]).reshape(-1, 2),
                        n_dyads=len(dyads), n_pairs=pairs, rejected=rejected)
