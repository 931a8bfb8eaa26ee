"""Optimal balancing: counterweights chosen by optimisation, and the trade-off between goals.

Counterweights are point masses (mass m, radius r from the hinge, angle alpha on the link) on
links hinged to the frame, within bounds. They change the shaking force F, the shaking moment M
about the crank axis and the driving torque Q; the design minimises

.. math::

    J = w_F \\frac{F_{rms}}{F_{rms,0}} + w_M \\frac{M_{rms}}{M_{rms,0}}
        + w_Q \\frac{\\Delta Q_{rms}}{\\Delta Q_{rms,0}},

with :math:`F_{rms}` the cycle RMS of :math:`|F|`, :math:`\\Delta Q_{rms}` the RMS of the
driving torque about its mean (its fluctuation), and index 0 the unbalanced mechanism. Sweeping
the weights over the simplex gives the trade-off (Pareto set).

All three quantities are linear in the counterweights' mass moments, so the motion is solved
once and each design is evaluated exactly by superposition: a counterweight on link k (hinge
:math:`H_k`, angle :math:`\\theta_k`) with local first moment :math:`q = m r (\\cos\\alpha,
\\sin\\alpha)` and inertia about its hinge :math:`J = m r^2` adds

.. math::

    F_k = (\\omega_k^2 I - \\varepsilon_k J_\\perp) A(\\theta_k) q, \\quad
    M_k = (H_k - P) \\times F_k - J \\varepsilon_k, \\quad
    Q_k = \\frac{J \\omega_k \\varepsilon_k - m\\,g \\cdot v_k}{\\omega_1},

(tested against re-solving the balanced mechanism with the engine).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.balancing.mechanism import (
    _cw_force_basis,
    add_counterweights,
    crank_axis,
    cycle,
    force_balance,
    frame_hinge,
    frame_hinged_links,
)
from linkwork.balancing.static import Counterweight
from linkwork.checks import require_finite
from linkwork.cycles import periodic_weights, rms
from linkwork.errors import ParameterError
from linkwork.planar.dynamics import inverse_dynamics
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import Mechanism
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["BalancingProblem", "OptimalBalance", "ParetoSet", "optimal_balance", "pareto_set"]


@dataclass(frozen=True)
class OptimalBalance(Result):
    """One optimised design.

    Attributes
    ----------
    weights : tuple of float
        (w_F, w_M, w_Q) used.
    counterweights : tuple of Counterweight
        The design (point masses with radius).
    force_rms, moment_rms, torque_fluct : float
        Cycle RMS of |F| [N], of M about the crank axis [N·m], of Q - mean(Q) [N·m].
    objective : float
        J at the optimum.
    mechanism : Mechanism
        The balanced mechanism.
    """

    weights: tuple[float, float, float]
    counterweights: tuple[Counterweight, ...]
    force_rms: float
    moment_rms: float
    torque_fluct: float
    objective: float
    mechanism: Mechanism
    units: ClassVar[dict[str, str]] = {"force_rms": "N", "moment_rms": "N*m",
                                       "torque_fluct": "N*m"}
    position_field: ClassVar[str] = "force_rms"

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """The design's three criteria as bars: a :class:`linkwork.plot.Figure` with 1 axes."""
        from linkwork.plot.balancing import optimal_balance_figure

        return optimal_balance_figure(self, ax=ax, **kw)


