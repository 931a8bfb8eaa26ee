r"""Synthesised linkages judged by forces: masses, engine inverse dynamics, weighted or Pareto.

Kinematic synthesis alone returns the linkage that is most accurate; an engineer also wants
moderate driving torque and bearing loads, little shaking and good transmission angles. Here
each defect-free design of a search is re-solved by the planar engine
(:func:`linkwork.planar.dynamics.inverse_dynamics`) with the masses the engineer gives, or that
are estimated from the link lengths and a cross-section (:func:`estimate_masses`), at the crank
speed and under the tool force of a :class:`ForceModel`, over the range the design runs (a full
turn when the crank rotates). Four numbers judge it: ``peak_torque`` (largest |Q| [N m]),
``peak_bearing`` (largest reaction of any joint [N]), ``rms_shaking`` (RMS of the shaking
force over the run [N]) and ``min_transmission_angle`` [rad]. An :class:`Objective` either
weighs them with the error or keeps the Pareto set of accuracy against dynamics.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np

from linkwork.cycles import rms
from linkwork.errors import ParameterError
from linkwork.planar.dynamics import PointForce, inverse_dynamics
from linkwork.planar.kinematics import kinematics
from linkwork.synthesis.design import FourbarDesign, LinkMasses, _loop

__all__ = ["METRICS", "ForceModel", "Objective", "estimate_masses", "evaluate_forces",
           "force_metrics", "fourbar_dynamics", "judge", "pareto_front", "run_angles",
           "weighted_score"]

#: The numbers a design is judged by, with the sense in which they are better.
METRICS: dict[str, str] = {"error": "min", "peak_torque": "min", "peak_bearing": "min",
                           "rms_shaking": "min", "min_transmission_angle": "max"}


@dataclass(frozen=True)
class ForceModel:
    """How the forces of a design are computed.

    Parameters
    ----------
    masses : (crank, coupler, rocker) [kg], optional
        Link masses; centres of mass at the link middles (the coupler's at the centroid of the
        triangle A, B, P) and thin-rod inertias. None: estimated from ``density`` and
        ``section`` (:func:`estimate_masses`).
    density : float
        Material density [kg/m^3] (default steel, 7850).
    section : float
        Cross-section area of every bar [m^2] (default 1e-4, a 10 x 10 mm bar).
    omega1 : float
        Crank speed [rad/s] (constant).
    force : (fx, fy)
        Tool force on the coupler point P, frame axes [N] (default none).
    gravity : (gx, gy)
        Gravity [m/s^2] (default off).
    n : int
        Positions over the run.
    """

    masses: tuple[float, float, float] | None = None
    density: float = 7850.0
    section: float = 1e-4
    omega1: float = 10.0
    force: tuple[float, float] = (0.0, 0.0)
    gravity: tuple[float, float] = (0.0, 0.0)
    n: int = 181

    def __post_init__(self) -> None:
        for k in ("density", "section", "omega1"):
            v = getattr(self, k)
            if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
                raise ParameterError(f"forces.{k}", v, "must be finite and > 0")
        if self.masses is not None:
            if len(self.masses) != 3 or any(not (math.isfinite(m) and m >= 0)
                                            for m in self.masses):
                raise ParameterError("forces.masses", self.masses,
                                     "must be three finite masses >= 0 [kg] (crank, coupler, "
                                     "rocker)")
        if not 8 <= int(self.n) <= 10_000:
            raise ParameterError("forces.n", self.n, "must be an integer from 8 to 10000")


def _mass_arrays(r2: Any, r3: Any, r4: Any, rcx: Any, rcy: Any, model: ForceModel
                 ) -> tuple[tuple[Any, Any, Any], Any, Any, tuple[Any, Any, Any]]:
    """Masses (crank, coupler, rocker), the coupler's centre of mass (x, y in its frame) and
    the centroidal inertias, as arrays broadcasting over designs: see :func:`estimate_masses`."""
    rho_a = model.density * model.section
    # the coupler: bars A-B, A-P, B-P (A at the origin, B at (r3, 0), P at (rcx, rcy))
    ends = (((0.0, 0.0), (r3, 0.0)), ((0.0, 0.0), (rcx, rcy)), ((r3, 0.0), (rcx, rcy)))
    bars = []
    for (ax, ay), (bx, by) in ends:
        L = np.hypot(np.subtract(bx, ax), np.subtract(by, ay))
        bars.append((rho_a * L, (np.add(ax, bx) / 2, np.add(ay, by) / 2), rho_a * L * L * L / 12))
    mc = bars[0][0] + bars[1][0] + bars[2][0]
    safe = np.where(mc > 0, mc, 1.0)
    gx = np.where(mc > 0, sum(b[0] * b[1][0] for b in bars) / safe, np.divide(r3, 2))
    gy = np.where(mc > 0, sum(b[0] * b[1][1] for b in bars) / safe, 0.0)
    ic = sum(b[2] + b[0] * ((b[1][0] - gx) ** 2 + (b[1][1] - gy) ** 2) for b in bars)
    mass = [rho_a * np.asarray(r2, dtype=float), mc, rho_a * np.asarray(r4, dtype=float)]
    inertia = [mass[0] * np.square(r2) / 12, ic, mass[2] * np.square(r4) / 12]
    if model.masses is not None:
        for i, m in enumerate(model.masses):
            inertia[i] = np.where(mass[i] > 0, inertia[i] * m / np.where(mass[i] > 0, mass[i],
                                                                          1.0), 0.0)
            mass[i] = np.full(np.shape(mass[i]), float(m))
    return (mass[0], mass[1], mass[2]), gx, gy, (inertia[0], inertia[1], inertia[2])


def estimate_masses(params: Mapping[str, Any], model: ForceModel) -> LinkMasses:
    """Masses of crank, coupler and rocker from the link lengths.

    Crank and rocker are straight bars (``density * section * length``, centre in the middle,
    inertia ``m L^2 / 12``). The coupler is the triangle of bars A-B, A-P and B-P (a plate's
    outline; P on the line AB leaves the bars along it): mass the sum, centre of mass their
    mass-weighted middle, inertia the bars' own plus the parallel-axis terms. Given masses
    (``model.masses``) replace the estimated ones, with the same centres; inertias scale with
    them.
    """
    r2, r3, r4 = float(params["r2"]), float(params["r3"]), float(params["r4"])
    mass, gx, gy, inertia = _mass_arrays(r2, r3, r4, float(params["rcx"]),
                                         float(params["rcy"]), model)
    return LinkMasses(mass=(float(mass[0]), float(mass[1]), float(mass[2])),
                      com=((r2 / 2, 0.0), (float(gx), float(gy)), (r4 / 2, 0.0)),
                      inertia=(float(inertia[0]), float(inertia[1]), float(inertia[2])))


def _cross(ax: Any, ay: Any, bx: Any, by: Any) -> Any:
    return ax * by - ay * bx


def fourbar_dynamics(X: np.ndarray, branch: np.ndarray, theta2: np.ndarray,
                     model: ForceModel) -> dict[str, np.ndarray]:
    """Inverse dynamics of four-bar designs at constant crank speed, in closed form over
    designs x positions: what :func:`evaluate_forces` gets from the engine, for a search.

    ``X`` (m, 9) the literature parameters (:data:`~linkwork.synthesis.design.PARAMS`),
    ``branch`` (m,), ``theta2`` (m, N) crank angles from the frame line [rad]; masses by
    :func:`estimate_masses`, speed, tool force on P and gravity from ``model``. Returns arrays
    (m, N): ``Q`` the driving torque on the crank [N m], ``bearing`` the largest joint
    reaction [N], ``shaking`` the magnitude of the force on the frame [N], ``cos_mu`` the
    cosine of the transmission angle, ``h2`` (>= 0 where it assembles).

    Velocity and acceleration loops of the closed form (``vB = vA + w3 x u = w4 x w``, ``u``
    the coupler AB, ``w`` the rocker O4B), then Newton-Euler: the force of the coupler on the
    rocker from the moments about O4 (rocker) and A (coupler), the other reactions from the
    bodies' force balances, the torque from the crank's moment about O2. Computed in the axes
    of the frame line (forces given in the task's axes are turned by -theta0 into them;
    magnitudes do not depend on the axes).
    """
    X = np.asarray(X, dtype=float)
    col = [X[:, i][:, None] for i in range(9)]
    r1, r2, r3, r4, rcx, rcy, _x0, _y0, t0 = col
    br = np.asarray(branch, dtype=float)[:, None]
    th = np.asarray(theta2, dtype=float)
    w2 = float(model.omega1)
    ax, ay, sx, sy, ux, uy, h2 = _loop(th, r1, r2, r3, r4, br)
    wx, wy = ux - sx, uy - sy  # B - O4
    det = _cross(ux, uy, wx, wy)
    det = np.where(det == 0.0, np.nan, det)
    # velocities: vB = vA + w3 k x u is normal to w, vB - vA normal to u (det = u x w)
    vax, vay = -w2 * ay, w2 * ax
    w3 = -(vax * wx + vay * wy) / det
    w4 = -(vax * ux + vay * uy) / det
    # accelerations (eps2 = 0): a3 k x u - a4 k x w = e = -aA + w3^2 u - w4^2 w
    aax, aay = -w2 * w2 * ax, -w2 * w2 * ay
    ex, ey = -aax + w3 * w3 * ux - w4 * w4 * wx, -aay + w3 * w3 * uy - w4 * w4 * wy
    a3 = (ex * wx + ey * wy) / det
    a4 = (ex * ux + ey * uy) / det
    (m2, m3, m4), gx, gy, (_, i3, i4) = _mass_arrays(r2, r3, r4, rcx, rcy, model)
    c0, s0 = np.cos(t0), np.sin(t0)

    def local(v: tuple[float, float]) -> tuple[Any, Any]:  # task axes -> frame-line axes
        return c0 * v[0] + s0 * v[1], -s0 * v[0] + c0 * v[1]

    gvx, gvy = local(model.gravity)
    fpx, fpy = local(model.force)
    # centres of mass relative to each body's pivot or origin, and their accelerations
    c2, s2 = np.cos(th), np.sin(th)
    p2x, p2y = r2 / 2 * c2, r2 / 2 * s2
    a2x, a2y = -w2 * w2 * p2x, -w2 * w2 * p2y
    e3x, e3y = ux / r3, uy / r3
    p3x, p3y = gx * e3x - gy * e3y, gx * e3y + gy * e3x
    a3x = aax - a3 * p3y - w3 * w3 * p3x
    a3y = aay + a3 * p3x - w3 * w3 * p3y
    p4x, p4y = wx / 2, wy / 2
    a4x, a4y = -a4 * p4y - w4 * w4 * p4x, a4 * p4x - w4 * w4 * p4y
    ppx, ppy = rcx * e3x - rcy * e3y, rcx * e3y + rcy * e3x  # P - A
    # the force F of the coupler on the rocker at B:
    #   rocker about O4:  w x F = i4 a4 + p4 x m4 (a4 - g)
    #   coupler about A: -u x F = i3 a3 + p3 x m3 (a3 - g) - (P - A) x F_P
    r_1 = i4 * a4 + _cross(p4x, p4y, m4 * (a4x - gvx), m4 * (a4y - gvy))
    r_2 = (i3 * a3 + _cross(p3x, p3y, m3 * (a3x - gvx), m3 * (a3y - gvy))
           - _cross(ppx, ppy, fpx, fpy))
    d2 = wy * ux - wx * uy
    d2 = np.where(d2 == 0.0, np.nan, d2)
    fbx = (-r_1 * ux - wx * r_2) / d2
    fby = (-wy * r_2 - r_1 * uy) / d2
    fax = m3 * (a3x - gvx) + fbx - fpx  # crank on coupler at A
    fay = m3 * (a3y - gvy) + fby - fpy
    f4x, f4y = m4 * (a4x - gvx) - fbx, m4 * (a4y - gvy) - fby  # frame on rocker at O4
    f2x, f2y = m2 * (a2x - gvx) + fax, m2 * (a2y - gvy) + fay  # frame on crank at O2
    Q = _cross(p2x, p2y, m2 * (a2x - gvx), m2 * (a2y - gvy)) + _cross(ax, ay, fax, fay)
    bearing = np.maximum.reduce([np.hypot(f2x, f2y), np.hypot(fax, fay), np.hypot(fbx, fby),
                                 np.hypot(f4x, f4y)])
    cos_mu = (ux * wx + uy * wy) / (r3 * r4)
    return {"Q": Q, "bearing": bearing, "shaking": np.hypot(f2x + f4x, f2y + f4y),
            "cos_mu": cos_mu, "h2": h2}


def run_angles(theta2: np.ndarray, rotates: np.ndarray, n: int) -> np.ndarray:
    """Crank angles (m, n) over the range designs run: a full turn from the first point where
    ``rotates``, else from the first to the last point the way the points are reached
    (``theta2`` (m, k) unwrapped, monotone, as the search keeps them)."""
    th = np.asarray(theta2, dtype=float)
    t = np.linspace(0.0, 1.0, n)
    s = np.where(th[:, -1] >= th[:, 0], 1.0, -1.0)[:, None]
    span = np.where(np.asarray(rotates)[:, None], s * 2 * math.pi, th[:, -1:] - th[:, :1])
    return th[:, :1] + span * t


def force_metrics(X: np.ndarray, branch: np.ndarray, theta2: np.ndarray,
                  rotates: np.ndarray, model: ForceModel) -> dict[str, np.ndarray]:
    """The numbers a design is judged by (:data:`METRICS` but the error), over the range it
    runs at ``model.n`` positions (:func:`run_angles`), for designs ``X`` (m, 9): arrays
    (m,). The same positions and definitions as :func:`evaluate_forces` (the RMS over a full
    turn by the periodic trapezoid rule); ``min_transmission_angle`` also takes a crank-
    rocker's exact extremes at theta2 = 0 and pi. NaN where a position does not assemble."""
    th = run_angles(theta2, rotates, model.n)
    dyn = fourbar_dynamics(X, branch, th, model)
    bad = np.any(dyn["h2"] < 0, axis=1)
    sh = dyn["shaking"]
    rot = np.asarray(rotates)
    rms_sh = np.where(rot, np.sqrt(np.mean(sh[:, :-1] ** 2, axis=1)),
                      np.sqrt(np.mean(sh ** 2, axis=1)))
    cm = np.max(np.abs(dyn["cos_mu"]), axis=1)
    r1, r2, r3, r4 = (X[:, i] for i in range(4))
    ext = np.maximum(np.abs((r3 * r3 + r4 * r4 - (r1 - r2) ** 2) / (2 * r3 * r4)),
                     np.abs((r3 * r3 + r4 * r4 - (r1 + r2) ** 2) / (2 * r3 * r4)))
    cm = np.where(rot, np.maximum(cm, ext), cm)
    mu = np.arccos(np.clip(cm, -1.0, 1.0))
    out = {"peak_torque": np.max(np.abs(dyn["Q"]), axis=1),
           "peak_bearing": np.max(dyn["bearing"], axis=1), "rms_shaking": rms_sh,
           "min_transmission_angle": mu}
    return {k: np.where(bad, np.nan, v) for k, v in out.items()}


