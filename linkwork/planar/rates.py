"""Velocities and accelerations of a planar mechanism, group by group, over all positions.

For each group the constraint equations, differentiated once and twice, give a linear system in
that group's unknown rates; the systems of all positions are solved at once: in closed form for
the driver body, by Cramer's rule for the dyads and one-body slot groups (each body hung on its
known neighbour by its external joint with one unknown rate, :class:`RatePar`; the joint between
them closes the loop), and by batched ``numpy.linalg.solve`` on the constraint Jacobian for the
Newton groups.
"""

from __future__ import annotations

import numpy as np

from linkwork.planar.joints import ClosureRow, ResolvedJoint, row_entries
from linkwork.planar.positions import Rows, assemble_jacobian, group_rows
from linkwork.planar.state import Arr, State, Vec
from linkwork.planar.structure import HUNG, Plan, PlanGroup

__all__ = ["RatePar", "acc_at", "batched_solve", "closure_rows", "cramer", "group_pars",
           "group_rates", "known_part", "vel_at"]


# velocities and accelerations
def group_rates(plan: Plan, st: State, g: PlanGroup, w1: Arr, e1: Arr) -> None:
    """Velocities and accelerations of the bodies of group ``g`` (the groups before it known);
    ``w1, e1`` the drivers' speeds and accelerations, shape (n_drivers, n)."""
    if g.kind == "driver":
        rd = g.joints[0]
        k = rd.drive_index
        if not rd.joint.driven_rates(st, rd, g.bodies[0], w1[k], e1[k]):
            _hung_driver_rates(st, g, w1[k], e1[k])
        return
    if g.kind in HUNG:
        _closed_rates(plan, st, g)
        return
    members = list(g.bodies)
    rows = group_rows(st, g, need_gamma=False)
    J, _ = assemble_jacobian(st, g, rows)
    rhs = -known_part(st, g, rows, "v")
    for r, (_, _, row) in enumerate(rows):
        if row.get("drive"):
            rhs[:, r] += w1[row["drive_index"]]
    good = ~st.bad
    sol = batched_solve(J, rhs, good)
    for k, b in enumerate(members):
        st.VX[b], st.VY[b], st.W[b] = sol[:, 3 * k], sol[:, 3 * k + 1], sol[:, 3 * k + 2]
    rows = group_rows(st, g, need_gamma=True)
    rhs = -known_part(st, g, rows, "a")
    for r, (_, _, row) in enumerate(rows):
        rhs[:, r] += row["gam"]
        if row.get("drive"):
            rhs[:, r] += e1[row["drive_index"]]
    sol = batched_solve(J, rhs, good)
    for k, b in enumerate(members):
        st.AX[b], st.AY[b], st.E[b] = sol[:, 3 * k], sol[:, 3 * k + 1], sol[:, 3 * k + 2]


def known_part(st: State, g: PlanGroup, rows: Rows, level: str) -> Arr:
    """Sum over known bodies of J_known * (q_dot or q_ddot) for each row."""
    members = set(g.bodies)
    out = np.zeros((st.n, len(rows)))
    for r, (ia, ib, row) in enumerate(rows):
        for body, ja in row_entries(ia, ib, row):
            if body not in members:
                if level == "v":
                    q = (st.VX[body], st.VY[body], st.W[body])
                else:
                    q = (st.AX[body], st.AY[body], st.E[body])
                out[:, r] += ja[0] * q[0] + ja[1] * q[1] + ja[2] * q[2]
    return out


# ---------------------------------------------------------------------------------------------
# closed-form velocities and accelerations of dyads and one-body slot groups
def vel_at(st: State, k: int, X: Vec) -> Vec:
    """Velocity of the material point of body k at world point X."""
    return (st.VX[k] - st.W[k] * (X[1] - st.Y[k]), st.VY[k] + st.W[k] * (X[0] - st.X[k]))


def acc_at(st: State, k: int, X: Vec) -> Vec:
    """Acceleration of the material point of body k at world point X."""
    rx, ry = X[0] - st.X[k], X[1] - st.Y[k]
    w2 = st.W[k] ** 2
    return (st.AX[k] - st.E[k] * ry - w2 * rx, st.AY[k] + st.E[k] * rx - w2 * ry)


