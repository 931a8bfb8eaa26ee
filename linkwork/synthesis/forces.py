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
from linkwork.synthesis.design import FourbarDesign, LinkMasses

__all__ = ["METRICS", "ForceModel", "Objective", "estimate_masses", "evaluate_forces", "judge",
           "pareto_front"]

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


def _bar(m: float, p0: np.ndarray, p1: np.ndarray) -> tuple[float, np.ndarray, float]:
    L = float(np.hypot(*(p1 - p0)))
    return m, (p0 + p1) / 2, m * L * L / 12.0


def estimate_masses(params: Mapping[str, Any], model: ForceModel) -> LinkMasses:
    """Masses of crank, coupler and rocker from the link lengths.

    Crank and rocker are straight bars (``density * section * length``, centre in the middle,
    inertia ``m L^2 / 12``). The coupler is the triangle of bars A-B, A-P and B-P (a plate's
    outline; P on the line AB leaves the bars along it): mass the sum, centre of mass their
    mass-weighted middle, inertia the bars' own plus the parallel-axis terms. Given masses
    (``model.masses``) replace the estimated ones, with the same centres; inertias scale with
    them.
    """
    rho_a = model.density * model.section
    r2, r3, r4 = float(params["r2"]), float(params["r3"]), float(params["r4"])
    A, B = np.zeros(2), np.array([r3, 0.0])
    P = np.array([float(params["rcx"]), float(params["rcy"])])
    bars = [_bar(rho_a * float(np.hypot(*(q - p))), p, q) for p, q in ((A, B), (A, P), (B, P))]
    mc = sum(b[0] for b in bars)
    com = np.asarray(sum(b[0] * b[1] for b in bars) / mc if mc > 0 else (A + B) / 2)
    ic = sum(b[2] + b[0] * float(np.sum((b[1] - com) ** 2)) for b in bars)
    mass = [rho_a * r2, mc, rho_a * r4]
    inertia = [mass[0] * r2 * r2 / 12, ic, mass[2] * r4 * r4 / 12]
    if model.masses is not None:
        for i, m in enumerate(model.masses):
            inertia[i] = inertia[i] * m / mass[i] if mass[i] > 0 else 0.0
            mass[i] = float(m)
    return LinkMasses(mass=(mass[0], mass[1], mass[2]),
                      com=((r2 / 2, 0.0), (float(com[0]), float(com[1])), (r4 / 2, 0.0)),
                      inertia=(inertia[0], inertia[1], inertia[2]))


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


def judge(pool: Sequence[FourbarDesign], obj: Objective, n_designs: int
          ) -> tuple[list[FourbarDesign], tuple[int, ...]]:
    """Rank the defect-free ``pool`` (sorted by error) by ``obj``: the designs to return and,
    for a Pareto objective, the indices of the Pareto set among them."""
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
    n_pts = len(pool[0].points)
    span = float(np.hypot(*np.ptp(pool[0].points, axis=0)))
    ref = {"error": n_pts * (0.01 * span) ** 2}
    for k in ("peak_torque", "peak_bearing", "rms_shaking"):
        vals_k = np.array([_metric(d, k) for d in judged])
        med = float(np.median(vals_k))
        ref[k] = med if med > 0 else 1.0
    weights = dict(obj.weights) or {"error": 1.0, "peak_torque": 1.0}

    def score(d: FourbarDesign) -> float:
        s = 0.0
        for k, w in weights.items():
            if k == "min_transmission_angle":
                s += w * (math.pi / 2) / max(_metric(d, k), 1e-9)
            else:
                s += w * _metric(d, k) / ref[k]
        return s

    ranked = sorted(judged, key=score)
    return ranked[:n_designs], ()
