r"""Path generation by the coupler point of a Watt II or Stephenson III six-bar.

Both six-bars are a driving four-bar O2-A-B-O4 (the literature's ``r1 r2 r3 r4 x0 y0 theta0``
as in :mod:`linkwork.synthesis.design`) and a dyad C-D-O6 driven by a point C of one of its
links; the traced point P is on the dyad's link CD:

* ``"stephenson"`` (Stephenson III): C on the four-bar's coupler, ``(cx, cy)`` in the coupler's
  frame (origin A, x along A -> B);
* ``"watt"`` (Watt II): C on the four-bar's rocker, ``(cx, cy)`` in the rocker's frame (origin
  O4, x along O4 -> B).

The dyad: ``r5`` = CD, ``r6`` = O6D with the fixed pivot ``O6 = (x6, y6)``; P at ``(px, py)``
in the frame of CD (origin C, x along C -> D). Branches: ``B`` of the four-bar, ``D`` of the dyad
(the engine's RRR convention: D on the left of C -> O6 for +1). Crank angles ``theta2`` from
the frame line, as for the four-bar.

Method (as :func:`linkwork.synthesis.path.path`)
-------------------------------------------------
1. **Global search.** A scrambled Sobol sample of the free parameters, the four branch pairs
   alternating; crank-rockers by construction where "grashof" is asked; half of the sample's
   dyads assembled by construction (D and O6 placed from C at the first crank angle, so that the
   wide bounds a blind search needs do not leave almost every dyad unassembled). Screened in
   chunks through :func:`linkwork.sweep.evaluate` (in-process or on a Dask cluster) by the closed
   form of the two loops (:func:`sixbar_point`, broadcast over designs x crank angles), with the
   ordered timing assignment of the four-bar search for free timing; each chunk keeps its best.
2. **Refinement.** SciPy's ``least_squares`` on the exact residuals over the free parameters
   (and the crank angles as first angle and non-negative increments), the constraints as
   penalties; the Jacobian by forward differences, all columns in one vectorised call.
3. **Defect checks by the engine.** Every refined design is rebuilt as an engine
   :class:`~linkwork.planar.model.Mechanism` and tracked densely between consecutive points
   (:func:`coupler_points`): it must assemble everywhere on its branches, give the closed
   form's coupler point at the targets (one circuit), keep both transmission angles off zero
   (no toggle) and above the asked minimum, reach the points in order within a turn, and turn
   its crank fully where asked.

The engine does not take dimensions as arrays (its compiled plan holds each joint's geometry
as numbers), so the screening and the refinement use the closed form of the two loops - the
same circle intersections the engine solves group by group, equal to it to 1e-12 (tested) -
and the engine re-solves every design returned. Once the engine evaluates designs in batches
(issue 20), :func:`coupler_points` can screen directly; it runs today at about 1e4 - 2e5
candidate-points per second against some 1e6 - 1e7 for the closed form (benchmarks/synthesis.py).
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike

from linkwork.errors import InfeasibleError, ParameterError
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import Body, Crank, Mechanism, Revolute, bar
from linkwork.results import Result
from linkwork.sweep import Generated, check_client, evaluate
from linkwork.synthesis.design import _loop, design_columns, run_range, write_planar_toml
from linkwork.synthesis.path import (
    DEFECTS,
    TRACK_DENSITY,
    PathTask,
    _crank_rocker_margin,
    _distinct,
    _keep_best,
    _ordered,
    _progress_bar,
    _seed,
    _sobol_rows,
    _unpack,
    _vector,
    check_bound,
    crank_rockers,
    default_bounds,
    exact_stop,
    refinement_start,
    task,
    wrap_theta0,
)

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["KINDS", "SIXBAR_PARAMS", "SixbarDesign", "SixbarResult", "coupler_points",
           "mechanism", "sixbar_bounds", "sixbar_path", "sixbar_point"]

TWO_PI = 2 * math.pi

#: Parameters of a six-bar path generator (lengths [m], theta0 [rad]).
SIXBAR_PARAMS = ("r1", "r2", "r3", "r4", "x0", "y0", "theta0", "cx", "cy", "r5", "r6", "x6",
                 "y6", "px", "py")

#: The six-bars: C on the four-bar's coupler (Stephenson III) or on its rocker (Watt II).
KINDS = ("stephenson", "watt")

#: Branch pairs (B, D) by code, as candidates carry them.
_BRANCHES = np.array([(1, 1), (1, -1), (-1, 1), (-1, -1)])


# ---------------------------------------------------------------------------------------------
# the engine model and the closed form
# ---------------------------------------------------------------------------------------------
def mechanism(p: Mapping[str, float], kind: str, branches: tuple[int, int] = (1, 1),
              omega1: float = 1.0) -> Mechanism:
    """The engine model of a six-bar design: frame points O2, O4, O6; bodies crank (O2 -> A),
    coupler (A, B; and C for Stephenson), rocker (O4 -> B; and C for Watt), link5 (C, D, P),
    link6 (O6 -> D); the crank drives at O2 (``phi1 = theta0 + theta2``).

    The parameters (and ``branches``) may be arrays over designs: the engine's batch of those
    designs (``Mechanism.n_designs``), solved in one call."""
    t0 = p["theta0"]
    o2 = (p["x0"], p["y0"])
    cos, sin = (np.cos, np.sin) if np.ndim(t0) else (math.cos, math.sin)
    o4 = (p["x0"] + p["r1"] * cos(t0), p["y0"] + p["r1"] * sin(t0))
    frame = Body("frame", {"O2": o2, "O4": o4, "O6": (p["x6"], p["y6"])})
    crank = bar("crank", "O2", "A", p["r2"], inertia=0.0)
    cpts = {"A": (0.0, 0.0), "B": (p["r3"], 0.0)}
    rpts = {"O4": (0.0, 0.0), "B": (p["r4"], 0.0)}
    (cpts if kind == "stephenson" else rpts)["C"] = (p["cx"], p["cy"])
    coupler = Body("coupler", cpts)
    rocker = Body("rocker", rpts)
    link5 = Body("link5", {"C": (0.0, 0.0), "D": (p["r5"], 0.0), "P": (p["px"], p["py"])})
    link6 = bar("link6", "O6", "D", p["r6"], inertia=0.0)
    host = "coupler" if kind == "stephenson" else "rocker"
    joints = (Revolute("O2", "frame", "crank"), Revolute("A", "crank", "coupler"),
              Revolute("B", "coupler", "rocker"), Revolute("O4", "frame", "rocker"),
              Revolute("C", host, "link5"), Revolute("D", "link5", "link6"),
              Revolute("O6", "frame", "link6"))
    return Mechanism(frame, (crank, coupler, rocker, link5, link6), joints,
                     Crank("O2", omega1, 0.0), {"B": _branch(branches[0]),
                                                "D": _branch(branches[1])})


def _branch(b: Any) -> Any:
    """A branch +1/-1 as an int, or an int array over a batch's designs."""
    return int(b) if np.ndim(b) == 0 else np.asarray(b, dtype=int)