class RatePar:
    """Motion of body b hung on a known body k through joint j, with one unknown rate z.

    The joint sets up the parametrisation (:meth:`~linkwork.planar.joints.Joint.hang`):

    Revolute at A: ``z = omega_b``, ``v_b(X) = v_k(A) + z k x (X - A)``,
    ``a_b(X) = a_k(A) + zdot k x (X - A) - z^2 (X - A)``.
    Prismatic with guide direction u: ``z`` = velocity of b relative to k along u,
    ``omega_b = omega_k``, ``v_b(X) = v_k(X) + z u``, ``a_b(X) = a_k(X) + zdot u + 2 omega_k z
    (k x u)``. A known body (``j`` None) has no unknown.
    """

    k: int  # the known neighbour
    pk: tuple[float, float]  # pivot: its local point on k
    A: Vec  # pivot: its world position
    u: Vec  # sliding: the guide direction

    def __init__(self, st: State, r: ResolvedJoint | None, b: int, idx: int | None) -> None:
        self.st, self.b, self.idx = st, b, idx
        self.rev = False
        self.known = r is None
        self.z: Arr | float = 0.0
        if r is None:
            return
        self.k = r.other(b)
        r.joint.hang(self, st, r)  # rotation about a pivot (rev) or sliding along u

    def d(self, X: Vec) -> Vec:
        if self.known:
            return 0.0, 0.0  # type: ignore[return-value]
        if self.rev:
            return -(X[1] - self.A[1]), X[0] - self.A[0]
        return self.u

    def cv(self, X: Vec) -> Vec:
        if self.known:
            return vel_at(self.st, self.b, X)
        if self.rev:
            return self.st.point_vel(self.k, self.pk)
        return vel_at(self.st, self.k, X)

    def w(self) -> tuple[Arr | float, float]:
        """Angular velocity as (constant part, coefficient of z)."""
        if self.known:
            return self.st.W[self.b], 0.0
        return (0.0, 1.0) if self.rev else (self.st.W[self.k], 0.0)

    def e(self) -> tuple[Arr | float, float]:
        if self.known:
            return self.st.E[self.b], 0.0
        return (0.0, 1.0) if self.rev else (self.st.E[self.k], 0.0)

    def ca(self, X: Vec) -> Vec:
        """Acceleration at X without the zdot term (z already solved)."""
        if self.known:
            return acc_at(self.st, self.b, X)
        z = self.z
        if self.rev:
            aA = self.st.point_acc(self.k, self.pk)
            return (aA[0] - z * z * (X[0] - self.A[0]), aA[1] - z * z * (X[1] - self.A[1]))
        aK = acc_at(self.st, self.k, X)
        c = 2 * self.st.W[self.k] * z
        return aK[0] - c * self.u[1], aK[1] + c * self.u[0]

    def vel(self, X: Vec) -> Vec:
        c = self.cv(X)
        if self.known:
            return c
        dd = self.d(X)
        return c[0] + self.z * dd[0], c[1] + self.z * dd[1]

    def set_velocity(self) -> None:
        st, b = self.st, self.b
        r = (st.X[b], st.Y[b])
        st.VX[b], st.VY[b] = self.vel(r)
        c, k = self.w()
        st.W[b] = np.asarray(c + k * self.z, dtype=float)

    def set_acceleration(self, zd: Arr) -> None:
        st, b = self.st, self.b
        r = (st.X[b], st.Y[b])
        c = self.ca(r)
        dd = self.d(r)
        st.AX[b], st.AY[b] = c[0] + zd * dd[0], c[1] + zd * dd[1]
        c0, k = self.e()
        st.E[b] = np.asarray(c0 + k * zd, dtype=float)


def closure_rows(st: State, r: ResolvedJoint, pars: dict[int, RatePar], n_unk: int,
                 level: str) -> list[ClosureRow]:
    """Closure equations of joint ``r`` in the unknown rates: rows (coefficients, rhs).

    ``level="v"``: velocity rows; ``"a"``: acceleration rows (the same coefficients, z known);
    see each joint type's :meth:`~linkwork.planar.joints.Joint.closure_rows`.
    """
    return r.joint.closure_rows(st, r, pars[r.ia], pars[r.ib], n_unk, level)


