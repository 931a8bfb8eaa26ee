"""The comparison of paper 001 for any crank-driven planar mechanism.

For a mechanism of the planar engine:

1. unbalanced: shaking moment :math:`M(\\varphi)` about the crank axis O and shaking force;
2. static (force) balancing by counterweights on the frame-hinged links
   (:func:`~linkwork.balancing.mechanism.force_balance`): residual moment :math:`\\Delta M_1`;
3. the crank counterweight's axis moved to O1(x, y) so as to cancel the first harmonic of
   :math:`\\Delta M_1` over the cycle: :math:`\\Delta M_2`;
4. the axis chosen by least squares over the table's positions (the paper's method,
   formula (1) generalised): :math:`\\Delta M_3`;

with the paper's efficiencies :math:`R_2, R_3` (:func:`~linkwork.balancing.partial.efficiency`),
and what balancing does to the driving torque and the frame-bearing reactions.

Moving the counterweight's axis leaves the counterweight's kinetic and potential energy
unchanged up to a constant, so the driving torque after steps 3 and 4 equals the one after
step 2 (the counterweight is assumed driven 1:1 by an ideal transmission). The crank bearing O
then no longer carries the counterweight's inertia force; the new bearing O1 does (the
transmission's own forces, present only when :math:`\\varepsilon_1 \\ne 0`, are neglected).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.balancing.mechanism import (
    ForceBalance,
    crank_axis,
    cycle,
    force_balance,
    frame_hinge,
)
from linkwork.balancing.partial import (
    counterweight_axis_moment,
    counterweight_axis_offset,
    efficiency,
    first_harmonic_offset,
    rms_offset,
)
from linkwork.balancing.static import Counterweight
from linkwork.checks import require_finite
from linkwork.cycles import Harmonics, harmonics, peak, rms
from linkwork.errors import ParameterError
from linkwork.planar.dynamics import BodyTorque, Dynamics, PointForce, inverse_dynamics
from linkwork.planar.kinematics import Kinematics, kinematics
from linkwork.planar.model import Mechanism
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["BalancingComparison", "CycleComparison", "compare_balancing", "crank_axis"]


@dataclass(frozen=True)
class CycleComparison(Result):
    """Everything of :class:`BalancingComparison` over a full cycle (for plots and RMS).

    Attributes
    ----------
    phi1 : ndarray (n,)
        Crank angle [rad].
    M, dM1, dM2, dM3 : ndarray (n,)
        Shaking moment about O unbalanced, after static balancing, after the first-harmonic
        and after the least-squares axis shift [N·m].
    F0, F1 : ndarray (n, 2)
        Shaking force unbalanced and after static balancing [N] (moving the axis keeps F1).
    Q0, Q1 : ndarray (n,)
        Driving torque unbalanced and balanced [N·m].
    reactions0, reactions1, reactions3 : dict joint -> ndarray (n,)
        Magnitudes of the frame-joint reactions [N] unbalanced, after static balancing and
        after the least-squares axis shift (with the new bearing ``"O1"``).
    """

    phi1: np.ndarray
    M: np.ndarray
    dM1: np.ndarray
    dM2: np.ndarray
    dM3: np.ndarray
    F0: np.ndarray
    F1: np.ndarray
    Q0: np.ndarray
    Q1: np.ndarray
    reactions0: Mapping[str, np.ndarray] = field(default_factory=dict)
    reactions1: Mapping[str, np.ndarray] = field(default_factory=dict)
    reactions3: Mapping[str, np.ndarray] = field(default_factory=dict)
    units: ClassVar[dict[str, str]] = {"phi1": "rad", "M": "N*m", "dM1": "N*m", "dM2": "N*m",
                                       "dM3": "N*m", "Q0": "N*m", "Q1": "N*m", "Fx0": "N",
                                       "Fy0": "N", "Fx1": "N", "Fy1": "N", "R0": "N", "R1": "N",
                                       "R3": "N"}

    def columns(self) -> dict[str, np.ndarray]:
        """Per-position columns: the moments and torques, the shaking force components
        ``Fx0, Fy0`` (unbalanced) and ``Fx1, Fy1`` (force balanced), and the frame-joint
        reaction magnitudes ``R0_<joint>``, ``R1_<joint>``, ``R3_<joint>`` (unbalanced, static,
        moved axis; ``R3_O1`` is the moved counterweight's own bearing)."""
        cols: dict[str, np.ndarray] = {
            "phi1": self.phi1, "M": self.M, "dM1": self.dM1, "dM2": self.dM2, "dM3": self.dM3,
            "Q0": self.Q0, "Q1": self.Q1,
            "Fx0": self.F0[:, 0], "Fy0": self.F0[:, 1], "Fx1": self.F1[:, 0],
            "Fy1": self.F1[:, 1]}
        for tag, reac in (("R0", self.reactions0), ("R1", self.reactions1),
                          ("R3", self.reactions3)):
            for name, val in reac.items():
                cols[f"{tag}_{name}"] = np.asarray(val)
        return {k: np.asarray(v, dtype=float) for k, v in cols.items()}

    def _unit_of(self, column: str) -> str:
        """Unit of a CSV column: that of its family (``R1_O`` -> ``R1``)."""
        return self.units.get(column.split("_")[0], "")

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Shaking moments, force hodographs and driving torques over the cycle: a
        :class:`linkwork.plot.Figure` with 3 axes."""
        from linkwork.plot.balancing import cycle_comparison_figure

        return cycle_comparison_figure(self, axes=axes, **kw)


@dataclass(frozen=True)
class BalancingComparison(Result):
    """The paper-001 table for a mechanism, plus torque and bearing-load consequences.

    Attributes
    ----------
    phi1 : ndarray (k,)
        Table positions [rad].
    M, dM1, dM2, dM3 : ndarray (k,)
        Moments at the table positions [N·m] (as in :class:`CycleComparison`).
    R2, R3 : float
        Efficiencies of first-harmonic and least-squares balancing [%], over the table
        positions (the paper's definition); 0 when the residual moment after static
        balancing is only round-off (below 1e-9 of the unbalanced shaking force times the
        counterweight radius: nothing to balance).
    static_moment : float
        S of the crank counterweight [kg·m].
    x2, y2, x3, y3 : float
        Axis O1 relative to O [m] for methods 2 (first harmonic) and 3 (least squares over the
        table positions).
    x_rms, y_rms : float
        Axis minimising the continuous RMS over the cycle [m].
    counterweights : tuple of Counterweight
        Static-balancing counterweights.
    balance : ForceBalance
        The static balancing (with the balanced mechanism).
    cycle : CycleComparison
        Full-cycle arrays.
    """

    phi1: np.ndarray
    M: np.ndarray
    dM1: np.ndarray
    dM2: np.ndarray
    dM3: np.ndarray
    R2: float
    R3: float
    static_moment: float
    x2: float
    y2: float
    x3: float
    y3: float
    x_rms: float
    y_rms: float
    counterweights: tuple[Counterweight, ...]
    balance: ForceBalance
    cycle: CycleComparison
    units: ClassVar[dict[str, str]] = {"phi1": "rad", "M": "N*m", "dM1": "N*m", "dM2": "N*m",
                                       "dM3": "N*m", "R2": "%", "R3": "%", "static_moment":
                                       "kg*m", "x2": "m", "y2": "m", "x3": "m", "y3": "m",
                                       "x_rms": "m", "y_rms": "m"}

    def summary(self) -> dict[str, dict[str, float]]:
        """Peaks and RMS over the cycle: quantity -> {variant: value} (N, N·m)."""
        c = self.cycle
        p = c.phi1
        out: dict[str, dict[str, float]] = {
            "shaking force peak [N]": {"unbalanced": peak(c.F0), "static": peak(c.F1)},
            "shaking force RMS [N]": {"unbalanced": rms(p, c.F0), "static": rms(p, c.F1)},
            "shaking moment peak [N*m]": {
                "unbalanced": peak(c.M), "static": peak(c.dM1), "first harmonic": peak(c.dM2),
                "least squares": peak(c.dM3)},
            "shaking moment RMS [N*m]": {
                "unbalanced": rms(p, c.M), "static": rms(p, c.dM1),
                "first harmonic": rms(p, c.dM2), "least squares": rms(p, c.dM3)},
            "driving torque peak [N*m]": {"unbalanced": peak(c.Q0), "balanced": peak(c.Q1)},
            "driving torque RMS [N*m]": {"unbalanced": rms(p, c.Q0), "balanced": rms(p, c.Q1)},
        }
        for name in c.reactions0:
            out[f"frame joint {name} peak [N]"] = {
                "unbalanced": peak(c.reactions0[name]), "static": peak(c.reactions1[name]),
                "least squares": peak(c.reactions3[name])}
        if "O1" in c.reactions3:
            out["frame joint O1 peak [N]"] = {"least squares": peak(c.reactions3["O1"])}
        return out

    def harmonics(self, k: int = 4) -> dict[str, Harmonics]:
        """First k harmonics (in the crank angle) of the cycle quantities.

        Keys: ``"M"``, ``"dM1"``, ``"dM2"``, ``"dM3"``, ``"Fx0"``, ``"Fy0"`` (unbalanced
        shaking force), ``"Q0"``, ``"Q1"`` (driving torque unbalanced / balanced).
        """
        c = self.cycle
        series = {"M": c.M, "dM1": c.dM1, "dM2": c.dM2, "dM3": c.dM3, "Fx0": c.F0[:, 0],
                  "Fy0": c.F0[:, 1], "Q0": c.Q0, "Q1": c.Q1}
        return {name: harmonics(c.phi1, v, k) for name, v in series.items()}

    def increases(self) -> list[str]:
        """Plain-language list of quantities whose peak grows through balancing."""
        msgs = []
        summary = self.summary()
        # round-off floor per unit: a peak of 2e-15 N m "raised" from 9e-16 N m is no increase
        floor: dict[str, float] = {}
        for q, vals in summary.items():
            unit = q[q.rfind("["):]
            floor[unit] = max(floor.get(unit, 0.0), *vals.values())
        # moments: also the forces times the counterweights' lever (a mechanism whose moments
        # are all round-off, e.g. only the crank has mass, has no moment scale of its own)
        floor["[N*m]"] = max(floor.get("[N*m]", 0.0),
                             floor.get("[N]", 0.0) * _lever(self.counterweights))
        for q, vals in summary.items():
            if "peak" not in q or "unbalanced" not in vals:
                continue
            base = vals["unbalanced"]
            tiny = 1e-9 * floor[q[q.rfind("["):]]
            for variant, v in vals.items():
                if variant != "unbalanced" and v > base * (1 + 1e-9) and v - base > tiny:
                    pct = (v / base - 1) * 100 if base > 0 else float("inf")
                    msgs.append(f"{q}: {variant} {v:.4g} vs unbalanced {base:.4g} (+{pct:.1f} %)")
        return msgs

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """The paper-001 table as grouped bars: a :class:`linkwork.plot.Figure` with 1 axes
        (``self.cycle.plot()`` draws the whole cycle)."""
        from linkwork.plot.balancing import balancing_comparison_figure

        return balancing_comparison_figure(self, ax=ax, **kw)


def _lever(counterweights: Sequence[Counterweight]) -> float:
    """Largest counterweight radius [m]: the length that turns forces into moments."""
    return max((c.radius for c in counterweights if c.radius is not None), default=0.0)


def _frame_reactions(dyn: Dynamics, mech: Mechanism) -> dict[str, np.ndarray]:
    out = {}
    for j in mech.joints:
        if mech.frame.name in (j.a, j.b):
            out[j.name] = dyn.reaction_magnitude(j.name)
    return out


def _cw_direction(kin: Kinematics, crank: str, cw: Counterweight) -> np.ndarray:
    """Paper's angle: direction opposite the counterweight, theta_crank + alpha - pi [rad]."""
    return np.asarray(kin.angle(crank) + cw.angle - np.pi)


def compare_balancing(mech: Mechanism, positions: ArrayLike | None = None, *,
                      links: Sequence[str] | None = None,
                      radii: float | Mapping[str, float] | None = None, n: int = 360,
                      gravity: ArrayLike | None = None,
                      loads: Callable[[np.ndarray], Sequence[PointForce | BodyTorque]] | None
                      = None) -> BalancingComparison:
    """Paper 001's comparison of balancing methods for a crank-driven planar mechanism.

    Parameters
    ----------
    mech : Mechanism
        Crank-driven (the crank hinged to the frame), with mass properties; the crank's
        ``omega1`` and ``eps1`` are used.
    positions : array_like, optional
        Crank angles of the table [rad]; default 0, 30, ..., 330 deg as in the paper. The
        least-squares axis (method 3) is fitted over these positions, as in the paper.
    links : sequence of str, optional
        Frame-hinged links carrying static-balancing counterweights (default all); must
        include the crank.
    radii : float or mapping, optional
        Counterweight radii [m] (see :func:`~linkwork.balancing.mechanism.force_balance`).
    n : int
        Positions of the full cycle (first harmonic, RMS, plots).
    gravity : (gx, gy), optional
        Gravity [m/s²] for the driving torque and bearing reactions (the shaking moment
        columns are always the moments of inertia forces, as in the paper's table).
    loads : callable, optional
        ``loads(phi1)`` -> external loads at the cycle positions (e.g. the technological
        resistance), for the driving torque and bearing reactions only.

    Returns
    -------
    BalancingComparison

    Raises
    ------
    ParameterError
        Not a crank-driven mechanism, or the crank carries no counterweight.
    """
    crank, O = crank_axis(mech)
    frame_hinge(mech, crank)
    if float(mech.drivers[0].omega1) == 0.0:
        raise ParameterError("driver.omega1", 0.0, "must be non-zero: the comparison is of "
                             "inertia loads at the crank's speed")
    tab = np.radians(np.arange(0.0, 360.0, 30.0)) if positions is None else np.atleast_1d(
        require_finite("positions", positions))
    fb = force_balance(mech, links, radii, n=n)
    cws = {c.link: c for c in fb.counterweights}
    if crank not in cws or cws[crank].static_moment <= 0:
        raise ParameterError("links", list(cws), f"must include the crank {crank!r} with a "
                             "non-zero counterweight (the one whose axis is moved)")
    cw = cws[crank]
    S = cw.static_moment
    bal = fb.mechanism
    phi = cycle(n)

    def solve(m: Mechanism, q: np.ndarray, grav: ArrayLike | None) -> tuple[Kinematics,
                                                                             Dynamics]:
        k = kinematics(m, q)
        return k, inverse_dynamics(k, about=O, gravity=grav)

    k0, d0 = solve(mech, phi, None)
    k1, d1 = solve(bal, phi, None)
    _, t0 = solve(mech, tab, None)
    kt1, t1 = solve(bal, tab, None)
    w = k1.omega1
    e = k1.eps1
    pc = _cw_direction(k1, crank, cw)
    # the paper's angle is a full turn of the crank: reorder so that it increases
    order = np.argsort(np.mod(pc, 2 * np.pi))
    pcs = np.mod(pc, 2 * np.pi)[order]
    fh = first_harmonic_offset(pcs, d1.shaking_m[order], S, w[order], e[order])
    rm = rms_offset(pcs, d1.shaking_m[order], S, w[order], e[order])
    pt = _cw_direction(kt1, crank, cw)
    try:
        ls = counterweight_axis_offset(pt, t1.shaking_m, S, kt1.omega1, kt1.eps1)
    except ParameterError as exc:
        if exc.parameter != "phi":
            raise
        raise ParameterError("positions", f"{np.round(np.degrees(tab), 6).tolist()} deg",
                             "the least-squares axis (method 3) needs at least two table "
                             "positions that are not 0 or 180 deg apart") from None

    def shifted(p: np.ndarray, m: np.ndarray, ww: np.ndarray, ee: np.ndarray, x: float,
                y: float) -> np.ndarray:
        return np.asarray(m + counterweight_axis_moment(p, x, y, S, ww, ee))

    dM2c = shifted(pc, d1.shaking_m, w, e, fh.x, fh.y)
    dM3c = shifted(pc, d1.shaking_m, w, e, ls.x, ls.y)
    dM2t = shifted(pt, t1.shaking_m, kt1.omega1, kt1.eps1, fh.x, fh.y)
    dM3t = ls.residual
    # driving torque and bearing reactions (with gravity if asked)
    if gravity is not None or loads is not None:
        ext = () if loads is None else tuple(loads(phi))
        d0g = inverse_dynamics(k0, about=O, gravity=gravity, loads=ext)
        d1g = inverse_dynamics(k1, about=O, gravity=gravity, loads=ext)
    else:
        d0g, d1g = d0, d1
    for dyn in (d0g, d1g):
        dyn.require_no_self_locking("balancing compares the driving torque and the bearing "
                                    "loads over a full turn of the crank")
    r0 = _frame_reactions(d0g, mech)
    r1 = _frame_reactions(d1g, bal)
    # moving the axis: the counterweight's inertia (and weight) goes from O to O1
    m_cw = cw.mass()
    r_cw = cw.radius if cw.radius is not None else 0.0
    i = k1.bodies.index(crank)
    psi = k1.angle(crank) + cw.angle
    ux, uy = np.cos(psi), np.sin(psi)
    om, ep = k1.omega[i], k1.eps[i]
    ax = r_cw * (-ep * uy - om**2 * ux)
    ay = r_cw * (ep * ux - om**2 * uy)
    g = (0.0, 0.0) if gravity is None else tuple(float(v) for v in np.ravel(gravity))
    bx, by = m_cw * (ax - g[0]), m_cw * (ay - g[1])  # force the bearing applies to the cw
    drv = mech.joint(mech.drivers[0].joint)
    r3 = dict(r1)
    fx, fy = d1g.reaction(drv.name)
    sgn = 1.0 if drv.b == crank else -1.0  # reaction as force of the frame on the crank
    r3[drv.name] = np.hypot(sgn * fx - bx, sgn * fy - by)
    r3["O1"] = np.hypot(bx, by)
    cyc = CycleComparison(phi, d0.shaking_m, d1.shaking_m, dM2c, dM3c,
                          np.stack([d0.shaking_fx, d0.shaking_fy], -1),
                          np.stack([d1.shaking_fx, d1.shaking_fy], -1), d0g.Q, d1g.Q, r0, r1, r3)
    # R_j of a residual moment that is only round-off (nothing to balance) would be noise
    f_peak = float(np.max(np.hypot(d0.shaking_fx, d0.shaking_fy)))
    nothing = np.max(np.abs(t1.shaking_m)) <= 1e-9 * f_peak * _lever(fb.counterweights)
    R2 = 0.0 if nothing else efficiency(t1.shaking_m, dM2t)
    R3 = 0.0 if nothing else efficiency(t1.shaking_m, dM3t)
    return BalancingComparison(
        tab, t0.shaking_m, t1.shaking_m, dM2t, dM3t, R2, R3, S, fh.x, fh.y, ls.x, ls.y, rm.x,
        rm.y,
        fb.counterweights, fb, cyc)
