"""Transmission angles and dead centres of the closed-form groups of a planar mechanism.

These work on a solved :class:`~linkwork.planar.state.State` (rebuilt from a
:class:`~linkwork.planar.kinematics.Kinematics` result); the public entry points
:func:`linkwork.planar.kinematics.transmission_angles` and
:func:`linkwork.planar.kinematics.dead_centres` take the result itself.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from linkwork.planar.rates import group_pars, vel_at
from linkwork.planar.state import Arr, State
from linkwork.planar.structure import HUNG, Plan, PlanGroup

__all__ = ["DeadCentre", "dead_centres_of", "dead_centres_of_rates", "group_rate",
           "output_rates", "transmission_angles_of"]


@dataclass(frozen=True)
class DeadCentre:
    """A dead-centre (extreme) position of a group's output body.

    ``phi1`` [rad or m] is where the output body's motion relative to its external joint
    reverses (angular velocity relative to the neighbour, or sliding speed, crosses zero),
    located between the samples to ~1e-13 (see :func:`dead_centres`); ``kind`` is ``"min"`` or
    ``"max"`` of its angle or slide.
    """

    group: str
    body: str
    phi1: float
    kind: str


def transmission_angles_of(plan: Plan, st: State) -> dict[str, tuple[Arr, Arr]]:
    """Transmission and pressure angles (mu, delta) [rad] of every closed-form group of the
    plan in the solved state ``st`` (see :func:`linkwork.planar.kinematics.transmission_angles`).
    """
    out: dict[str, tuple[Arr, Arr]] = {}
    for g in plan.groups:
        if g.kind not in HUNG:
            continue
        _pars, rc, unk = group_pars(st, g, plan.nb)
        out_par = unk[-1]
        P = st.wpt(rc.ib, rc.pb)
        fx, fy = rc.joint.transmitted_direction(st, rc, unk[0], P)
        vx, vy = out_par.d(P)
        # atan2(|f x v|, |f . v|): full precision also near 0 and 90 deg (arccos of the
        # cosine loses half the digits near delta = 0)
        cr, dt = np.abs(fx * vy - fy * vx), np.abs(fx * vx + fy * vy)
        delta = np.where((cr == 0) & (dt == 0), np.nan, np.arctan2(cr, dt))  # NaN: undefined
        out[g.key] = (np.pi / 2 - delta, delta)
    return out


def group_rate(plan: Plan, st: State, g: PlanGroup) -> tuple[int, Arr]:
    """Output body of a closed-form group and its rate relative to its external neighbour:
    angular velocity (revolute) or sliding speed along the guide (prismatic)."""
    _pars, _, unk = group_pars(st, g, plan.nb)
    p = unk[-1]
    b = p.b
    if p.rev:
        return b, st.W[b] - st.W[p.k]
    # sliding velocity of the output body relative to its neighbour along u
    r = (st.X[b], st.Y[b])
    vb, vk = vel_at(st, b, r), vel_at(st, p.k, r)
    return b, (vb[0] - vk[0]) * p.u[0] + (vb[1] - vk[1]) * p.u[1]


#: the solved state of the mechanism at one driver position (unit speed, no acceleration)
Resolve = Callable[[float], State]


def _refine_dead_centre(plan: Plan, resolve: Resolve, g: PlanGroup, lo: float, hi: float,
                        guess: float) -> float:
    """The zero of the group's rate between driver positions lo and hi, to ~1e-13 [rad or m]:
    Brent's method on single-position analyses (unit driver speed, no acceleration), falling
    back to ``guess`` (linear interpolation) where that is not possible."""

    from scipy.optimize import brentq  # lazily: 0.2 s of import that `linkwork --help` skips

    def rate(x: float) -> float:
        return float(group_rate(plan, resolve(x), g)[1][0])

    try:
        f_lo, f_hi = rate(lo), rate(hi)
        if not (np.isfinite(f_lo) and np.isfinite(f_hi)) or f_lo * f_hi > 0:
            return guess
        if f_lo == 0.0:
            return lo
        if f_hi == 0.0:
            return hi
        scale = max(abs(lo), abs(hi), 1.0)
        return float(brentq(rate, lo, hi, xtol=1e-14 * scale, rtol=1e-15, maxiter=60))
    except (ValueError, RuntimeError):  # every linkwork error is one of these
        return guess


def dead_centres_of(plan: Plan, st: State, q: Arr, resolve: Resolve | None
                    ) -> list[DeadCentre]:
    """Dead centres of every closed-form group of the plan in the solved state ``st`` over the
    driver positions ``q``; each sign change is refined with ``resolve`` (None: linear
    interpolation only). See :func:`linkwork.planar.kinematics.dead_centres`."""
    return dead_centres_of_rates(plan, output_rates(plan, st), q, resolve)


def output_rates(plan: Plan, st: State) -> dict[str, tuple[int, Arr]]:
    """The output body and its rate (:func:`group_rate`) of every closed-form group, by group
    key: what :func:`dead_centres_of_rates` needs of a solved motion (a long cycle keeps these
    one array per group, chunk after chunk, instead of the whole motion)."""
    return {g.key: group_rate(plan, st, g) for g in plan.groups if g.kind in HUNG}


def dead_centres_of_rates(plan: Plan, rates: dict[str, tuple[int, Arr]], q: Arr,
                          resolve: Resolve | None) -> list[DeadCentre]:
    """Dead centres from the output rates (:func:`output_rates`) over the driver positions
    ``q``: each sign change of a rate, refined with ``resolve`` (None: linear interpolation),
    and each sample where a rate is zero between samples of opposite signs."""
    groups = {g.key: g for g in plan.groups}
    found: list[DeadCentre] = []
    for key, (b, rate) in rates.items():
        g = groups[key]
        tiny = 1e-12 * float(np.nanmax(np.abs(rate))) if np.isfinite(rate).any() else 0.0
        rate = np.where(np.abs(rate) <= tiny, 0.0, rate)
        sgn = np.sign(rate)
        name = plan.body_names[b]
        idx = np.flatnonzero((sgn[:-1] * sgn[1:] < 0) & np.isfinite(rate[:-1] + rate[1:]))
        for i in idx:
            t = rate[i] / (rate[i] - rate[i + 1])
            at = float(q[i] + t * (q[i + 1] - q[i]))
            if resolve is not None:
                at = _refine_dead_centre(plan, resolve, g, float(q[i]), float(q[i + 1]), at)
            found.append(DeadCentre(g.key, name, at, "max" if rate[i] > 0 else "min"))
        for i in np.flatnonzero(sgn == 0):  # a sample exactly at the dead centre
            before = sgn[i - 1] if i > 0 else -sgn[i + 1] if i + 1 < sgn.size else 0
            after = sgn[i + 1] if i + 1 < sgn.size else -before
            if before * after < 0:
                found.append(DeadCentre(g.key, name, float(q[i]), "max" if before > 0 else "min"))
    found.sort(key=lambda d: (d.group, d.phi1))
    return found