def cramer(st: State, rows: list[tuple[list[Arr | float], Arr]], scale: Arr | float
            ) -> list[Arr]:
    """Solve 1x1 or 2x2 systems position by position; singular -> NaN.

    A 2 x 2 system is singular (a toggle) where ``|det|`` is below 1e-7 times the product of its
    column norms (the sine of the angle between the columns); a 1 x 1 one where the coefficient
    is below 1e-7 ``scale`` (a length). Near a toggle rounding alone leaves that sine near
    1e-8, so such positions would otherwise give arbitrary finite rates.
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        if len(rows) == 1:
            (a,), r = rows[0]
            a = np.asarray(a) + np.zeros(st.n)
            sing = ~(np.abs(a) > 1e-7 * np.asarray(scale))
            return [np.where(sing, np.nan, r / np.where(sing, 1.0, a))]
        (a11, a12), r1 = rows[0]
        (a21, a22), r2 = rows[1]
        det = np.asarray(a11 * a22 - a12 * a21) + np.zeros(st.n)
        norm = np.hypot(a11, a21) * np.hypot(a12, a22)
        sing = ~(np.abs(det) > 1e-7 * norm)
        inv = 1.0 / np.where(sing, np.nan, det)
        return [(r1 * a22 - r2 * a12) * inv, (a11 * r2 - a21 * r1) * inv]


def group_pars(st: State, g: PlanGroup, nb: int
               ) -> tuple[dict[int, RatePar], ResolvedJoint, list[RatePar]]:
    """Parametrisations of a closed-form group's bodies and its closure joint."""
    members = g.bodies
    pars: dict[int, RatePar] = {}
    for i in range(nb):
        if i not in members:
            pars[i] = RatePar(st, None, i, None)
    if g.kind in ("RS", "PS"):
        rt, rs = g.joints
        b = members[0]
        pars[b] = RatePar(st, rt, b, 0)
        return pars, rs, [pars[b]]
    r1, r2, r3 = g.joints
    b1, b2 = members
    pars[b1] = RatePar(st, r1, b1, 0)
    pars[b2] = RatePar(st, r3, b2, 1)
    return pars, r2, [pars[b1], pars[b2]]


def _closed_rates(plan: Plan, st: State, g: PlanGroup) -> None:
    pars, rc, unk = group_pars(st, g, plan.nb)
    n_unk = len(unk)
    L = plan.length_scale
    scale = L ** n_unk
    z = cramer(st, closure_rows(st, rc, pars, n_unk, "v"), scale)
    for p, zi in zip(unk, z, strict=True):
        p.z = zi
    for p in unk:
        p.set_velocity()
    zd = cramer(st, closure_rows(st, rc, pars, n_unk, "a"), scale)
    for p, zdi in zip(unk, zd, strict=True):
        p.set_acceleration(zdi)


def _hung_driver_rates(st: State, g: PlanGroup, w1: Arr, e1: Arr) -> None:
    """The driven body hung on its joint with the driver's rate (a linear driver)."""
    r = g.joints[0]
    b = g.bodies[0]
    sign = 1.0 if b == r.ib else -1.0
    p = RatePar(st, r, b, 0)
    p.z = sign * w1
    p.set_velocity()
    p.set_acceleration(sign * e1)


def batched_solve(J: Arr, rhs: Arr, good: Arr) -> Arr:
    out = np.full(rhs.shape, np.nan)
    if good.all():
        Jg, rg = J, rhs
    else:
        Jg, rg = J[good], rhs[good]
    with np.errstate(all="ignore"):
        det = np.linalg.det(Jg) if Jg.shape[0] else np.zeros(0)
        sing = ~(np.abs(det) > 1e-300)
        if sing.any():
            Jg = Jg.copy()
            Jg[sing] = np.eye(J.shape[1])
        x = np.linalg.solve(Jg, rg[..., None])[..., 0]
        x[sing] = np.nan
    if good.all():
        return x
    out[good] = x
    return out