def evaluate_forces(design: FourbarDesign, model: ForceModel) -> dict[str, float]:
    """Peak driving torque, peak bearing load and RMS shaking force of a design, by the engine
    over the range it runs (``model.n`` positions), with its :func:`estimate_masses`."""
    masses = estimate_masses(design.params, model)
    mech = design.mechanism(masses, omega1=model.omega1)
    th = design.run_range(model.n) + float(design.params["theta0"])
    kin = kinematics(mech, th)
    loads = []
    if model.force != (0.0, 0.0):
        loads.append(PointForce("coupler", "P", float(model.force[0]), float(model.force[1])))
    dyn = inverse_dynamics(kin, gravity=model.gravity if model.gravity != (0.0, 0.0) else None,
                           loads=loads)
    full = bool(design.checks.get("crank_rotates", False)) or design.closed
    bearing = max(float(np.max(dyn.reaction_magnitude(j))) for j in dyn.joints)
    shaking = np.hypot(dyn.shaking_fx, dyn.shaking_fy)
    turn = np.linspace(0.0, 2 * math.pi, len(th))[:-1]  # the run's spacing, increasing
    rms_sh = float(rms(turn, shaking[:-1])) if full else float(np.sqrt(np.mean(shaking ** 2)))
    return {"peak_torque": float(np.max(np.abs(dyn.Q))), "peak_bearing": bearing,
            "rms_shaking": rms_sh}


