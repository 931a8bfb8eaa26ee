r"""Path generation by the coupler point of a Watt II or Stephenson III six-bar, through the
planar engine.

Both six-bars are a driving four-bar O2-A-B-O4 (the literature's ``r1 r2 r3 r4 x0 y0 theta0``
as in :mod:`linkwork.synthesis.design`) and a dyad C-D-O6 driven by a point C of one of its
links; the traced point P is on the dyad's link CD:

* ``"stephenson"`` (Stephenson III): C on the four-bar's coupler, ``(cx, cy)`` in the coupler's
  frame (origin A, x along A -> B);
* ``"watt"`` (Watt II): C on the four-bar's rocker, ``(cx, cy)`` in the rocker's frame (origin
  O4, x along O4 -> B).

The dyad: ``r5`` = CD, ``r6`` = O6D with the fixed pivot ``O6 = (x6, y6)``; P at ``(px, py)``
in the frame of CD (origin C, x along C -> D). Branches: ``B`` of the four-bar, ``D`` of the dyad
(the engine's RRR convention: the joint on the left of the line from the first body's external
joint to the second's). Crank angles ``theta2`` from the frame line, as for the four-bar.

Every candidate is evaluated by the engine (:func:`linkwork.planar.kinematics.kinematics`), one
design at a time: :func:`coupler_points` takes the designs as an array and loops over them, so
that the engine's batch over designs (a later change of the engine) can replace the loop
without touching the search. The search is that of :func:`linkwork.synthesis.path.path`: a
Sobol sample screened with the ordered timing assignment, ``least_squares`` refinement of the
exact residuals, defect checks by dense engine tracking.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from linkwork.errors import InfeasibleError, ParameterError
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import Body, Crank, Mechanism, Revolute, bar
from linkwork.synthesis.design import write_planar_toml
from linkwork.synthesis.path import _crank_rocker_margin, _ordered, default_bounds, task

__all__ = ["SIXBAR_PARAMS", "SixbarDesign", "SixbarResult", "coupler_points", "mechanism",
           "sixbar_path"]

TWO_PI = 2 * math.pi

#: Parameters of a six-bar path generator (lengths [m], theta0 [rad]).
SIXBAR_PARAMS = ("r1", "r2", "r3", "r4", "x0", "y0", "theta0", "cx", "cy", "r5", "r6", "x6",
                 "y6", "px", "py")


def mechanism(p: Mapping[str, float], kind: str, branches: tuple[int, int] = (1, 1),
              omega1: float = 1.0) -> Mechanism:
    """The engine model of a six-bar design: frame points O2, O4, O6; bodies crank (O2 -> A),
    coupler (A, B; and C for Stephenson), rocker (O4 -> B; and C for Watt), link5 (C, D, P),
    link6 (O6 -> D); the crank drives at O2 (``phi1 = theta0 + theta2``)."""
    t0 = p["theta0"]
    o2 = (p["x0"], p["y0"])
    o4 = (p["x0"] + p["r1"] * math.cos(t0), p["y0"] + p["r1"] * math.sin(t0))
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
                     Crank("O2", omega1, 0.0), {"B": int(branches[0]), "D": int(branches[1])})


def coupler_points(X: np.ndarray, branches: np.ndarray, theta2: np.ndarray, kind: str
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coupler point P (x, y) and validity of designs ``X`` (m, 15) on ``branches`` (m, 2) at
    crank angles ``theta2`` (n,) or (m, n): arrays (m, n). One engine call per design (the
    engine's batch over designs would replace this loop)."""
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


def sixbar_bounds(points: np.ndarray) -> dict[str, tuple[float, float]]:
    """Default bounds from the targets (as :func:`linkwork.synthesis.path.default_bounds`)."""
    b = default_bounds(points)
    L = b["r1"][1] / 3.0
    out = {k: b[k] for k in ("r1", "r2", "r3", "r4", "x0", "y0", "theta0")}
    out |= {"cx": (-3 * L, 3 * L), "cy": (-3 * L, 3 * L), "r5": b["r1"], "r6": b["r1"],
            "x6": b["x0"], "y6": b["y0"], "px": (-3 * L, 3 * L), "py": (-3 * L, 3 * L)}
    return out