class BalancingProblem:
    """Fast exact evaluation of counterweight designs for one mechanism (superposition).

    Parameters
    ----------
    mech : Mechanism
        Crank-driven mechanism with mass properties.
    links : sequence of str, optional
        Frame-hinged links that may carry a counterweight (default all).
    n : int
        Positions over one cycle.
    gravity : (gx, gy), optional
        Gravity [m/s²] (enters the driving torque only).
    """

    def __init__(self, mech: Mechanism, links: Sequence[str] | None = None, n: int = 180,
                 gravity: ArrayLike | None = None) -> None:
        self.mech = mech
        self.links = tuple(frame_hinged_links(mech) if links is None else links)
        if not self.links:
            raise ParameterError("links", [], "no link hinged to the frame")
        _, self.O = crank_axis(mech)
        self.phi = cycle(n)
        self.w = periodic_weights(self.phi)
        kin = kinematics(mech, self.phi)
        self.g = np.zeros(2) if gravity is None else require_finite("gravity", gravity)
        dyn = inverse_dynamics(kin, about=self.O, gravity=None if gravity is None else self.g)
        dyn_inertial = dyn if gravity is None else inverse_dynamics(kin, about=self.O)
        self.F0 = np.stack([dyn_inertial.shaking_fx, dyn_inertial.shaking_fy], -1)
        self.M0 = np.asarray(dyn_inertial.shaking_m)
        self.Q0 = np.asarray(dyn.Q)
        self.omega1 = kin.omega1
        self.B, self.H, self.th, self.om, self.ep = [], [], [], [], []
        for link in self.links:
            h = frame_hinge(mech, link)
            i = kin.bodies.index(link)
            self.B.append(_cw_force_basis(kin, link))
            c, s = np.cos(kin.theta[i]), np.sin(kin.theta[i])
            self.H.append(np.array([kin.x[i] + c * h[0] - s * h[1],
                                    kin.y[i] + s * h[0] + c * h[1]])[:, 0])
            self.th.append(kin.theta[i])
            self.om.append(kin.omega[i])
            self.ep.append(kin.eps[i])
        base = self.evaluate(np.zeros(3 * len(self.links)))
        self.ref = tuple(v if v > 0 else 1.0 for v in base)

    def loads(self, x: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(F (n, 2), M (n,), Q (n,)) for design x = (m, r, alpha) per link."""
        v = np.asarray(x, dtype=float).reshape(-1, 3)
        F = self.F0.copy()
        M = self.M0.copy()
        Q = self.Q0.copy()
        for k, (m, r, a) in enumerate(v):
            q = m * r * np.array([np.cos(a), np.sin(a)])
            Fk = self.B[k] @ q
            d = self.H[k] - self.O
            J = m * r * r
            F += Fk
            M += d[0] * Fk[:, 1] - d[1] * Fk[:, 0] - J * self.ep[k]
            psi = self.th[k] + a
            vx = -r * self.om[k] * np.sin(psi)
            vy = r * self.om[k] * np.cos(psi)
            Q += (J * self.om[k] * self.ep[k] - m * (self.g[0] * vx + self.g[1] * vy)) / \
                self.omega1
        return F, M, Q

    def evaluate(self, x: ArrayLike) -> tuple[float, float, float]:
        """(F_rms [N], M_rms [N·m], torque fluctuation RMS [N·m]) of design x."""
        F, M, Q = self.loads(x)
        tw = 2.0 * np.pi
        f = float(np.sqrt(np.sum(self.w * np.sum(F**2, axis=-1)) / tw))
        mm = float(np.sqrt(np.sum(self.w * M**2) / tw))
        qm = np.sum(self.w * Q) / tw
        qf = float(np.sqrt(np.sum(self.w * (Q - qm) ** 2) / tw))
        return f, mm, qf

    def evaluate_with_gradient(self, x: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """(F_rms, M_rms, torque fluctuation) and their gradients w.r.t. x, shape (3, 3k).

        Analytic: every load is linear in q = m r (cos a, sin a) and J = m r^2, so
        d(load)/d(m, r, a) follows by the chain rule; d sqrt(sum w f^2) = sum w f df / rms.
        """
        v = np.asarray(x, dtype=float).reshape(-1, 3)
        F, M, Q = self.loads(x)
        tw = 2.0 * np.pi
        f = float(np.sqrt(np.sum(self.w * np.sum(F**2, axis=-1)) / tw))
        mm = float(np.sqrt(np.sum(self.w * M**2) / tw))
        qd = Q - np.sum(self.w * Q) / tw
        qf = float(np.sqrt(np.sum(self.w * qd**2) / tw))
        grad = np.zeros((3, v.size))
        tiny = 1e-300
        for k, (m, r, a) in enumerate(v):
            u = np.array([np.cos(a), np.sin(a)])
            up = np.array([-np.sin(a), np.cos(a)])
            dq = (r * u, m * u, m * r * up)
            dJ = (r * r, 2 * m * r, 0.0)
            psi = self.th[k] + a
            G = -self.g[0] * np.sin(psi) + self.g[1] * np.cos(psi)
            Gp = -self.g[0] * np.cos(psi) - self.g[1] * np.sin(psi)
            dgv = (r * self.om[k] * G, m * self.om[k] * G, m * r * self.om[k] * Gp)
            d = self.H[k] - self.O
            for j in range(3):
                dF = self.B[k] @ dq[j]
                dM = d[0] * dF[:, 1] - d[1] * dF[:, 0] - dJ[j] * self.ep[k]
                dQ = (dJ[j] * self.om[k] * self.ep[k] - dgv[j]) / self.omega1
                col = 3 * k + j
                grad[0, col] = np.sum(self.w * np.sum(F * dF, axis=-1)) / (tw * max(f, tiny))
                grad[1, col] = np.sum(self.w * M * dM) / (tw * max(mm, tiny))
                grad[2, col] = np.sum(self.w * qd * dQ) / (tw * max(qf, tiny))
        return np.array([f, mm, qf]), grad

    def counterweights(self, x: ArrayLike) -> tuple[Counterweight, ...]:
        """Design vector -> counterweights (links with zero mass included)."""
        v = np.asarray(x, dtype=float).reshape(-1, 3)
        out = []
        for link, (m, r, a) in zip(self.links, v, strict=True):
            ang = float(np.angle(np.exp(1j * a)))
            out.append(Counterweight(link, float(m * r), ang, float(r)))
        return tuple(out)


def _bounds(prob: BalancingProblem, mass: tuple[float, float] | Mapping[str, tuple[float, float]],
            radius: tuple[float, float] | Mapping[str, tuple[float, float]]
            ) -> list[tuple[float, float]]:
    out = []
    for link in prob.links:
        mb = mass[link] if isinstance(mass, Mapping) else mass
        rb = radius[link] if isinstance(radius, Mapping) else radius
        lo_m, hi_m = (float(v) for v in mb)
        lo_r, hi_r = (float(v) for v in rb)
        if not (0.0 <= lo_m <= hi_m):
            raise ParameterError(f"mass bounds of {link}", (lo_m, hi_m), "need 0 <= lo <= hi")
        if not (0.0 < lo_r <= hi_r):
            raise ParameterError(f"radius bounds of {link}", (lo_r, hi_r), "need 0 < lo <= hi")
        out += [(lo_m, hi_m), (lo_r, hi_r), (-2 * np.pi, 2 * np.pi)]
    return out


def optimal_balance(mech: Mechanism | BalancingProblem, weights: Sequence[float] = (1, 1, 1), *,
                    mass: tuple[float, float] | Mapping[str, tuple[float, float]] = (0.0, 10.0),
                    radius: tuple[float, float] | Mapping[str, tuple[float, float]] = (
                        0.02, 0.2), links: Sequence[str] | None = None, n: int = 180,
                    starts: int = 4, seed: int = 0) -> OptimalBalance:
    """Counterweights minimising the weighted sum of normalised RMS shaking force, RMS shaking
    moment and driving-torque fluctuation (see the module docstring).

    Parameters
    ----------
    mech : Mechanism or BalancingProblem
        The mechanism (or a prepared problem, to reuse its motion for many weights).
    weights : (w_F, w_M, w_Q)
        Non-negative weights, not all zero.
    mass, radius : (lo, hi) or mapping link -> (lo, hi)
        Bounds of each counterweight's mass [kg] and radius [m].
    links : sequence of str, optional
        Frame-hinged links allowed to carry a counterweight (default all).
    n : int
        Positions per cycle.
    starts : int
        Local searches (SLSQP) from the force-balancing solution clipped to the bounds, from
        no counterweight and from random points; the best is returned.
    seed : int
        Seed of the random starts.

    Returns
    -------
    OptimalBalance
    """
    prob = mech if isinstance(mech, BalancingProblem) else BalancingProblem(mech, links, n)
    w = require_finite("weights", weights)
    if w.shape != (3,) or np.any(w < 0) or w.sum() == 0:
        raise ParameterError("weights", w.tolist(), "must be three weights >= 0, not all 0")
    bnds = _bounds(prob, mass, radius)
    lo = np.array([b[0] for b in bnds])
    hi = np.array([b[1] for b in bnds])

    scale = w / np.asarray(prob.ref)

    def J(x: np.ndarray) -> tuple[float, np.ndarray]:
        vals, grad = prob.evaluate_with_gradient(x)
        return float(scale @ vals), scale @ grad

    x0s = [np.clip(np.column_stack([np.zeros(len(prob.links)), (lo[1::3] + hi[1::3]) / 2,
                                    np.full(len(prob.links), np.pi)]).ravel(), lo, hi)]
    try:
        fb = force_balance(prob.mech, prob.links, n=len(prob.phi))
        xs = []
        for c, r_lo, r_hi, m_hi in zip(fb.counterweights, lo[1::3], hi[1::3], hi[0::3],
                                       strict=True):
            r = float(np.clip(max(c.static_moment / max(m_hi, 1e-300), (r_lo + r_hi) / 2),
                              r_lo, r_hi))
            xs += [c.static_moment / r, r, c.angle]
        x0s.insert(0, np.clip(np.array(xs), lo, hi))
    except ParameterError:
        pass
    rng = np.random.default_rng(seed)
    while len(x0s) < max(starts, 1):
        x0s.append(rng.uniform(lo, hi))
    from scipy import optimize  # lazily: 0.3-0.5 s of import that `linkwork --help` skips

    best = None
    for x0 in x0s[:max(starts, len(x0s[:2]))]:
        res = optimize.minimize(J, x0, jac=True, method="SLSQP", bounds=bnds,
                                options={"maxiter": 500, "ftol": 1e-12})
        if best is None or res.fun < best.fun:
            best = res
    assert best is not None
    x = best.x
    f, m, q = prob.evaluate(x)
    cws = prob.counterweights(x)
    bal = add_counterweights(prob.mech, [c for c in cws if c.static_moment > 0])
    return OptimalBalance((float(w[0]), float(w[1]), float(w[2])), cws, f, m, q,
                          float(best.fun), bal)


@dataclass(frozen=True)
class ParetoSet(Result):
    """Optimal designs over a set of weights, with the non-dominated ones flagged.

    Attributes
    ----------
    weights : ndarray (k, 3)
    force_rms, moment_rms, torque_fluct : ndarray (k,)
        [N], [N·m], [N·m].
    dominated : ndarray of bool (k,)
        True where another design is no worse in all three and better in one.
    designs : tuple of OptimalBalance
    unbalanced, static : tuple of float
        (F_rms, M_rms, torque fluctuation) of the unbalanced mechanism and of full force
        balancing (with the radii given), for comparison.
    """

    weights: np.ndarray
    force_rms: np.ndarray
    moment_rms: np.ndarray
    torque_fluct: np.ndarray
    dominated: np.ndarray
    designs: tuple[OptimalBalance, ...]
    unbalanced: tuple[float, float, float]
    static: tuple[float, float, float]
    units: ClassVar[dict[str, str]] = {"force_rms": "N", "moment_rms": "N*m",
                                       "torque_fluct": "N*m"}
    position_field: ClassVar[str] = "force_rms"

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """RMS shaking force against RMS shaking moment, coloured by the torque fluctuation:
        a :class:`linkwork.plot.Figure` with 1 axes (plus its colour bar)."""
        from linkwork.plot.balancing import pareto_figure

        return pareto_figure(self, ax=ax, **kw)


def weight_grid(k: int = 5) -> np.ndarray:
    """Weights (w_F, w_M, w_Q) on the simplex with steps 1/(k-1), shape (k(k+1)/2, 3)."""
    if int(k) != k or k < 2:
        raise ParameterError("k", k, "must be an integer >= 2")
    out = [(i, j, k - 1 - i - j) for i in range(k) for j in range(k - i)]
    return np.array(out, dtype=float) / (k - 1)


def pareto_set(mech: Mechanism, weights: ArrayLike | None = None, *,
               mass: tuple[float, float] | Mapping[str, tuple[float, float]] = (0.0, 10.0),
               radius: tuple[float, float] | Mapping[str, tuple[float, float]] = (0.02, 0.2),
               static_radii: float | Mapping[str, float] | None = None,
               links: Sequence[str] | None = None, n: int = 180, starts: int = 2
               ) -> ParetoSet:
    """Optimal balancing over many weights: the trade-off between F, M and Q fluctuation.

    Parameters are those of :func:`optimal_balance`; ``weights`` is an array (k, 3)
    (default :func:`weight_grid` with 5 steps, 15 weight vectors); ``static_radii`` are the
    radii of the force-balancing comparison design.
    """
    prob = BalancingProblem(mech, links, n)
    W = weight_grid(5) if weights is None else np.atleast_2d(require_finite("weights", weights))
    designs = tuple(optimal_balance(prob, wv, mass=mass, radius=radius, starts=starts)
                    for wv in W)
    f = np.array([d.force_rms for d in designs])
    m = np.array([d.moment_rms for d in designs])
    q = np.array([d.torque_fluct for d in designs])
    P = np.stack([f, m, q], -1)
    tol = 1e-9 * (np.abs(P).max(axis=0) + 1e-300)
    dom = np.array([np.any(np.all(P <= p + tol, axis=1) & np.any(P < p - tol, axis=1))
                    for p in P])
    fb = force_balance(mech, prob.links, static_radii, n=n)
    kin = kinematics(fb.mechanism, prob.phi)
    dyn = inverse_dynamics(kin, about=prob.O)
    Fs = np.stack([dyn.shaking_fx, dyn.shaking_fy], -1)
    Qs = dyn.Q - np.sum(prob.w * dyn.Q) / (2 * np.pi)
    static = (rms(prob.phi, Fs, vector=True), rms(prob.phi, dyn.shaking_m), rms(prob.phi, Qs))
    return ParetoSet(W, f, m, q, dom, designs, prob.evaluate(np.zeros(3 * len(prob.links))),
                     static)