@dataclass(frozen=True)
class Objective:
    """What a synthesis minimises.

    ``kind``: ``"sum_squares"`` (the literature's error alone), ``"weighted"`` (the error plus
    the weighted dynamics, each term normalised: the error by ``n (0.01 L)^2``, an RMS
    deviation of 1 % of the size ``L`` of the targets, the forces by their median over the
    candidates, the transmission angle as ``(pi/2) / mu_min``) or ``"pareto"`` (the
    non-dominated designs in ``metrics``). ``weights``: metric -> weight (:data:`METRICS`
    names). ``forces``: the :class:`ForceModel`.
    """

    kind: Literal["sum_squares", "weighted", "pareto"] = "sum_squares"
    weights: Mapping[str, float] = field(default_factory=dict)
    metrics: tuple[str, ...] = ("error", "peak_torque")
    forces: ForceModel = ForceModel()

    def __post_init__(self) -> None:
        if self.kind not in ("sum_squares", "weighted", "pareto"):
            raise ParameterError("objective", self.kind,
                                 "must be 'sum_squares', 'weighted' or 'pareto'")
        for k, w in self.weights.items():
            if k not in METRICS:
                raise ParameterError("objective.weights", k, f"unknown; known: {list(METRICS)}")
            if not (math.isfinite(w) and w >= 0):
                raise ParameterError(f"objective.weights.{k}", w, "must be finite and >= 0")
        for k in self.metrics:
            if k not in METRICS:
                raise ParameterError("objective.metrics", k, f"unknown; known: {list(METRICS)}")
        if self.kind == "weighted" and self.weights.get("error", 1.0) <= 0:
            raise ParameterError("objective.weights.error", self.weights["error"],
                                 "must be > 0: a weighted search still follows the path")
        if self.kind == "pareto" and len(self.metrics) < 2:
            raise ParameterError("objective.metrics", self.metrics,
                                 "a Pareto set needs at least two metrics")

    @classmethod
    def parse(cls, objective: Any) -> Objective:
        """An Objective from ``"sum_squares"``, ``"pareto"``, a mapping of weights, or one."""
        if isinstance(objective, Objective):
            return objective
        if objective in ("sum_squares", None):
            return cls()
        if objective == "pareto":
            return cls(kind="pareto")
        if isinstance(objective, Mapping):
            return cls(kind="weighted", weights=dict(objective))
        raise ParameterError("objective", objective, "must be 'sum_squares', 'pareto', a "
                             "mapping of weights or an Objective")


