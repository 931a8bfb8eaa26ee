"""Kinetostatics with Coulomb friction in the joints: the exact solve, losses, self-locking.

Each joint type states its own friction law in :mod:`linkwork.planar.joints`
(:meth:`~linkwork.planar.joints.Joint.friction_wrench`: the friction force and couple exerted
by its body a on its body b, given the joint's constraint reaction and the relative motion);
this module solves the equilibrium of all bodies with those laws, at every position at once.

The problem
-----------
Without friction the equilibrium is linear, ``J^T lambda = f`` (``J`` the constraint Jacobian
with the driver's row, ``lambda`` the multipliers, ``f`` the applied and inertia loads on every
moving body; :func:`linkwork.planar.dynamics.inverse_dynamics`). The friction forces and
couples ``G(lambda)`` depend on the magnitudes of the reactions (``|R|``, ``|N|``, ``|N1| +
|N2|``) and on the direction of the relative velocities, which the kinematics gives:

.. math:: \\mathbf r(\\lambda) = J^T\\lambda - \\mathbf G(\\lambda) - \\mathbf f = 0 .

It is solved exactly (to a residual of ``TOL`` times the loads' scale) by Newton's method from
the frictionless solution, all positions at once, with the Jacobian ``J^T - dG/dlambda``
(``dG/dlambda`` by central differences over the multipliers of the joints with friction; the
residual is exact, so the Jacobian's accuracy only changes the number of iterations). ``G`` is
positively homogeneous of degree 1 in ``lambda`` and piecewise linear in the reaction
magnitudes, so Newton ends in a few steps once the signs of the normal forces are right.

Where a relative velocity passes through zero (a revolute at a dead centre, a slider
reversing) the sign is regularised: :func:`~linkwork.planar.joints.smooth_sign` with width
``SIGN_WIDTH`` times the driver's largest speed (rotation; times the mechanism's length scale
for sliding), i.e. the friction fades to zero over a band of relative speeds 1e-9 of the
driver's (the sign is off by ``width^2 / (2 v^2)``: below 1e-12 once ``|v|`` exceeds a
thousandth of the driver's speed). The relative velocities come from the kinematics, so the
sign is a known number at each position, not an unknown of the solve (except the side of the
slot a pin touches, which follows the sign of its normal force). With the driver at rest at
every position (``omega1 = 0``) friction is not determined by Coulomb's law (static): it is set
to zero and said so in ``Dynamics.friction_static``.

Self-locking
------------
``kappa = det(J^T - dG/dlambda) / det(J^T)`` at the solution (1 without friction). It is the
factor by which friction divides the drive's gain: the driving torque grows like ``1/kappa``
as kappa -> 0 and diverges where it vanishes. A position is **self-locking** where kappa <= 0
(the friction-augmented system changed its sign: the solution found moves the mechanism only
if the driver pulls it backwards) or where no solution exists (Newton did not converge: no
finite driving torque moves the mechanism). Those positions are flagged in ``Dynamics.locked``
and their reactions and driving torque are undefined (NaN, written as empty/null).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkwork.planar.joints import ResolvedJoint
from linkwork.planar.rates import batched_solve
from linkwork.planar.state import Arr, State
from linkwork.planar.structure import Plan

__all__ = [
    "MAX_ITER",
    "SIGN_WIDTH",
    "TOL",
    "FrictionSolution",
    "has_friction",
    "has_separation",
    "separated",
    "separating_forces",
    "sign_widths",
    "solve",
]

#: width of the smooth sign, relative to the driver's largest speed
SIGN_WIDTH = 1e-9
#: residual of the equilibrium, relative to the largest load or multiplier term at the position
TOL = 1e-12
#: Newton iterations at most
MAX_ITER = 60

#: one multiplier row: (its joint, its kind: a row kind of the joint, or "drive")
Meta = list[tuple[ResolvedJoint, str]]


def has_friction(plan: Plan) -> bool:
    """Some joint of the plan dissipates."""
    return any(rj.joint.has_friction for rj in plan.joints)


def has_separation(plan: Plan) -> bool:
    """Some joint's reaction has a part set by the magnitude of its multiplier (a gear pair's
    separating force)."""
    return any(rj.joint.has_separation for rj in plan.joints)


def sign_widths(plan: Plan, omega1: Arr) -> tuple[float, float]:
    """Widths of the smooth sign: rotation [rad/s] and sliding [m/s] (see the module doc); with
    several drivers from the fastest (a slide speed counted as a rotation over the mechanism's
    length scale)."""
    L = plan.length_scale
    w = np.atleast_2d(np.asarray(omega1, dtype=float))
    top = 0.0
    for k, kind in enumerate(plan.driver_kinds or (plan.driver_kind,)):
        v = float(np.max(np.abs(w[k]), initial=0.0)) if w[k].size else 0.0
        top = max(top, v / L if kind == "linear" else v)  # linear: omega1 a slide speed [m/s]
    if not np.isfinite(top):
        top = 0.0
    return SIGN_WIDTH * top, SIGN_WIDTH * top * L


@dataclass(frozen=True)
class FrictionSolution:
    """The multipliers with friction and what they carry.

    ``lam`` (n, size): the multipliers; ``ffx, ffy, fmz`` (n_joints, n): the friction force
    [N] (at the joint's reaction point) and couple [N m] exerted by the joint's body a on its
    body b; ``converged`` (n,): Newton reached the tolerance; ``kappa`` (n,): the self-locking
    indicator (NaN where not converged); ``iterations``: Newton steps taken.
    """

    lam: Arr
    ffx: Arr
    ffy: Arr
    fmz: Arr
    converged: Arr
    kappa: Arr
    iterations: int


def _joint_rows(plan: Plan, meta: Meta) -> list[tuple[ResolvedJoint, list[tuple[int, str]]]]:
    """The joints with friction (or a separating force) and their multiplier rows (drive rows
    excluded)."""
    out = []
    for rj in plan.joints:
        if rj.joint.has_friction or rj.joint.has_separation:
            rows = [(r, kind) for r, (rj2, kind) in enumerate(meta)
                    if rj2 is rj and kind != "drive"]
            out.append((rj, rows))
    return out


def _wrenches(st: State, lam: Arr, jrows: list[tuple[ResolvedJoint, list[tuple[int, str]]]],
              width: tuple[float, float], separation: bool = True
              ) -> list[tuple[Arr, Arr, Arr]]:
    """Friction (Fx, Fy, Mz) by a on b of every joint in ``jrows`` (zero for one without),
    with its separating force added (``separation``)."""
    out = []
    n = lam.shape[0]
    for rj, rows in jrows:
        comp = {"fx": np.zeros(n), "fy": np.zeros(n), "mz": np.zeros(n)}
        for r, kind in rows:
            for key, v in rj.joint.reaction_components(st, rj, kind, lam[:, r]).items():
                comp[key] = comp[key] + v
        j = rj.joint
        wr = (j.friction_wrench(st, rj, comp["fx"], comp["fy"], comp["mz"], width)
              if j.has_friction else (np.zeros(n), np.zeros(n), np.zeros(n)))
        if separation and j.has_separation:
            sx, sy = j.separation(st, rj, comp["fx"], comp["fy"])
            wr = (wr[0] + sx, wr[1] + sy, wr[2])
        out.append(wr)
    return out


def separating_forces(plan: Plan, st: State, lam: Arr, meta: Meta) -> tuple[Arr, Arr]:
    """The separating forces (fx, fy) on b of every joint (n_joints, n) for the multipliers
    ``lam`` (zero for the joints without)."""
    nj, n = len(plan.joints), st.n
    sfx, sfy = np.zeros((nj, n)), np.zeros((nj, n))
    for rj, rows in _joint_rows(plan, meta):
        if rj.joint.has_separation:
            fx, fy = np.zeros(n), np.zeros(n)
            for r, kind in rows:
                comp = rj.joint.reaction_components(st, rj, kind, lam[:, r])
                fx = fx + comp.get("fx", 0.0)
                fy = fy + comp.get("fy", 0.0)
            sfx[rj.index], sfy[rj.index] = rj.joint.separation(st, rj, fx, fy)
    return sfx, sfy


def separated(plan: Plan, st: State, JT: Arr, f: Arr, lam0: Arr, good: Arr, meta: Meta
              ) -> Arr:
    """The multipliers with the separating forces of frictionless joints: they do no work, so
    they leave the multipliers they depend on unchanged and one more linear solve, ``J^T lam
    = f + G(lam0)``, gives the others."""
    jrows = _joint_rows(plan, meta)
    G = _generalised(st, f.shape[1], jrows, _wrenches(st, np.nan_to_num(lam0), jrows,
                                                       (0.0, 0.0)))
    return batched_solve(JT, f + G, good)


def _generalised(st: State, size: int, jrows: list[tuple[ResolvedJoint, list[tuple[int, str]]]],
                 wr: list[tuple[Arr, Arr, Arr]]) -> Arr:
    """The friction wrenches as generalised forces on the moving bodies (about their origins):
    the wrench on body b, its opposite on body a, at the joint's reaction point."""
    G = np.zeros((st.n, size))
    for (rj, _), (Fx, Fy, Mz) in zip(jrows, wr, strict=True):
        Px, Py = rj.joint.reaction_point(st, rj)
        for body, sgn in ((rj.ib, 1.0), (rj.ia, -1.0)):
            if body == 0:
                continue
            G[:, 3 * body - 3] += sgn * Fx
            G[:, 3 * body - 2] += sgn * Fy
            G[:, 3 * body - 1] += sgn * (Mz + (Px - st.X[body]) * Fy - (Py - st.Y[body]) * Fx)
    return G


def solve(plan: Plan, st: State, JT: Arr, f: Arr, lam0: Arr, good: Arr, meta: Meta,
          width: tuple[float, float]) -> FrictionSolution:
    """Newton's method on ``J^T lambda - G(lambda) = f`` from ``lam0`` (the frictionless
    multipliers), at the positions ``good`` (the others stay NaN)."""
    n, size = f.shape
    jrows = _joint_rows(plan, meta)
    lam = np.where(good[:, None], lam0, 0.0)
    ok = good & np.all(np.isfinite(lam), axis=1)
    lam[~ok] = 0.0
    done = ~ok
    converged = np.zeros(n, dtype=bool)
    it = 0

    def residual(lm: Arr) -> Arr:
        G = _generalised(st, size, jrows, _wrenches(st, lm, jrows, width))
        return np.einsum("kij,kj->ki", JT, lm) - f - G

    def jacobian(lm: Arr) -> Arr:
        """``J^T - dG/dlambda``: each joint's law differenced in its own multipliers only."""
        A = JT.copy()
        h = 1e-7 * (np.max(np.abs(lm), axis=1) + 1e-30)
        for one in jrows:
            for c, _ in one[1]:
                lp, lq = lm.copy(), lm.copy()
                lp[:, c] += h
                lq[:, c] -= h
                Gp = _generalised(st, size, [one], _wrenches(st, lp, [one], width))
                Gq = _generalised(st, size, [one], _wrenches(st, lq, [one], width))
                A[:, :, c] -= (Gp - Gq) / (2 * h)[:, None]
        return A

    with np.errstate(all="ignore"):
        scale = np.max(np.abs(f), axis=1)
        for it in range(MAX_ITER + 1):
            R = residual(lam)
            term = np.max(np.abs(np.einsum("kij,kj->ki", JT, lam)), axis=1)
            conv = np.max(np.abs(R), axis=1) <= TOL * np.maximum(scale, term)
            converged |= conv & ~done
            done |= conv
            active = ~done & np.all(np.isfinite(lam), axis=1)
            if not active.any() or it == MAX_ITER:
                break
            step = batched_solve(jacobian(lam), R, active)
            lam[active] -= step[active]
        A = jacobian(lam)
        det_aug = np.linalg.det(np.where(converged[:, None, None], A, np.eye(size)))
        det0 = np.linalg.det(np.where(converged[:, None, None], JT, np.eye(size)))
        kappa = np.where(converged, det_aug / det0, np.nan)
    lam[~converged] = np.nan
    wr = _wrenches(st, lam, jrows, width, separation=False)
    nj = len(plan.joints)
    ffx, ffy, fmz = (np.zeros((nj, n)) for _ in range(3))
    for (rj, _), (Fx, Fy, Mz) in zip(jrows, wr, strict=True):
        ffx[rj.index], ffy[rj.index], fmz[rj.index] = Fx, Fy, Mz
    bad = ~converged
    ffx[:, bad] = np.nan
    ffy[:, bad] = np.nan
    fmz[:, bad] = np.nan
    return FrictionSolution(lam, ffx, ffy, fmz, converged, kappa, it)
