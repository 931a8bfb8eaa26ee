"""Velocities and accelerations of a planar mechanism, group by group, over all positions.

For each group the constraint equations, differentiated once and twice, give a linear system in
that group's unknown rates; the systems of all positions are solved at once: in closed form for
the driver body, by Cramer's rule for the dyads and one-body slot groups (each body hung on its
known neighbour by its external joint with one unknown rate, :class:`RatePar`; the joint between
them closes the loop), and by batched ``numpy.linalg.solve`` on the constraint Jacobian for the
Newton groups.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from linkwork.planar.model import Joint, Mechanism, Prismatic, Revolute
from linkwork.planar.positions import assemble_jacobian, group_rows, length_scale
from linkwork.planar.state import Arr, State, Vec
from linkwork.planar.structure import Group

__all__ = ["RatePar", "acc_at", "batched_solve", "closure_rows", "cramer", "group_pars",
           "group_rates", "known_part", "vel_at"]


# velocities and accelerations
def _driver_rates(mech: Mechanism, st: State, g: Group, w1: Arr, e1: Arr) -> bool:
    """Closed-form velocity/acceleration of a crank body; False if not applicable."""
    j = mech.joint(g.joints[0])
    if not isinstance(j, Revolute):
        return False
    ia, ib = mech.index[j.a], mech.index[j.b]
    u = mech.index[g.bodies[0]]
    k = ia if u == ib else ib
    sign = 1.0 if u == ib else -1.0
    qa, pb, _ = mech.joint_geometry(j)
    pk, pu = (qa, pb) if u == ib else (pb, qa)
    st.W[u] = st.W[k] + sign * w1
    st.E[u] = st.E[k] + sign * e1
    vP = st.point_vel(k, pk)
    aP = st.point_acc(k, pk)
    rx, ry = st.rot(u, pu)
    w, e = st.W[u], st.E[u]
    st.VX[u], st.VY[u] = vP[0] + w * ry, vP[1] - w * rx
    st.AX[u] = aP[0] + e * ry + w * w * rx
    st.AY[u] = aP[1] - e * rx + w * w * ry
    return True


def group_rates(mech: Mechanism, st: State, g: Group, w1: Arr, e1: Arr) -> None:
    if g.kind == "driver":
        if not _driver_rates(mech, st, g, w1, e1):
            _linear_driver_rates(mech, st, g, w1, e1)
        return
    if g.kind != "newton":
        _closed_rates(mech, st, g)
        return
    members = [mech.index[b] for b in g.bodies]
    rows = group_rows(mech, st, g, need_gamma=False)
    J, _ = assemble_jacobian(mech, st, g, rows)
    rhs = -known_part(mech, st, g, rows, "v")
    for r, (_, _, row) in enumerate(rows):
        if row.get("drive"):
            rhs[:, r] += w1
    good = ~st.bad
    sol = batched_solve(J, rhs, good)
    for k, b in enumerate(members):
        st.VX[b], st.VY[b], st.W[b] = sol[:, 3 * k], sol[:, 3 * k + 1], sol[:, 3 * k + 2]
    rows = group_rows(mech, st, g, need_gamma=True)
    rhs = -known_part(mech, st, g, rows, "a")
    for r, (_, _, row) in enumerate(rows):
        rhs[:, r] += row["gam"]
        if row.get("drive"):
            rhs[:, r] += e1
    sol = batched_solve(J, rhs, good)
    for k, b in enumerate(members):
        st.AX[b], st.AY[b], st.E[b] = sol[:, 3 * k], sol[:, 3 * k + 1], sol[:, 3 * k + 2]


def known_part(mech: Mechanism, st: State, g: Group, rows: list[tuple[int, int, dict[str, Any]]],
                level: str) -> Arr:
    """Sum over known bodies of J_known * (q_dot or q_ddot) for each row."""
    members = {mech.index[b] for b in g.bodies}
    out = np.zeros((st.n, len(rows)))
    for r, (ia, ib, row) in enumerate(rows):
        for body, key in ((ia, "ja"), (ib, "jb")):
            if body not in members:
                if level == "v":
                    q = (st.VX[body], st.VY[body], st.W[body])
                else:
                    q = (st.AX[body], st.AY[body], st.E[body])
                ja = row[key]
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

    Revolute at A: ``z = omega_b``, ``v_b(X) = v_k(A) + z k x (X - A)``,
    ``a_b(X) = a_k(A) + zdot k x (X - A) - z^2 (X - A)``.
    Prismatic with guide direction u: ``z`` = velocity of b relative to k along u,
    ``omega_b = omega_k``, ``v_b(X) = v_k(X) + z u``, ``a_b(X) = a_k(X) + zdot u + 2 omega_k z
    (k x u)``. A known body (``j`` None) has no unknown.
    """

    def __init__(self, mech: Mechanism, st: State, j: Joint | None, b: int,
                 idx: int | None) -> None:
        self.st, self.b, self.idx = st, b, idx
        self.rev = False
        self.known = j is None
        self.z: Arr | float = 0.0
        if j is None:
            return
        ia, ib = mech.index[j.a], mech.index[j.b]
        self.k = ia if b == ib else ib
        qa, pb, ang = mech.joint_geometry(j)
        if isinstance(j, Revolute):
            self.rev = True
            self.pk = qa if self.k == ia else pb
            self.A = st.wpt(self.k, self.pk)
        else:
            self.u = st.rot(ia, (np.cos(ang), np.sin(ang)))

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