def pareto_front(values: np.ndarray) -> np.ndarray:
    """Indices of the non-dominated rows of ``values`` (rows: designs; columns: metrics to
    minimise), in row order."""
    v = np.asarray(values, dtype=float)
    keep = []
    for i in range(len(v)):
        dominated = np.any(np.all(v <= v[i], axis=1) & np.any(v < v[i], axis=1))
        if not dominated:
            keep.append(i)
    return np.array(keep, dtype=int)


def _metric(d: FourbarDesign, k: str) -> float:
    if k == "error":
        return float(d.error)
    if k == "min_transmission_angle":
        return float(d.checks.get(k, 0.0))
    return float(d.forces[k])


def judge(pool: Sequence[FourbarDesign], obj: Objective, n_designs: int,
          scales: Mapping[str, float] | None = None
          ) -> tuple[list[FourbarDesign], tuple[int, ...]]:
    """Rank the defect-free ``pool`` (sorted by error) by ``obj``, each design's forces
    re-solved by the engine (:func:`evaluate_forces`): the designs to return and, for a
    Pareto objective, the indices of the Pareto set among them.

    ``scales``: what each metric is measured against in the weighted score (the search's:
    the error against ``n (0.01 L)^2``, each force against its median over the screened
    candidates); without them, the forces' medians over ``pool``."""
    if obj.kind == "sum_squares":
        return list(pool[:n_designs]), ()
    model = obj.forces
    judged = [replace(d, forces=evaluate_forces(d, model),
                      masses=estimate_masses(d.params, model), omega1=model.omega1)
              for d in pool]
    if obj.kind == "pareto":
        vals = np.array([[(_metric(d, k) if METRICS[k] == "min" else -_metric(d, k))
                          for k in obj.metrics] for d in judged])
        front = pareto_front(vals)
        chosen = [judged[i] for i in front]  # in error order (the pool is sorted by error)
        return chosen, tuple(range(len(chosen)))
    ref = dict(scales or {})
    if not ref:
        n_pts = len(pool[0].points)
        span = float(np.hypot(*np.ptp(pool[0].points, axis=0)))
        ref = {"error": n_pts * (0.01 * span) ** 2}
        for k in ("peak_torque", "peak_bearing", "rms_shaking"):
            med = float(np.median([_metric(d, k) for d in judged]))
            ref[k] = med if med > 0 else 1.0
    ranked = sorted(judged, key=lambda d: weighted_score(d, obj, ref))
    return ranked[:n_designs], ()


def weighted_score(d: FourbarDesign, obj: Objective, scales: Mapping[str, float]) -> float:
    """The weighted objective of a judged design: ``sum_k w_k m_k / scale_k`` over the
    weights (the error's 1 when not given; ``{"peak_torque": 1}`` when none are), the
    transmission angle as ``(pi/2) / mu_min``."""
    weights = {"error": 1.0} | (dict(obj.weights) or {"peak_torque": 1.0})
    s = 0.0
    for k, w in weights.items():
        if k == "min_transmission_angle":
            s += w * (math.pi / 2) / max(_metric(d, k), 1e-9)
        else:
            s += w * _metric(d, k) / scales[k]
    return s