@dataclass(frozen=True)
class SixbarDesign:
    """A six-bar path generator: ``params`` (:data:`SIXBAR_PARAMS` and ``theta2``), ``kind``,
    ``branches`` (B, D), ``error`` [m^2], ``checks``."""

    kind: str
    params: Mapping[str, Any]
    branches: tuple[int, int]
    error: float
    points: np.ndarray
    checks: Mapping[str, Any] = field(default_factory=dict)

    @property
    def theta2(self) -> np.ndarray:
        return np.asarray(self.params["theta2"], dtype=float)

    def mechanism(self, omega1: float = 1.0) -> Mechanism:
        return mechanism(self.params, self.kind, self.branches, omega1)

    def to_toml(self, path: str | Path, *, name: str | None = None, n: int = 361) -> Path:
        """A ``planar`` file of the six-bar over the crank's range from the first to the last
        point (a full turn when the checks found the crank turning)."""
        t0 = float(self.params["theta0"])
        th = self.theta2
        span = TWO_PI if self.checks.get("crank_rotates") else float(th[-1] - th[0])
        return write_planar_toml(
            self.mechanism(), path, name=name or f"{self.kind} six-bar synthesised by linkwork",
            start=t0 + float(th[0]), stop=t0 + float(th[0]) + span, n=n,
            comments=(f"A {self.kind} six-bar path generator synthesised by linkwork.",
                      f"error = {self.error!r} m^2"))


@dataclass(frozen=True)
class SixbarResult:
    """Six-bar designs, best first, and what the search did (as
    :class:`~linkwork.synthesis.design.SynthesisResult`)."""

    designs: tuple[SixbarDesign, ...]
    points: np.ndarray
    n_evaluated: int
    rejected: dict[str, int]
    n_residual_evaluations: int
    time: float
    time_global: float
    samples_per_candidate: int

    @property
    def best(self) -> SixbarDesign:
        return self.designs[0]

    @property
    def candidate_points_per_second(self) -> float:
        """Engine positions evaluated per second in the global search (designs x angles)."""
        return self.n_evaluated * self.samples_per_candidate / max(self.time_global, 1e-12)


def _check(x: np.ndarray, br: tuple[int, int], th: np.ndarray, tk: Any, kind: str
           ) -> tuple[str | None, dict[str, Any]]:
    """Order within one turn, assembly at the points, dense engine tracking between them."""
    checks: dict[str, Any] = {}
    rot = bool(_crank_rocker_margin(x[None, :4])[0] < 0)
    checks["crank_rotates"] = rot
    if tk.grashof and not rot:
        return "grashof", checks
    d = np.diff(th)
    fwd, bwd = np.mod(d, TWO_PI), np.mod(-d, TWO_PI)
    s = 1.0 if fwd.sum() <= bwd.sum() else -1.0
    steps = fwd if s > 0 else bwd
    if tk.order and steps.sum() > TWO_PI + 1e-9:
        return "order", checks
    arcs = [th[i] + s * np.linspace(0.0, steps[i], max(2, int(steps[i] * 60) + 2))
            for i in range(len(th) - 1)]
    if tk.closed:
        back = TWO_PI - steps.sum()
        arcs.append(th[-1] + s * np.linspace(0.0, back, max(2, int(back * 60) + 2)))
    dense = np.concatenate(arcs) if arcs else th
    xs, ys, ok = coupler_points(x[None, :], np.array([br]), np.concatenate([th, dense]), kind)
    n = len(th)
    if not ok[0, :n].all():
        return "assembly", checks
    if not ok[0, n:].all():
        return "branch", checks
    checks["max_deviation"] = float(np.max(np.hypot(xs[0, :n] - tk.points[:, 0],
                                                    ys[0, :n] - tk.points[:, 1])))
    return None, checks


