"""Four-bar path synthesis on the literature's test problems: linkwork, the published designs
and pylinkage's optimiser side by side.

The problems and the published designs are data, with where each was read:
``benchmarks/data/synthesis_literature.toml`` (targets, timing, bounds and constraints as the
sources state them; the designs as printed). The error is the literature's, f = the sum of
squared distances between the coupler point and the targets, in the problem's units squared.

* **Published designs.** Each design is recomputed in linkwork's parametrisation
  (:func:`linkwork.synthesis.design.coupler_point` on the assembly branch the sources' fixed
  root gives, :func:`published`) and run through linkwork's own defect checks
  (:func:`linkwork.synthesis.path.check_design`: order, one circuit and no toggle between the
  points by dense engine tracking, Grashof crank-rocker with ``r2`` the crank) with its
  transmission angle; :func:`printed_check` compares the recomputed error with the value the
  sources print, within the printed precision (half a unit of the printed value's last digit
  plus what rounding the design's printed digits can change).
* **linkwork**: :func:`linkwork.synthesis.path.path` with the problem's bounds and
  constraints; error, wall time (min / median / max over seeds), candidates screened and
  residual evaluations; its best design rechecked by :func:`published`'s checks.
* **pylinkage**: its particle-swarm optimiser (``pylinkage.optimization.
  particle_swarm_optimization``, 100 particles, 200 iterations: its defaults) over the same
  literature parameters and bounds, its own simulation (``Linkage.step_fast``: the coupler
  point from the crank's start angle, steps equal to the timing's, or a full turn in 1 degree
  steps with each target's nearest point for free timing: order not required, generous to
  it) as the fitness; its best design recomputed and checked as the published ones.
* **dask**: linkwork's global search (timed alone; ``n_refine = 4``) in-process and on
  ``LocalCluster(processes=True)`` with 1 and 2 workers (:func:`run_dask`).

Usage::

    .venv/bin/python benchmarks/synthesis.py [--repeat 3] [--problems six-line,arc-6-timing]
        [--no-published] [--no-pylinkage] [--no-dask] [--no-throughput]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
import tomllib
from decimal import Decimal
from pathlib import Path
from typing import Any

import numpy as np

from linkwork.synthesis.design import PARAMS, coupler_point
from linkwork.synthesis.path import check_design, path, task

PI = math.pi
DATA = Path(__file__).resolve().parent / "data" / "synthesis_literature.toml"


# ---------------------------------------------------------------------------------------------
# the problems
# ---------------------------------------------------------------------------------------------
def _planted() -> dict[str, Any]:
    p = dict(r1=4.0, r2=1.0, r3=3.5, r4=3.0, rcx=1.5, rcy=1.2, x0=0.5, y0=-0.3, theta0=0.3)
    x, y, _ = coupler_point(np.linspace(0.2, 5.5, 8), p, 1)
    return {"id": "planted", "name": "eight points of a known crank-rocker, free timing",
            "origin": "a known crank-rocker: f = 0 exactly", "points": np.c_[x, y],
            "timing": None, "free_start": False, "closed": False, "fixed": {},
            "constraints": ("grashof", "order"), "bounds": None, "design": []}


def load(data: Path = DATA) -> dict[str, dict[str, Any]]:
    """The problems of the data file (and the planted one), by id: points (n, 2), timing [rad]
    or None, free_start, closed, fixed parameters, constraints (with "order" for free timing),
    bounds (fixed parameters as equal bounds) and the published designs as printed."""
    with open(data, "rb") as f:
        raw = tomllib.load(f)
    out = {}
    for pb in raw["problem"]:
        pts = np.array(pb["points"], dtype=float)
        timing = None
        if "timing_deg" in pb:
            timing = np.radians(np.array(pb["timing_deg"], dtype=float))
        elif "timing_step_deg" in pb:
            timing = math.radians(pb["timing_step_deg"]) * np.arange(len(pts))
        bounds = {k: (float(v[0]), float(v[1])) for k, v in pb["bounds"].items()}
        bounds |= {k: (float(v), float(v)) for k, v in pb.get("fixed", {}).items()}
        cons = tuple(pb["constraints"]) + (("order",) if timing is None else ())
        out[pb["id"]] = {**pb, "points": pts, "timing": timing,
                         "free_start": "timing_step_deg" in pb,
                         "closed": bool(pb.get("closed", False)),
                         "fixed": dict(pb.get("fixed", {})), "constraints": cons,
                         "bounds": bounds, "design": list(pb.get("design", []))}
    for base, mu in VARIANTS:  # the same problem with a minimum transmission angle asked
        pb = out[base]
        out[f"{base}-mu{mu}"] = {**pb, "id": f"{base}-mu{mu}",
                                 "name": f"{pb['name']}, transmission angle >= {mu} deg",
                                 "constraints": (*pb["constraints"],
                                                 ("transmission", math.radians(mu)))}
    out["planted"] = _planted()
    return out


#: Problems also run with a minimum transmission angle [deg] (not in the literature: the best
#: published designs of the semicircle run through a change point).
VARIANTS = (("arc-6-timing", 30),)


PROBLEMS = load()
#: The problems of the literature (the data file's), without variants and the planted one.
LITERATURE = tuple(k for k in PROBLEMS if k != "planted" and "-mu" not in k)


# ---------------------------------------------------------------------------------------------
# published designs: recomputation, printed values, defect checks
# ---------------------------------------------------------------------------------------------
def _sources_side(p: dict[str, float], th: float, root: str) -> int:
    """The assembly branch (linkwork's: +1 where B lies left of A -> O4) of the sources' fixed
    root of Norton's half-angle form, theta3 = 2 atan((-E -+ sqrt(E^2 - 4 D F)) / (2 D))."""
    r1, r2, r3, r4 = p["r1"], p["r2"], p["r3"], p["r4"]
    k1, k4, k5 = r1 / r2, r1 / r3, (r4 * r4 - r1 * r1 - r2 * r2 - r3 * r3) / (2 * r2 * r3)
    d = math.cos(th) - k1 + k4 * math.cos(th) + k5
    e = -2 * math.sin(th)
    f = k1 + (k4 - 1) * math.cos(th) + k5
    sq = math.sqrt(max(e * e - 4 * d * f, 0.0))
    t3 = 2 * math.atan((-e + (sq if root == "+" else -sq)) / (2 * d))
    ax, ay = r2 * math.cos(th), r2 * math.sin(th)
    bx, by = ax + r3 * math.cos(t3), ay + r3 * math.sin(t3)
    return 1 if (r1 - ax) * (by - ay) + ay * (bx - ax) > 0 else -1


def _values(d: dict[str, Any], override: dict[str, float] | None = None) -> dict[str, float]:
    if d.get("form") == "S2":
        v = {k: float(s) for k, s in d["s2"].items()}
    else:
        v = {f"x{i}": float(s) for i, s in enumerate(d["x"])}
    v.update(override or {})
    return v


def _nearest_in_order(p: dict[str, float], branch: int, pts: np.ndarray
                      ) -> tuple[np.ndarray, float]:
    """Crank angles of the targets' nearest points on the coupler curve, in order (either
    sense), polished per point (bounded scalar search): for designs printed without them."""
    from scipy.optimize import minimize_scalar

    from linkwork.synthesis.path import _ordered

    m = 3600
    th = np.linspace(0, 2 * PI, m, endpoint=False)
    x, y, ok = coupler_point(th, p, branch)
    D = (x[None, :] - pts[:, :1]) ** 2 + (y[None, :] - pts[:, 1:]) ** 2
    D = np.where(ok[None, :], D, np.inf)[None]
    _, t = _ordered(D, None if ok.all() else ok[None])
    out = []
    for (px, py), t0 in zip(pts, t[0], strict=True):
        def g(a: float, px: float = px, py: float = py) -> float:
            xx, yy, _ = coupler_point(np.array([a]), p, branch)
            v = float((xx[0] - px) ** 2 + (yy[0] - py) ** 2)
            return v if math.isfinite(v) else math.inf
        r = minimize_scalar(g, bounds=(t0 - 2 * PI / m, t0 + 2 * PI / m), method="bounded",
                            options={"xatol": 1e-13})
        out.append(float(r.x))
    tt = np.array(out)
    x, y, _ = coupler_point(tt, p, branch)
    return tt, float(np.sum((x - pts[:, 0]) ** 2 + (y - pts[:, 1]) ** 2))


def published(pb: dict[str, Any], d: dict[str, Any], override: dict[str, float] | None = None
              ) -> tuple[dict[str, Any], int, str]:
    """A published design in linkwork's parameters: (params with ``theta2``, branch, note).

    Designs in the sources' vector form take the branch of their fixed root (at the first
    point; the note says if it changes between points). S2's designs (polar coupler point,
    degrees, no crank angles) take the targets' nearest points on the coupler curve in order,
    on the branch that gives the smaller error."""
    v = _values(d, override)
    pts = pb["points"]
    if d.get("form") == "S2":
        p = {"r1": v["g"], "r2": v["d"], "r3": v["c"], "r4": v["f"],
             "rcx": v["l"] * math.cos(math.radians(v["eta_deg"])),
             "rcy": v["l"] * math.sin(math.radians(v["eta_deg"])),
             "x0": v["sx"], "y0": v["sy"], "theta0": math.radians(v["gamma_deg"])}
        fits = [(_nearest_in_order(p, br, pts), br) for br in (1, -1)]
        (th, _), br = min(fits, key=lambda f: f[0][1])
        return dict(p, theta2=list(th)), br, "crank angles not printed: nearest points, in order"
    p = dict(pb["fixed"])
    p.update({name: v[f"x{i}"] for i, name in enumerate(pb["variables"])})
    n = len(pts)
    if pb["timing"] is None:
        th = np.array([p[f"theta2_{i + 1}"] for i in range(n)])
    elif pb["free_start"]:
        th = p["theta2_1"] + pb["timing"]
    else:
        th = pb["timing"]
    root = d.get("root", "-")
    sides = {_sources_side(p, float(t), root) for t in th}
    note = "" if len(sides) == 1 else "the sources' fixed root changes branch between points"
    params: dict[str, Any] = {k: float(p[k]) for k in PARAMS}
    params["theta2"] = [float(t) for t in th]
    return params, _sources_side(p, float(th[0]), root), note


def error_of(pb: dict[str, Any], params: dict[str, Any], branch: int) -> float:
    """The literature's error f of a design on ``branch`` (inf where a point does not
    assemble)."""
    x, y, ok = coupler_point(np.asarray(params["theta2"]), params, branch)
    pts = pb["points"]
    return float(np.sum((x - pts[:, 0]) ** 2 + (y - pts[:, 1]) ** 2)) if ok.all() else math.inf


def _half_unit(s: str) -> float:
    """Half a unit in the last printed digit of a number printed as ``s``."""
    return 0.5 * 10.0 ** Decimal(s.strip()).as_tuple().exponent  # type: ignore[operator]


_S2_NAMES = {"g": "r1", "d": "r2", "c": "r3", "f": "r4", "sx": "x0", "sy": "y0",
             "gamma_deg": "theta0"}


def _on_bound(pb: dict[str, Any], d: dict[str, Any], key: str, value: float) -> bool:
    """Whether a design's printed number sits exactly on a bound of its parameter."""
    if d.get("form") == "S2":
        name = _S2_NAMES.get(key)
        value = math.radians(value) if key == "gamma_deg" else value
    else:
        name = pb["variables"][int(key[1:])]
    lim = pb["bounds"].get(name) if name else None
    return lim is not None and value in lim


def printed_check(pb: dict[str, Any], d: dict[str, Any]) -> dict[str, float]:
    """The recomputed error against the value the sources print: ``recomputed``, ``printed``
    and the tolerance ``tol`` = half a unit of the printed value's last digit + the sum over
    the design's printed numbers of the largest change of f when each moves by half a unit of
    its own last digit (the first-order bound of what their rounding can change; a number
    printed on a bound of the problem is taken as that bound); ``at_most`` for designs printed
    without crank angles (see :func:`printed_agrees`)."""
    params, br, _ = published(pb, d)
    f0 = error_of(pb, params, br)
    keys = list(d["s2"]) if d.get("form") == "S2" else [f"x{i}" for i in range(len(d["x"]))]
    texts = d["s2"] if d.get("form") == "S2" else {f"x{i}": s for i, s in enumerate(d["x"])}
    base = _values(d)
    rounding = 0.0
    for k in keys:
        if _on_bound(pb, d, k, base[k]):
            continue  # a number printed on a bound of the problem (60, 0) is that bound
        h = _half_unit(texts[k])
        ch = []
        for sgn in (1.0, -1.0):
            pp, bb, _ = published(pb, d, {k: base[k] + sgn * h})
            ch.append(abs(error_of(pb, pp, bb) - f0))
        rounding += max(ch)
    printed = float(d["printed"])
    return {"recomputed": f0, "printed": printed, "tol": _half_unit(d["printed"]) + rounding,
            "at_most": d.get("form") == "S2"}


def printed_agrees(c: dict[str, float]) -> bool:
    """The recomputation equals the printed value within the tolerance; for a design printed
    without its crank angles (recomputed at the targets' nearest points, the least error its
    curve allows) it is at most the printed value plus the tolerance."""
    if c["at_most"]:
        return c["recomputed"] <= c["printed"] + c["tol"]
    return abs(c["recomputed"] - c["printed"]) <= c["tol"]


def defects(pb: dict[str, Any], params: dict[str, Any], branch: int) -> dict[str, Any]:
    """linkwork's defect checks of a design for the problem (bounds apart: ``in_bounds``):
    ``defect`` (None, or grashof / assembly / order / circuit / branch), the Grashof class, its
    margin (p + q - s - l, > 0 rotates fully), the minimum transmission angle [deg]."""
    wide = {k: (1e-12, 1e12) for k in ("r1", "r2", "r3", "r4")}
    wide |= {k: (-1e12, 1e12) for k in ("rcx", "rcy", "x0", "y0", "theta0")}
    tk = task(pb["points"], timing=pb["timing"], bounds=wide, constraints=pb["constraints"],
              closed=pb["closed"], free_start=pb["free_start"])
    defect, checks = check_design(params, branch, tk)
    r = sorted(params[k] for k in ("r1", "r2", "r3", "r4"))
    bounds = pb["bounds"] or {}
    inb = all(bounds[k][0] - 1e-9 <= params[k] <= bounds[k][1] + 1e-9
              for k in bounds if k != "theta0")
    shortest = min(("r1", "r2", "r3", "r4"), key=lambda k: params[k])
    return {"defect": defect, "grashof": checks.get("grashof"), "shortest": shortest,
            "margin": r[1] + r[2] - r[0] - r[3],
            "mu_min": math.degrees(checks.get("min_transmission_angle", math.nan)),
            "in_bounds": inb}


def published_table(names: list[str]) -> list[dict[str, Any]]:
    """Every published design of the problems: recomputed error, printed value, checks."""
    rows = []
    for name in names:
        pb = PROBLEMS[name]
        for d in pb["design"]:
            params, br, note = published(pb, d)
            row = {"problem": name, "who": d["who"], "source": d["source"],
                   "error": error_of(pb, params, br), "branch": br, "note": note,
                   **defects(pb, params, br)}
            if "printed" in d:
                row |= {"printed_" + k: v for k, v in printed_check(pb, d).items()}
            rows.append(row)
    return rows


def best_published(rows: list[dict[str, Any]], name: str, passing: bool
                   ) -> dict[str, Any] | None:
    """The smallest published error of a problem (of a design that passes the checks, within
    the bounds, when ``passing``)."""
    cand = [r for r in rows if r["problem"] == name
            and (not passing or (r["defect"] is None and r["in_bounds"]))]
    return min(cand, key=lambda r: r["error"]) if cand else None


# ---------------------------------------------------------------------------------------------
# contenders
# ---------------------------------------------------------------------------------------------
def run_linkwork(name: str, seed: int, **kw: Any) -> dict[str, Any]:
    pb = PROBLEMS[name]
    t = time.perf_counter()
    res = path(pb["points"], timing=pb["timing"], bounds=pb["bounds"],
               constraints=pb["constraints"], closed=pb["closed"],
               free_start=pb["free_start"], seed=seed, progress=False, **kw)
    wall = time.perf_counter() - t
    d = res.best
    return {"error": d.error, "time": wall, "time_global": res.time_global,
            "candidates": res.n_evaluated, "residuals": res.n_residual_evaluations,
            "mu_min": math.degrees(d.checks.get("min_transmission_angle", math.nan)),
            "rejected": sum(res.rejected.values()), "design": d,
            **{"check_" + k: v for k, v in defects(pb, dict(d.params), d.branch).items()}}


def _pylinkage_fourbar() -> tuple[Any, Any]:
    from pylinkage import Crank, FixedDyad, Ground, RRRDyad
    from pylinkage.simulation import Linkage

    o2, o4 = Ground(0.0, 0.0, name="O2"), Ground(1.0, 0.0, name="O4")
    crank = Crank(o2, radius=0.3, angular_velocity=0.1, name="A")
    rocker = RRRDyad(crank.output, o4, distance1=1.0, distance2=1.0, name="B")
    point = FixedDyad(crank.output, rocker, distance=0.5, angle=0.3, name="P")
    return Linkage([o2, o4, crank, rocker, point], name="four-bar"), crank


def _pylinkage_sim(lk: Any, crank: Any, v: np.ndarray, start: float, step: float, n: int
                   ) -> np.ndarray:
    """pylinkage's positions (steps, [O2, O4, A, B, P], 2) over ``n`` crank steps of ``step``
    from the crank angle ``start`` (from the frame line), for literature parameters ``v[:9]``
    and B first placed on the side ``v[-1]`` (> 0: left of A -> O4); NaN where it does not
    assemble."""
    r1, r2, r3, r4, rcx, rcy, x0, y0, t0 = v[:9]
    o2 = np.array([x0, y0])
    o4 = o2 + r1 * np.array([math.cos(t0), math.sin(t0)])
    a0 = t0 + start - step
    a = o2 + r2 * np.array([math.cos(a0), math.sin(a0)])
    dd = o4 - a
    nrm = float(np.hypot(*dd)) or 1.0
    b = a + 0.5 * dd + math.copysign(r3, v[-1]) * np.array([-dd[1], dd[0]]) / nrm
    lk.set_constraints([r2, r3, r4, math.hypot(rcx, rcy), math.atan2(rcy, rcx)])
    crank.angular_velocity = step
    lk.set_coords([tuple(o2), tuple(o4), tuple(a), tuple(b), (0.0, 0.0)])
    return np.asarray(lk.step_fast(iterations=n))


def run_pylinkage(name: str, iterations: int = 200, particles: int = 100) -> dict[str, Any]:
    """pylinkage's particle swarm on the problem (see the module's docstring); its best design
    converted, recomputed on the branch its simulation started on and checked by linkwork."""
    from pylinkage.optimization import particle_swarm_optimization

    from linkwork.synthesis.path import default_bounds

    pb = PROBLEMS[name]
    pts = pb["points"]
    L = float(np.hypot(*np.ptp(pts, axis=0)))
    bnd = default_bounds(pts) | (pb["bounds"] or {})
    lo = [bnd[k][0] for k in PARAMS] + [-1.0]  # the last: the side B starts on
    hi = [bnd[k][1] for k in PARAMS] + [1.0]
    if pb["free_start"]:
        lo.insert(9, 0.0)
        hi.insert(9, 2 * PI)
    lk, crank = _pylinkage_fourbar()
    penalty = 1e6 * L * L
    timing = pb["timing"]

    def angles(v: np.ndarray) -> tuple[float, float, int]:
        if timing is None:
            return 0.0, 2 * PI / 360, 360
        start = float(v[9]) if pb["free_start"] else float(timing[0])
        return start, float(timing[1] - timing[0]), len(timing)

    def fitness(_linkage: Any, dims: list[float], _pos: Any) -> float:
        v = np.asarray(dims)
        P = _pylinkage_sim(lk, crank, v, *angles(v))[:, 4, :]
        if not np.isfinite(P).all():
            return penalty
        if timing is not None:
            return float(np.sum((P - pts) ** 2))
        d2 = ((P[None, :, :] - pts[:, None, :]) ** 2).sum(axis=2)
        return float(d2.min(axis=1).sum())

    t = time.perf_counter()
    ens = particle_swarm_optimization(fitness, lk, dimensions=len(lo), bounds=(lo, hi),
                                      order_relation=min, n_particles=particles,
                                      iterations=iterations, verbose=False)
    wall = time.perf_counter() - t
    v = np.asarray(ens.dimensions[0], dtype=float)
    score = fitness(None, list(v), None)
    out = {"fitness": score, "time": wall, "evaluations": particles * (iterations + 1)}
    if score >= penalty:
        return out | {"error": math.inf, "check_defect": "unbuildable", "branch": 0}
    params: dict[str, Any] = {k: float(x) for k, x in zip(PARAMS, v[:9], strict=True)}
    start, step, n = angles(v)
    traj = _pylinkage_sim(lk, crank, v, start, step, n)
    if timing is not None:
        th = start + step * np.arange(n)
    else:  # the crank angles of the nearest points pylinkage's fitness took
        d2 = ((traj[None, :, 4, :] - pts[:, None, :]) ** 2).sum(axis=2)
        th = start + step * np.argmin(d2, axis=1)
    params["theta2"] = [float(a) for a in th]
    o4, a, b = traj[0, 1], traj[0, 2], traj[0, 3]  # B's side of A -> O4 at the first step
    br = 1 if (o4[0] - a[0]) * (b[1] - a[1]) - (o4[1] - a[1]) * (b[0] - a[0]) > 0 else -1
    return out | {"error": error_of(pb, params, br), "branch": br, "design": params,
                  **{"check_" + k: val for k, val in defects(pb, params, br).items()}}


def run_dask(name: str, n: int) -> dict[int, float]:
    from dask.distributed import Client, LocalCluster

    out = {}
    pb = PROBLEMS[name]
    kw = dict(timing=pb["timing"], bounds=pb["bounds"], constraints=pb["constraints"],
              closed=pb["closed"], free_start=pb["free_start"], seed=0, progress=False,
              n_refine=4)  # a single refinement may end defective (no design)
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            path(pb["points"], n_candidates=4096, client=client, **kw)  # warm-up
            res = path(pb["points"], n_candidates=n, client=client, **kw)
            out[workers] = res.time_global
    res = path(pb["points"], n_candidates=n, **kw)
    out[0] = res.time_global
    return out


def throughput(n_closed: int = 8192, n_engine: int = 200) -> dict[str, float]:
    """Candidate-points per second (designs x 120 crank angles): the four-bar's closed form
    screening (broadcast, with the ordered timing assignment) and the planar engine on one
    four-bar design at a time; the six-bar's (Stephenson III) closed form screening and the
    engine on one six-bar at a time (:func:`linkwork.synthesis.sixbar.coupler_points`: a model
    built per design) and on all of them in one batch call (``sixbar.mechanism`` of arrays over
    the designs, one ``kinematics``: the engine's designs in batches)."""
    from linkwork.planar.kinematics import kinematics
    from linkwork.synthesis import path as pa
    from linkwork.synthesis import sixbar as sb
    from linkwork.synthesis.design import FourbarDesign

    pb = PROBLEMS["ellipse-10"]
    tk = pa.task(pb["points"], bounds=pb["bounds"], closed=True)
    cands = pa._candidates(tk, n_closed, 0)
    t = time.perf_counter()
    pa._screen(cands, tk=tk, n_samples=120, keep=64)
    closed = n_closed * 120 / (time.perf_counter() - t)
    phi = np.linspace(0, 2 * PI, 120, endpoint=False)
    X = cands["X"][:n_engine]
    t = time.perf_counter()
    for x, br in zip(X, cands["branch"][:n_engine], strict=True):
        p = dict(zip(pa.PARAMS, map(float, x), strict=True))
        d = FourbarDesign(params=dict(p, theta2=[0.0]), branch=int(br), error=0.0,
                          points=pb["points"])
        kinematics(d.mechanism(), phi + p["theta0"], on_failure="nan")
    engine4 = n_engine * 120 / (time.perf_counter() - t)
    tk6 = sb._task(pb["points"], "stephenson", None, None, ("order",), True, False)
    c6 = sb._candidates(tk6, n_closed, 0, "stephenson")
    t = time.perf_counter()
    sb._screen(c6, tk=tk6, kind="stephenson", n_samples=120, keep=64)
    closed6 = n_closed * 120 / (time.perf_counter() - t)
    br6 = sb._BRANCHES[c6["branch"][:n_engine].astype(int)]
    t = time.perf_counter()
    sb.coupler_points(c6["X"][:n_engine], br6, phi, "stephenson")
    engine6 = n_engine * 120 / (time.perf_counter() - t)
    p6 = {k: c6["X"][:, i] for i, k in enumerate(sb.SIXBAR_PARAMS)}
    br_all = sb._BRANCHES[c6["branch"].astype(int)]
    t = time.perf_counter()
    batch = sb.mechanism(p6, "stephenson", (br_all[:, 0], br_all[:, 1]))
    kinematics(batch, p6["theta0"][:, None] + phi, on_failure="nan").point("link5", "P")
    batch6 = n_closed * 120 / (time.perf_counter() - t)
    return {"four-bar closed form (broadcast)": closed,
            "engine, one four-bar at a time": engine4,
            "six-bar closed form (broadcast)": closed6,
            "engine, one six-bar at a time": engine6,
            "engine, six-bars in one batch call": batch6}


# ---------------------------------------------------------------------------------------------
# tables
# ---------------------------------------------------------------------------------------------
def _fmt_t(v: list[float]) -> str:
    return f"{min(v):.2f} / {statistics.median(v):.2f} / {max(v):.2f}"


def _verdict(r: dict[str, Any], prefix: str = "") -> str:
    d = r.get(prefix + "defect")
    out = "passes" if d is None else f"**{d}**"
    if d == "grashof":
        cls, short = r.get(prefix + "grashof"), r.get(prefix + "shortest")
        out += (f" (class {cls}, not a crank-rocker" if cls != "I" else
                f" ({short} the shortest, not the crank r2") + ")"
    if not r.get(prefix + "in_bounds", True):
        out += ", outside the bounds"
    return out


def print_published(rows: list[dict[str, Any]]) -> None:
    print("| problem | design (who) | f recomputed | printed (where) | Grashof, margin | "
          "μmin [deg] | linkwork's checks |")
    print("|---|---|---:|---|---|---:|---|")
    for r in rows:
        pr = "-"
        if "printed_printed" in r:
            c = {k[8:]: v for k, v in r.items() if k.startswith("printed_")}
            pr = (f"{'≥ ' if c['at_most'] else ''}{c['printed']:.6g} ± {c['tol']:.2g} "
                  f"{'agrees' if printed_agrees(c) else '**disagrees**'}")
        print(f"| {r['problem']} | {r['who']} | {r['error']:.6g} | {pr} | "
              f"{r['grashof']}, {r['margin']:.3g} | {r['mu_min']:.3g} | {_verdict(r)}"
              f"{'; ' + r['note'] if r['note'] else ''} |")


def main(argv: list[str] | None = None) -> list[dict[str, Any]]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--problems", default=",".join(PROBLEMS))
    ap.add_argument("--candidates", type=int, default=2**16)
    ap.add_argument("--no-published", action="store_true")
    ap.add_argument("--no-pylinkage", action="store_true")
    ap.add_argument("--pylinkage-iterations", type=int, default=200)
    ap.add_argument("--no-dask", action="store_true")
    ap.add_argument("--no-throughput", action="store_true")
    ap.add_argument("--dask-problem", default="ellipse-10")
    ap.add_argument("--dask-candidates", type=int, default=2**18)
    args = ap.parse_args(argv)
    names = args.problems.split(",")
    rows: list[dict[str, Any]] = []
    pub = [] if args.no_published else published_table(names)
    if pub:
        print_published(pub)
        print()
        rows += pub
    print("| problem | contender | best f | time min / median / max [s] | evaluations | "
          "μmin [deg] | linkwork's checks of the best | published best (who) | "
          "published best passing the checks |")
    print("|---|---|---:|---:|---:|---:|---|---|---|")
    for name in names:
        runs = [run_linkwork(name, seed, n_candidates=args.candidates)
                for seed in range(args.repeat)]
        best = min(runs, key=lambda r: r["error"])
        rows.append({"problem": name, "contender": "linkwork", **best,
                     "times": [r["time"] for r in runs]})
        b_all, b_ok = best_published(pub, name, False), best_published(pub, name, True)
        print(f"| {name} | linkwork | {best['error']:.7g} | "
              f"{_fmt_t([r['time'] for r in runs])} | {best['candidates']} candidates, "
              f"{best['residuals']} residuals | {best['mu_min']:.3g} | "
              f"{_verdict(best, 'check_')} | "
              + (f"{b_all['error']:.7g} ({b_all['who']})" if b_all else "-") + " | "
              + (f"{b_ok['error']:.7g} ({b_ok['who']})" if b_ok else "-") + " |")
        if not args.no_pylinkage:
            pr = [run_pylinkage(name, iterations=args.pylinkage_iterations)
                  for _ in range(args.repeat)]
            b = min(pr, key=lambda r: r["error"])
            rows.append({"problem": name, "contender": "pylinkage", **b})
            fails = sum(r.get("check_defect") is not None for r in pr)
            print(f"| {name} | pylinkage PSO | {b['error']:.7g} (its fitness "
                  f"{b['fitness']:.4g}) | {_fmt_t([r['time'] for r in pr])} | "
                  f"{b['evaluations']} fitness calls | {b.get('check_mu_min', math.nan):.3g} | "
                  f"{_verdict(b, 'check_')} ({fails} of {len(pr)} runs defective) | | |")
    if not args.no_throughput:
        tp = throughput()
        print("\ncandidate-points per second: "
              + "; ".join(f"{k} {v:.3g}" for k, v in tp.items()))
        rows.append({"throughput": tp})
    if not args.no_dask:
        t = run_dask(args.dask_problem, args.dask_candidates)
        print(f"\nglobal search of {args.dask_problem}, {args.dask_candidates} candidates: "
              f"in-process {t[0]:.2f} s, dask 1 worker {t[1]:.2f} s, 2 workers {t[2]:.2f} s "
              f"(speed-up 1 -> 2 workers: {t[1] / t[2]:.2f})")
        rows.append({"dask": t})
    return rows


if __name__ == "__main__":
    main()