def coupler_points(X: np.ndarray, branches: np.ndarray, theta2: np.ndarray, kind: str
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coupler point P (x, y) and validity of designs ``X`` (m, 15) on ``branches`` (m, 2) at
    crank angles ``theta2`` (n,) or (m, n) through the engine: arrays (m, n). One engine model
    per design (the engine takes no dimensions as arrays)."""
    X = np.atleast_2d(X)
    th = np.broadcast_to(np.asarray(theta2, dtype=float), (len(X), np.shape(theta2)[-1]))
    xs = np.full(th.shape, np.nan)
    ys = np.full(th.shape, np.nan)
    for i, (x, br) in enumerate(zip(X, branches, strict=True)):
        p = dict(zip(SIXBAR_PARAMS, map(float, x), strict=True))
        try:
            mech = mechanism(p, kind, (int(br[0]), int(br[1])))
            kin = kinematics(mech, th[i] + p["theta0"], on_failure="nan")
        except ValueError:  # a degenerate design (a zero-length link): not assembled
            continue
        P = kin.point("link5", "P")
        xs[i], ys[i] = P.x, P.y
    ok = np.isfinite(xs) & np.isfinite(ys)
    return xs, ys, ok


def _chain(th: Any, X: np.ndarray, brb: Any, brd: Any, kind: str) -> dict[str, Any]:
    """The two loops in closed form over designs ``X`` (m, 15) (columns broadcast against
    ``th``): the coupler point ``x, y`` and the point C ``cx, cy`` [m], ``h2b`` and ``h2d``
    (>= 0 where the four-bar and
    the dyad assemble, dimensionless), the transmission angles' cosines ``cos_b``
    (coupler-rocker at B) and ``cos_d`` (link5-link6 at D)."""
    r1, r2, r3, r4, x0, y0, t0, cx, cy, r5, r6, x6, y6, px, py = (
        X[:, i][:, None] for i in range(15))
    ax, ay, sx, sy, ux, uy, h2b = _loop(th, r1, r2, r3, r4, brb)
    wx, wy = ux - sx, uy - sy  # B - O4
    if kind == "stephenson":  # C on the coupler: origin A, x along A -> B
        ex, ey = ux / r3, uy / r3
        clx, cly = ax + cx * ex - cy * ey, ay + cx * ey + cy * ex
    else:  # C on the rocker: origin O4, x along O4 -> B
        ex, ey = wx / r4, wy / r4
        clx, cly = r1 + cx * ex - cy * ey, cx * ey + cy * ex
    c0, s0 = np.cos(t0), np.sin(t0)
    gx, gy = x0 + c0 * clx - s0 * cly, y0 + s0 * clx + c0 * cly  # C, task frame
    dx, dy = x6 - gx, y6 - gy  # C -> O6
    dd = np.hypot(dx, dy)
    dd = np.where(dd > 0, dd, np.nan)
    a = (r5 * r5 - r6 * r6 + dd * dd) / (2.0 * dd)
    h2d = 1.0 - (a / r5) ** 2
    h = brd * r5 * np.sqrt(np.maximum(h2d, 0.0))
    fx, fy = dx / dd, dy / dd
    qx, qy = a * fx - h * fy, a * fy + h * fx  # D - C (left of C -> O6 for brd = +1)
    e5x, e5y = qx / r5, qy / r5
    cos_b = (ux * wx + uy * wy) / (r3 * r4)
    cos_d = ((-qx) * (dx - qx) + (-qy) * (dy - qy)) / (r5 * r6)
    return {"x": gx + px * e5x - py * e5y, "y": gy + px * e5y + py * e5x, "cx": gx, "cy": gy,
            "h2b": h2b, "h2d": np.where(np.isfinite(h2d), h2d, -1.0), "cos_b": cos_b,
            "cos_d": cos_d}


def sixbar_point(theta2: ArrayLike, X: ArrayLike, branches: ArrayLike, kind: str
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The coupler point of six-bar designs in closed form: ``X`` (m, 15)
    (:data:`SIXBAR_PARAMS`), ``branches`` (m, 2) of B and D, crank angles ``theta2`` (n,) or
    (m, n) from the frame line: ``x, y`` (m, n) [m] (NaN where it does not assemble) and
    ``valid``. Equal to the engine (:func:`coupler_points`) to round-off."""
    X = np.atleast_2d(np.asarray(X, dtype=float))
    br = np.atleast_2d(np.asarray(branches, dtype=float))
    c = _chain(np.asarray(theta2, dtype=float), X, br[:, :1], br[:, 1:], kind)
    ok = (c["h2b"] >= 0) & (c["h2d"] >= 0)
    return np.where(ok, c["x"], np.nan), np.where(ok, c["y"], np.nan), ok


def sixbar_bounds(points: np.ndarray) -> dict[str, tuple[float, float]]:
    """Default bounds from the targets (as :func:`linkwork.synthesis.path.default_bounds`):
    lengths 2 % to 3 times the targets' size L, points on links within +-3 L, pivots within
    3 L of the targets' centre."""
    b = default_bounds(points)
    L = b["r1"][1] / 3.0
    out = {k: b[k] for k in ("r1", "r2", "r3", "r4", "x0", "y0", "theta0")}
    out |= {"cx": (-3 * L, 3 * L), "cy": (-3 * L, 3 * L), "r5": b["r1"], "r6": b["r1"],
            "x6": b["x0"], "y6": b["y0"], "px": (-3 * L, 3 * L), "py": (-3 * L, 3 * L)}
    return out


# ---------------------------------------------------------------------------------------------
# designs and results
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SixbarDesign:
    """A six-bar path generator: ``params`` (:data:`SIXBAR_PARAMS` and ``theta2``), ``kind``,
    ``branches`` (B, D), ``error`` [m^2] (the sum of squared distances to the targets),
    ``checks`` (``crank_rotates``, ``direction``, ``max_deviation`` [m],
    ``engine_deviation`` [m], ``min_transmission_angle`` [rad] of the two loops over the range
    the design runs)."""

    kind: str
    params: Mapping[str, Any]
    branches: tuple[int, int]
    error: float
    points: np.ndarray
    closed: bool = False
    checks: Mapping[str, Any] = field(default_factory=dict)

    @property
    def theta2(self) -> np.ndarray:
        return np.asarray(self.params["theta2"], dtype=float)

    @property
    def vector(self) -> np.ndarray:
        """The parameters as a vector in the order of :data:`SIXBAR_PARAMS`."""
        return np.array([float(self.params[k]) for k in SIXBAR_PARAMS])

    def mechanism(self, omega1: float = 1.0) -> Mechanism:
        return mechanism(self.params, self.kind, self.branches, omega1)

    def run_range(self, n: int = 361) -> np.ndarray:
        """Crank angles the design runs through (see
        :func:`linkwork.synthesis.design.run_range`)."""
        return run_range(self.theta2, self.checks, self.closed, n)

    def coupler_curve(self, n: int = 361) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Crank angles over the range the design runs and the coupler point's x, y [m]."""
        th = self.run_range(n)
        x, y, _ = sixbar_point(th, self.vector[None, :], [self.branches], self.kind)
        return th, x[0], y[0]

    def skeleton(self, theta2: float) -> tuple[list[np.ndarray], np.ndarray]:
        """The links at the crank angle ``theta2`` as polylines [m] and the fixed pivots."""
        kin = kinematics(self.mechanism(), np.array([float(theta2) + self.params["theta0"]]),
                         on_failure="nan")

        def pt(body: str, name: str) -> np.ndarray:
            m = kin.point(body, name)
            return np.array([m.x[0], m.y[0]])

        host = "coupler" if self.kind == "stephenson" else "rocker"
        o2, a, b, o4 = pt("crank", "O2"), pt("crank", "A"), pt("rocker", "B"), pt("rocker", "O4")
        c, d, o6, p = pt(host, "C"), pt("link5", "D"), pt("link6", "O6"), pt("link5", "P")
        tri = [a, c, b] if self.kind == "stephenson" else [o4, c, b]
        return ([np.array([o2, a, b, o4]), np.array(tri), np.array([c, d, o6]),
                 np.array([c, p, d])], np.array([o2, o4, o6]))

    def to_toml(self, path: str | Path, *, name: str | None = None, n: int = 361) -> Path:
        """A ``planar`` file of the six-bar over the range it runs (``linkwork analyze``
        reads it)."""
        t0 = float(self.params["theta0"])
        th = self.run_range(2) + t0
        p = self.params
        return write_planar_toml(
            self.mechanism(), path, name=name or f"{self.kind} six-bar synthesised by linkwork",
            start=float(th[0]), stop=float(th[-1]), n=n,
            comments=(f"A {self.kind} six-bar path generator synthesised by linkwork "
                      "(linkwork.synthesis.sixbar); plain numbers are SI.",
                      "parameters: " + ", ".join(f"{k} = {float(p[k])!r}"
                                                 for k in SIXBAR_PARAMS)
                      + f", branches B = {self.branches[0]}, D = {self.branches[1]}",
                      "theta2 (crank angles from the frame line at the points) = ["
                      + ", ".join(repr(float(v)) for v in self.theta2) + "]",
                      f"error (sum of squared distances to the targets) = {self.error!r} m^2"))

    def summary(self) -> dict[str, Any]:
        d: dict[str, Any] = {k: float(self.params[k]) for k in SIXBAR_PARAMS}
        d["theta2"] = [float(v) for v in self.theta2]
        d["branch_B"], d["branch_D"] = (int(b) for b in self.branches)
        d["error"] = float(self.error)
        d.update({k: (float(v) if isinstance(v, float | np.floating) else v)
                  for k, v in self.checks.items()})
        return d


@dataclass(frozen=True)
class SixbarResult(Result):
    """Six-bar designs, best first, and what the search did (as
    :class:`~linkwork.synthesis.design.SynthesisResult`; ``samples_per_candidate`` crank
    angles per candidate in the global search)."""

    designs: tuple[SixbarDesign, ...]
    points: np.ndarray
    timing: np.ndarray | None
    closed: bool
    constraints: tuple[str, ...]
    kind: str
    n_evaluated: int
    rejected: Mapping[str, int]
    n_refined: int
    n_residual_evaluations: int
    time: float
    time_global: float
    samples_per_candidate: int
    objective: str = "sum_squares"

    units: ClassVar[dict[str, str]] = {
        **{k: "m" for k in SIXBAR_PARAMS}, "theta0": "rad", "branch_B": "", "branch_D": "",
        "error": "m^2", "max_deviation": "m", "min_transmission_angle": "rad", "rank": ""}
    position_field: ClassVar[str] = "rank"

    @property
    def best(self) -> SixbarDesign:
        return self.designs[0]

    @property
    def rank(self) -> np.ndarray:
        return np.arange(1, len(self.designs) + 1)

    @property
    def candidate_points_per_second(self) -> float:
        """Positions evaluated per second in the global search (designs x crank angles)."""
        return self.n_evaluated * self.samples_per_candidate / max(self.time_global, 1e-12)

    def columns(self) -> dict[str, np.ndarray]:
        return design_columns(self, (*SIXBAR_PARAMS, "branch_B", "branch_D", "error"))

    def _unit_of(self, column: str) -> str:
        return "rad" if column.startswith("theta2_") else self.units.get(column, "")

    def scalars(self) -> dict[str, Any]:
        return {"linkage": self.kind, "n_points": len(self.points), "closed": self.closed,
                "timing": self.timing is not None, "constraints": list(self.constraints),
                "n_evaluated": self.n_evaluated, "rejected": dict(self.rejected),
                "n_refined": self.n_refined,
                "n_residual_evaluations": self.n_residual_evaluations, "time": self.time,
                "time_global": self.time_global,
                "candidate_points_per_second": self.candidate_points_per_second,
                "objective": self.objective,
                "points": [[float(x), float(y)] for x, y in self.points]}

    def to_dict(self) -> dict[str, Any]:
        d = super().to_dict()
        d["designs"] = [x.summary() for x in self.designs]
        return d

    def plot(self, ax: Any = None, n_designs: int = 1, **kw: Any) -> Figure:
        """The coupler curves of the first ``n_designs`` designs against the targets (the
        first design's linkage at its first point): a :class:`linkwork.plot.Figure`."""
        from linkwork.plot.synthesis import path_figure

        return path_figure(self, ax=ax, n_designs=n_designs, **kw)


# ---------------------------------------------------------------------------------------------
# the search
# ---------------------------------------------------------------------------------------------
def _task(points: ArrayLike, kind: str, timing: ArrayLike | None,
          bounds: Mapping[str, tuple[float, float]] | None, constraints: Any, closed: bool,
          free_start: bool) -> PathTask:
    if kind not in KINDS:
        raise ParameterError("kind", kind, "must be 'stephenson' or 'watt'")
    base = task(points, timing=timing, constraints=constraints, closed=closed,
                free_start=free_start)
    b = sixbar_bounds(base.points)
    for k, v in (bounds or {}).items():
        if k not in SIXBAR_PARAMS:
            raise ParameterError("bounds", k, "unknown parameter; known: "
                                 + ", ".join(SIXBAR_PARAMS))
        b[k] = check_bound(k, v, k in ("r1", "r2", "r3", "r4", "r5", "r6"))
    return PathTask(points=base.points, timing=base.timing, closed=base.closed,
                    lo=np.array([b[k][0] for k in SIXBAR_PARAMS]),
                    hi=np.array([b[k][1] for k in SIXBAR_PARAMS]), theta2_bounds=None,
                    grashof=base.grashof, order=base.order, mu_min=base.mu_min,
                    scale=base.scale, free_start=base.free_start,
                    theta0_index=SIXBAR_PARAMS.index("theta0"))


def _candidates(tk: PathTask, n: int, seed: int, kind: str, start: int = 0,
                stop: int | None = None) -> dict[str, np.ndarray]:
    """A scrambled Sobol sample of the free parameters; crank-rockers by construction where
    asked; every other candidate's dyad assembled by construction at the first crank angle
    (D at ``r5`` from C, O6 at ``r6`` from D, in directions drawn from two more dimensions;
    kept only where O6 falls within its bounds); the branch pairs alternating (code 0..3).
    Its candidates ``start .. stop-1`` of ``n``, the same however the sample is cut (as the
    four-bar's), so that each worker of a cluster makes its own chunk."""
    stop = n if stop is None else stop
    free = tk.free
    k = int(free.sum())
    extra = 3 + int(tk.free_start)  # directions of D and O6, a first crank angle
    U = _sobol_rows(k + extra, seed, start, stop)
    index = np.arange(start, stop)
    X = np.tile(tk.lo, (len(U), 1))
    X[:, free] = tk.lo[free] + U[:, :k] * (tk.hi - tk.lo)[free]
    if (tk.grashof or tk.closed) and free[1]:
        crank_rockers(X, U[:, int(free[:1].sum())], tk)
    code = index % 4
    br = _BRANCHES[code].astype(float)
    if tk.timing is not None:
        first = tk.angles(TWO_PI * U[:, k + 3] if tk.free_start else np.zeros(len(U)))[:, 0]
    else:
        first = TWO_PI * U[:, k + 2]
    # the dyad by construction on every other candidate
    sel = index % 2 == 1
    c = _chain(first[sel, None], X[sel], br[sel, :1], br[sel, 1:], kind)
    cx_, cy_ = c["cx"][:, 0], c["cy"][:, 0]
    phi, psi = TWO_PI * U[sel, k], TWO_PI * U[sel, k + 1]
    dx = cx_ + X[sel, 9] * np.cos(phi)
    dy = cy_ + X[sel, 9] * np.sin(phi)
    o6x, o6y = dx + X[sel, 10] * np.cos(psi), dy + X[sel, 10] * np.sin(psi)
    inside = ((c["h2b"][:, 0] >= 0) & (o6x >= tk.lo[11]) & (o6x <= tk.hi[11])
              & (o6y >= tk.lo[12]) & (o6y <= tk.hi[12]) & free[11] & free[12])
    # the dyad's branch: the side of C -> O6 that D was placed on
    side = np.where((o6x - cx_) * (dy - cy_) - (o6y - cy_) * (dx - cx_) > 0, 1.0, -1.0)
    idx = np.flatnonzero(sel)[inside]
    X[idx, 11], X[idx, 12] = o6x[inside], o6y[inside]
    br[idx, 1] = side[inside]
    code = 2 * (br[:, 0] < 0) + (br[:, 1] < 0)
    out = {"X": X, "branch": code.astype(float)}
    if tk.free_start:
        out["start"] = first
    return out


def _screen(chunk: dict[str, np.ndarray], *, tk: PathTask, kind: str, n_samples: int,
            keep: int) -> dict[str, np.ndarray]:
    """Screen one chunk of six-bar candidates in closed form; keep its ``keep`` best."""
    X = np.asarray(chunk["X"], dtype=float)
    code = np.asarray(chunk["branch"], dtype=float)
    br = _BRANCHES[code.astype(int)].astype(float)
    counts = np.zeros(len(DEFECTS))
    closest = np.full(len(DEFECTS), np.inf)
    ok = np.ones(len(X), dtype=bool)
    if tk.grashof or tk.closed:
        g = _crank_rocker_margin(X[:, :4])
        bad = g > 0
        counts[DEFECTS.index("grashof")] += bad.sum()
        if bad.any():
            closest[DEFECTS.index("grashof")] = float(g[bad].min())
        ok &= ~bad
    Xo, bo, co = X[ok], br[ok], code[ok]
    pts = tk.points
    if tk.timing is not None:
        th = tk.angles(np.asarray(chunk["start"], dtype=float)[ok] if tk.free_start
                       else np.zeros(len(Xo))).copy()
        c = _chain(th, Xo, bo[:, :1], bo[:, 1:], kind)
        valid = ((c["h2b"] >= 0) & (c["h2d"] >= 0)).all(axis=1)
        err = ((c["x"] - pts[:, 0]) ** 2 + (c["y"] - pts[:, 1]) ** 2).sum(axis=1)
    else:
        ths = np.linspace(0.0, TWO_PI, n_samples, endpoint=False)
        c = _chain(ths[None, :], Xo, bo[:, :1], bo[:, 1:], kind)
        vs = (c["h2b"] >= 0) & (c["h2d"] >= 0)
        D = ((c["x"][:, None, :] - pts[None, :, 0, None]) ** 2
             + (c["y"][:, None, :] - pts[None, :, 1, None]) ** 2)
        D = np.where(vs[:, None, :], D, np.inf)
        err, th = _ordered(D, vs)
        valid = np.isfinite(err)
    counts[DEFECTS.index("assembly")] += (~valid).sum()
    err = np.where(valid, err, np.inf)
    top = np.argsort(err, kind="stable")[:keep]
    top = top[np.isfinite(err[top])]
    return {"X": Xo[top], "branch": co[top], "theta2": th[top], "err": err[top],
            "counts": counts[None, :], "closest": closest[None, :]}


def _residuals(V: np.ndarray, x15: np.ndarray, tk: PathTask, s: float, br: np.ndarray,
               kind: str, weight: float) -> np.ndarray:
    """Coupler point minus target (x then y) of refinement vectors ``V`` (m, nv), then the
    penalties (zero where the constraints hold)."""
    X, th = _unpack(V, x15, tk.free, tk, s)
    c = _chain(th, X, br[0], br[1], kind)
    wl = weight * tk.scale
    pen = [wl * np.maximum(-c["h2b"], 0.0), wl * np.maximum(-c["h2d"], 0.0)]
    if tk.grashof or tk.closed:
        pen.append(weight * np.maximum(_crank_rocker_margin(X[:, :4]) + 1e-7 * tk.scale,
                                       0.0)[:, None])
    if tk.mu_min is not None:
        lim = math.cos(tk.mu_min)
        pen.append(wl * np.maximum(np.abs(c["cos_b"]) - lim + 1e-9, 0.0))
        pen.append(wl * np.maximum(np.abs(c["cos_d"]) - lim + 1e-9, 0.0))
    if tk.timing is None:
        k = int(tk.free.sum())
        pen.append(wl * np.maximum(V[:, k + 1:].sum(axis=1) - (TWO_PI - 1e-6), 0.0)[:, None])
    R = np.concatenate([c["x"] - tk.points[:, 0], c["y"] - tk.points[:, 1], *pen], axis=1)
    return np.where(np.isfinite(R), R, 10.0 * wl)


def _jacobian(v: np.ndarray, *args: Any) -> np.ndarray:
    """Forward differences of :func:`_residuals`, all columns in one vectorised call."""
    h = 1.5e-8 * np.maximum(np.abs(v), 1.0)
    R = _residuals(np.vstack([v, v + np.diag(h)]), *args)
    return ((R[1:] - R[0]) / h[:, None]).T


def _refine(x15: np.ndarray, code: float, th: np.ndarray, tk: PathTask, kind: str,
            max_nfev: int) -> tuple[np.ndarray, np.ndarray, int]:
    from scipy.optimize import least_squares

    br = _BRANCHES[int(code)].astype(float)
    v, s, blo, bhi = refinement_start(x15, th, tk)
    nfev = 0
    for weight in (1e2, 1e4):
        args = (x15, tk, s, br, kind, weight)
        res = least_squares(lambda u, *a: _residuals(u[None, :], *a)[0], v, jac=_jacobian,
                            bounds=(blo, bhi), method="trf", x_scale="jac", max_nfev=max_nfev,
                            args=args, ftol=1e-15, xtol=1e-15, gtol=1e-15,
                            callback=exact_stop(tk))
        nfev += int(res.nfev) + int(res.njev or 0) * len(v)
        v = res.x
        if not np.any(_residuals(v[None, :], *args)[0, 2 * tk.n:] > 0):
            break
    X, th_r = _unpack(v[None, :], x15, tk.free, tk, s)
    if tk.theta0_periodic:
        wrap_theta0(X, tk)
    return X[0], th_r[0].copy(), nfev


def _check(x: np.ndarray, br: tuple[int, int], th: np.ndarray, tk: PathTask, kind: str
           ) -> tuple[str | None, dict[str, Any]]:
    """The defect checks of a refined design, through the engine: bounds, Grashof where
    asked, order within one turn, assembly at the points, dense tracking between them (no
    unassembled position, no toggle of either loop), the engine's coupler point at the
    targets against the closed form (one circuit), the transmission angle."""
    checks: dict[str, Any] = {}
    rot = bool(_crank_rocker_margin(x[None, :4])[0] < 0)
    checks["crank_rotates"] = rot
    if np.any(x < tk.lo - 1e-9 * tk.scale) or np.any(x > tk.hi + 1e-9 * tk.scale):
        return "bounds", checks
    if (tk.grashof or tk.closed) and not rot:
        return "grashof", checks
    d = np.diff(th)
    fwd, bwd = np.mod(d, TWO_PI), np.mod(-d, TWO_PI)
    s = 1.0 if fwd.sum() <= bwd.sum() else -1.0
    steps = fwd if s > 0 else bwd
    checks["direction"] = int(s)
    if tk.order and steps.sum() > TWO_PI + 1e-9:
        return "order", checks
    arcs = [th[i] + s * np.linspace(0.0, steps[i], max(2, int(steps[i] * TRACK_DENSITY) + 2))
            for i in range(len(th) - 1)]
    if tk.closed or rot:
        back = TWO_PI - steps.sum()
        arcs.append(th[-1] + s * np.linspace(0.0, back, max(2, int(back * TRACK_DENSITY) + 2)))
    dense = np.concatenate(arcs) if arcs else th
    p = dict(zip(SIXBAR_PARAMS, map(float, x), strict=True))
    try:
        kin = kinematics(mechanism(p, kind, br), np.concatenate([th, dense]) + p["theta0"],
                         on_failure="nan")
    except ValueError:
        return "assembly", checks
    n = len(th)
    ok = np.asarray(kin.valid)
    if not ok[:n].all():
        return "assembly", checks
    P = kin.point("link5", "P")
    cx, cy, _ = sixbar_point(th, x[None, :], [br], kind)
    checks["max_deviation"] = float(np.max(np.hypot(P.x[:n] - tk.points[:, 0],
                                                    P.y[:n] - tk.points[:, 1])))
    checks["engine_deviation"] = float(np.max(np.hypot(P.x[:n] - cx[0], P.y[:n] - cy[0])))
    if not checks["engine_deviation"] <= 1e-9 * tk.scale:
        return "circuit", checks
    if not ok[n:].all():
        return "branch", checks
    mu = []
    for a, b in (("coupler", "rocker"), ("link5", "link6")):
        t = np.abs(np.mod(kin.theta[kin.mechanism.index[a], n:]
                          - kin.theta[kin.mechanism.index[b], n:] + math.pi, TWO_PI) - math.pi)
        mu.append(np.minimum(t, math.pi - t).min())
    checks["min_transmission_angle"] = float(min(mu))
    if not checks["min_transmission_angle"] > 1e-6:
        return "branch", checks
    if tk.mu_min is not None and checks["min_transmission_angle"] < tk.mu_min:
        return "transmission", checks
    return None, checks


def sixbar_path(points: ArrayLike, *, kind: Literal["stephenson", "watt"] = "stephenson",
                timing: ArrayLike | None = None,
                bounds: Mapping[str, tuple[float, float]] | None = None,
                constraints: Any = ("order",), closed: bool = False, free_start: bool = False,
                seed: int | None = None, client: Any = None, progress: Any = False,
                n_candidates: int = 2**16, n_samples: int = 90, n_refine: int = 16,
                n_designs: int = 3, chunk_size: int = 2048, max_nfev: int = 1000
                ) -> SixbarResult:
    """Six-bars whose coupler point P (on the dyad's link CD) passes through ``points``,
    defect-free, best first.

    Arguments as :func:`linkwork.synthesis.path.path` (``bounds`` names: :data:`SIXBAR_PARAMS`,
    defaults :func:`sixbar_bounds`; ``"grashof"`` asks the driving four-bar to be a
    crank-rocker with ``r2`` the crank; ``("transmission", mu)`` bounds both loops'
    transmission angles); ``kind`` ``"stephenson"`` or ``"watt"``.

    Raises
    ------
    ParameterError
        Bad points, timing, bounds, kind or search sizes.
    InfeasibleError
        No candidate assembles along the points, or no refined design is free of defects.
    """
    t_start = time.perf_counter()
    tk = _task(points, kind, timing, bounds, constraints, closed, free_start)
    for name, val, least in (("n_candidates", n_candidates, 16), ("n_samples", n_samples, 8),
                             ("n_refine", n_refine, 1), ("n_designs", n_designs, 1),
                             ("chunk_size", chunk_size, 1), ("max_nfev", max_nfev, 10)):
        if isinstance(val, bool) or int(val) != val or val < least:
            raise ParameterError(name, val, f"must be an integer >= {least}")
    if n_candidates > 2**22:
        raise ParameterError("n_candidates", n_candidates, "must be at most 4194304 (2^22)")
    check_client(client)
    cands = Generated(int(n_candidates), functools.partial(
        _candidates, tk, int(n_candidates), _seed(seed), kind))
    keep = max(4 * int(n_refine), 64)
    screen = functools.partial(_screen, kind=kind, n_samples=int(n_samples), keep=keep)
    with _progress_bar(progress, "screening six-bars") as bar:
        res = evaluate(screen, cands, chunk_size=int(chunk_size), client=client, progress=bar,
                       combine=_keep_best(keep), shared={"tk": tk})
    t_global = time.perf_counter() - t_start
    rejected = {k: int(v) for k, v in zip(DEFECTS, res["counts"].sum(axis=0), strict=True)}
    if len(res["err"]) == 0:
        raise InfeasibleError("a six-bar within the bounds whose coupler point reaches the "
                              "points", f"none of {int(n_candidates)} candidates assembles "
                              "along them", ", ".join(f"{v} {k}" for k, v in rejected.items()
                                                      if v))
    starts = _distinct(np.c_[res["X"], res["branch"]], range(len(res["err"])),
                       np.append(tk.hi - tk.lo, 4.0), int(n_refine))
    designs: list[SixbarDesign] = []
    nres = 0
    # successive halving: every start refined briefly, the better third then to convergence
    first = []
    for i in starts:
        code = float(res["branch"][i])
        x, th, nf = _refine(res["X"][i], code, res["theta2"][i], tk, kind,
                            max(int(max_nfev) // 4, 10))
        nres += nf
        vec, sense = _vector(x, th, tk)
        r = _residuals(vec[None, :], x, tk, sense, _BRANCHES[int(code)].astype(float), kind,
                       1e4)
        first.append((float(np.sum(r ** 2)), x, th, code))
    first.sort(key=lambda f: f[0])
    keep_n = max(3, len(first) // 3)
    refined = []
    for _, x, th, code in first[:keep_n]:
        x, th, nf = _refine(x, code, th, tk, kind, int(max_nfev))
        nres += nf
        refined.append((x, th, code))
    refined += [(x, th, code) for _, x, th, code in first[keep_n:]]
    for x, th, code in refined:
        br = tuple(int(b) for b in _BRANCHES[int(code)])
        defect, checks = _check(x, (br[0], br[1]), th, tk, kind)
        if defect is not None:
            rejected[defect] += 1
            continue
        px, py, _ = sixbar_point(th, x[None, :], [br], kind)
        e = float(np.sum((px[0] - tk.points[:, 0]) ** 2 + (py[0] - tk.points[:, 1]) ** 2))
        params: dict[str, Any] = {k: float(v) for k, v in zip(SIXBAR_PARAMS, x, strict=True)}
        params["theta2"] = [float(v) for v in np.mod(th, TWO_PI)]
        designs.append(SixbarDesign(kind, params, (br[0], br[1]), e, tk.points, tk.closed,
                                    checks))
    if not designs:
        raise InfeasibleError("a defect-free six-bar through the points",
                              f"all {len(starts)} refined designs defective",
                              ", ".join(f"{v} {k}" for k, v in rejected.items() if v))
    designs.sort(key=lambda d: d.error)
    Xd = np.array([[*d.vector, 2 * (d.branches[0] < 0) + (d.branches[1] < 0)]
                   for d in designs])
    keep_i = _distinct(Xd, range(len(designs)), np.append(tk.hi - tk.lo, 4.0), len(designs))
    return SixbarResult(designs=tuple(designs[i] for i in keep_i[:int(n_designs)]),
                        points=tk.points, timing=tk.timing, closed=tk.closed,
                        constraints=tk.constraint_names(), kind=kind,
                        n_evaluated=int(n_candidates), rejected=rejected, n_refined=len(starts),
                        n_residual_evaluations=nres, time=time.perf_counter() - t_start,
                        time_global=t_global,
                        samples_per_candidate=tk.n if tk.timing is not None else int(n_samples))