def sixbar_path(points: ArrayLike, *, kind: Literal["stephenson", "watt"] = "stephenson",
                timing: ArrayLike | None = None,
                bounds: Mapping[str, tuple[float, float]] | None = None,
                constraints: Any = ("order",), closed: bool = False, seed: int | None = None,
                n_candidates: int = 2048, n_samples: int = 90, n_refine: int = 6,
                n_designs: int = 3, max_nfev: int = 300) -> SixbarResult:
    """Six-bars whose coupler point P (on the dyad's link CD) passes through ``points``.

    Arguments as :func:`linkwork.synthesis.path.path` (``bounds`` names: :data:`SIXBAR_PARAMS`
    and ``theta2``; ``"grashof"`` asks the driving four-bar to be a crank-rocker); the global
    search evaluates ``n_candidates`` designs through the engine, one at a time
    (:func:`coupler_points`), at ``n_samples`` crank angles each.

    Raises
    ------
    ParameterError
        Bad points, timing, bounds or kind.
    InfeasibleError
        No candidate assembles, or no refined design is free of defects.
    """
    from scipy.optimize import least_squares
    from scipy.stats import qmc

    if kind not in ("stephenson", "watt"):
        raise ParameterError("kind", kind, "must be 'stephenson' or 'watt'")
    t_start = time.perf_counter()
    tk = task(points, timing=timing, constraints=constraints, closed=closed)
    b = sixbar_bounds(tk.points)
    for k, v in (bounds or {}).items():
        if k == "theta2":
            continue
        if k not in SIXBAR_PARAMS:
            raise ParameterError("bounds", k, f"unknown parameter; known: "
                                 f"{', '.join(SIXBAR_PARAMS)}")
        lo_k, hi_k = float(v[0]), float(v[1])
        if not lo_k <= hi_k:
            raise ParameterError(f"bounds[{k}]", (lo_k, hi_k), "needs low <= high")
        b[k] = (lo_k, hi_k)
    lo = np.array([b[k][0] for k in SIXBAR_PARAMS])
    hi = np.array([b[k][1] for k in SIXBAR_PARAMS])
    free = hi > lo
    m = max(4, math.ceil(math.log2(max(int(n_candidates), 2))))
    U = qmc.Sobol(int(free.sum()), scramble=True, seed=seed).random_base2(m)[:n_candidates]
    X = np.tile(lo, (len(U), 1))
    X[:, free] = lo[free] + U * (hi - lo)[free]
    brs = np.array([(1, 1), (1, -1), (-1, 1), (-1, -1)])[np.arange(len(U)) % 4]
    rejected: dict[str, int] = {"assembly": 0, "grashof": 0, "order": 0, "branch": 0}
    if tk.grashof:
        bad = _crank_rocker_margin(X[:, :4]) >= 0
        rejected["grashof"] += int(bad.sum())
        X, brs = X[~bad], brs[~bad]
    if tk.timing is not None:
        xs, ys, ok = coupler_points(X, brs, tk.timing, kind)
        err = np.where(ok.all(axis=1), ((xs - tk.points[:, 0]) ** 2
                                        + (ys - tk.points[:, 1]) ** 2).sum(axis=1), np.inf)
        ths = np.broadcast_to(tk.timing, (len(X), tk.n))
    else:
        samp = np.linspace(0.0, TWO_PI, int(n_samples), endpoint=False)
        xs, ys, ok = coupler_points(X, brs, samp, kind)
        D = ((xs[:, None, :] - tk.points[None, :, 0, None]) ** 2
             + (ys[:, None, :] - tk.points[None, :, 1, None]) ** 2)
        D = np.where(ok[:, None, :], D, np.inf)
        err, ths = _ordered(D, ok)
    rejected["assembly"] += int((~np.isfinite(err)).sum())
    t_global = time.perf_counter() - t_start
    order = np.argsort(err)[: int(n_refine)]
    order = order[np.isfinite(err[order])]
    if len(order) == 0:
        raise InfeasibleError("a six-bar within the bounds whose coupler point reaches the "
                              "points", f"none of {len(X)} candidates assembles along them")
    designs: list[SixbarDesign] = []
    nres = 0
    for i in order:
        x0 = X[i].copy()
        br = (int(brs[i][0]), int(brs[i][1]))
        th0 = np.asarray(ths[i], dtype=float)
        nf = int(free.sum())
        if tk.timing is None:
            d = np.diff(th0)
            s = 1.0 if d.sum() >= 0 else -1.0
            v0 = np.concatenate([x0[free], [th0[0]], np.abs(d) + 1e-6])
            vlo = np.concatenate([lo[free], [-np.inf], np.zeros(len(d))])
            vhi = np.concatenate([hi[free], [np.inf], np.full(len(d), TWO_PI)])
        else:
            s = 1.0
            v0, vlo, vhi = x0[free], lo[free], hi[free]

        def unpack(v: np.ndarray, x0: np.ndarray = x0, s: float = s, nf: int = nf
                   ) -> tuple[np.ndarray, np.ndarray]:
            x = x0.copy()
            x[free] = v[:nf]
            th = tk.timing if tk.timing is not None else v[nf] + s * np.concatenate(
                [[0.0], np.cumsum(v[nf + 1:])])
            return x, np.asarray(th, dtype=float)

        def res(v: np.ndarray, br: tuple[int, int] = br) -> np.ndarray:
            x, th = unpack(v)
            px, py, _ = coupler_points(x[None, :], np.array([br]), th, kind)
            r = np.concatenate([px[0] - tk.points[:, 0], py[0] - tk.points[:, 1]])
            return np.where(np.isfinite(r), r, 10.0 * tk.scale)

        fin = np.isfinite(vlo) & np.isfinite(vhi)
        sp = np.where(fin, vhi - vlo, 0.0)
        v0 = np.clip(v0, np.where(fin, vlo + 1e-9 * sp, vlo), np.where(fin, vhi - 1e-9 * sp,
                                                                        vhi))
        sol = least_squares(res, v0, bounds=(vlo, vhi), x_scale="jac", max_nfev=max_nfev,
                            ftol=1e-15, xtol=1e-15, gtol=1e-15)
        nres += int(sol.nfev) + int(sol.njev or 0) * len(v0)
        x, th = unpack(sol.x)
        defect, checks = _check(x, br, th, tk, kind)
        if defect is not None:
            rejected[defect] = rejected.get(defect, 0) + 1
            continue
        px, py, _ = coupler_points(x[None, :], np.array([br]), th, kind)
        e = float(np.sum((px[0] - tk.points[:, 0]) ** 2 + (py[0] - tk.points[:, 1]) ** 2))
        params: dict[str, Any] = {kk: float(v) for kk, v in zip(SIXBAR_PARAMS, x, strict=True)}
        params["theta2"] = [float(v) for v in np.mod(th, TWO_PI)]
        designs.append(SixbarDesign(kind, params, br, e, tk.points, checks))
    if not designs:
        raise InfeasibleError("a defect-free six-bar through the points",
                              "every refined design defective",
                              ", ".join(f"{v} {k}" for k, v in rejected.items() if v))
    designs.sort(key=lambda d: d.error)
    return SixbarResult(designs=tuple(designs[:n_designs]), points=tk.points,
                        n_evaluated=len(U), rejected=rejected, n_residual_evaluations=nres,
                        time=time.perf_counter() - t_start, time_global=t_global,
                        samples_per_candidate=tk.n if tk.timing is not None else int(n_samples))