def closure_rows(mech: Mechanism, st: State, j: Joint, pars: dict[int, RatePar], n_unk: int,
                  level: str) -> list[tuple[list[Arr | float], Arr]]:
    """Closure equations of joint j in the unknown rates: rows (coefficients, rhs).

    ``level="v"``: velocity rows; ``"a"``: acceleration rows (the same coefficients, z known).
    Revolute at B: ``v_a(B) = v_b(B)``; prismatic (guide a): ``omega_a = omega_b`` and
    ``n . (v_b(P) - v_a(P)) = 0``; pin-in-slot: the latter only. Accelerations add the Coriolis
    term ``-2 omega_a k x v_rel`` of the relative sliding.
    """
    ia, ib = mech.index[j.a], mech.index[j.b]
    pa_, pb_ = pars[ia], pars[ib]
    _qa, pb, ang = mech.joint_geometry(j)
    rows: list[tuple[list[Arr | float], Arr]] = []

    def coefs(vals: list[tuple[RatePar, Any]]) -> list[Arr | float]:
        c: list[Arr | float] = [0.0] * n_unk
        for par, val in vals:
            if par.idx is not None:
                c[par.idx] = c[par.idx] + val
        return c

    if isinstance(j, Revolute):
        B = st.wpt(ib, pb)
        da, db = pa_.d(B), pb_.d(B)
        if level == "v":
            ca, cb = pa_.cv(B), pb_.cv(B)
        else:
            ca, cb = pa_.ca(B), pb_.ca(B)
        for c in range(2):
            rows.append((coefs([(pa_, da[c]), (pb_, -db[c])]), cb[c] - ca[c]))
        return rows
    P = st.wpt(ib, pb)
    ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
    nx, ny = -uy, ux
    da, db = pa_.d(P), pb_.d(P)
    cf = coefs([(pa_, -(nx * da[0] + ny * da[1])), (pb_, nx * db[0] + ny * db[1])])
    if level == "v":
        ca, cb = pa_.cv(P), pb_.cv(P)
        rows.append((cf, -(nx * (cb[0] - ca[0]) + ny * (cb[1] - ca[1]))))
    else:
        ca, cb = pa_.ca(P), pb_.ca(P)
        va, vb = pa_.vel(P), pb_.vel(P)
        wa = pa_.w()[0] + pa_.w()[1] * pa_.z
        rvx, rvy = vb[0] - va[0], vb[1] - va[1]
        cor = 2 * wa * (nx * -rvy + ny * rvx)
        rows.append((cf, -(nx * (cb[0] - ca[0]) + ny * (cb[1] - ca[1])) + cor))
    if isinstance(j, Prismatic):
        (c0a, ka), (c0b, kb) = (pa_.w(), pb_.w()) if level == "v" else (pa_.e(), pb_.e())
        rows.append((coefs([(pa_, ka), (pb_, -kb)]), np.asarray(c0b - c0a) + np.zeros(st.n)))
    return rows


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


def group_pars(mech: Mechanism, st: State, g: Group) -> tuple[dict[int, RatePar], Joint,
                                                                list[RatePar]]:
    """Parametrisations of a closed-form group's bodies and its closure joint."""
    nb = len(mech.body_names)
    members = [mech.index[b] for b in g.bodies]
    pars: dict[int, RatePar] = {}
    for i in range(nb):
        if i not in members:
            pars[i] = RatePar(mech, st, None, i, None)
    if g.kind in ("RS", "PS"):
        jt, js = (mech.joint(n) for n in g.joints)
        b = members[0]
        pars[b] = RatePar(mech, st, jt, b, 0)
        return pars, js, [pars[b]]
    j1, j2, j3 = (mech.joint(n) for n in g.joints)
    b1, b2 = members
    pars[b1] = RatePar(mech, st, j1, b1, 0)
    pars[b2] = RatePar(mech, st, j3, b2, 1)
    return pars, j2, [pars[b1], pars[b2]]


def _closed_rates(mech: Mechanism, st: State, g: Group) -> None:
    pars, jc, unk = group_pars(mech, st, g)
    n_unk = len(unk)
    L = length_scale(mech)
    scale = L ** n_unk
    z = cramer(st, closure_rows(mech, st, jc, pars, n_unk, "v"), scale)
    for p, zi in zip(unk, z, strict=True):
        p.z = zi
    for p in unk:
        p.set_velocity()
    zd = cramer(st, closure_rows(mech, st, jc, pars, n_unk, "a"), scale)
    for p, zdi in zip(unk, zd, strict=True):
        p.set_acceleration(zdi)


def _linear_driver_rates(mech: Mechanism, st: State, g: Group, w1: Arr, e1: Arr) -> None:
    j = mech.joint(g.joints[0])
    b = mech.index[g.bodies[0]]
    sign = 1.0 if b == mech.index[j.b] else -1.0
    p = RatePar(mech, st, j, b, 0)
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
