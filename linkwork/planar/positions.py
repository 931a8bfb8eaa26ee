"""Positions of a planar mechanism, group by group, over all driver positions at once.

The groups come in the order of :mod:`linkwork.planar.structure`. The driver body and every
dyad (RRR, RRP, PRR, RPR, RPP, PPR, PRP) and one-body slot group (RS, PS) are solved in closed
form, as array expressions over the positions, with the branch chosen per group (see
``docs/planar.md`` for the branch definitions): each body's external joint gives a locus (circle
or line) of the point it shares with the other body, and the two loci intersect. Other groups are
solved by Newton iteration on the joints' constraint equations, continued from the previous
position. Results are written into a :class:`~linkwork.planar.state.State`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from linkwork.errors import StructureError
from linkwork.planar.model import Crank, Joint, Linear, Mechanism, Prismatic, Revolute
from linkwork.planar.state import Arr, State, Vec
from linkwork.planar.structure import Group

__all__ = ["assemble_jacobian", "constraint_rows", "group_rows", "length_scale",
           "solve_driver", "solve_dyad", "solve_newton", "solve_slot_group"]


# joint constraint rows: Jacobian blocks on body a and b, gamma (J qdd = gamma), residual
def _geom(mech: Mechanism, j: Joint) -> tuple[tuple[float, float], tuple[float, float], float]:
    return mech.joint_geometry(j)


def constraint_rows(mech: Mechanism, st: State, j: Joint, drv: Crank | Linear | None,
          rates: tuple[Arr, Arr] | None, need_gamma: bool = True) -> list[dict[str, Any]]:
    """Constraint rows of joint j (plus the driver row if drv is given).

    Each row: ``ja``, ``jb`` (3-tuples of arrays: d/dx, d/dy, d/dtheta), ``gam`` (acceleration
    right-hand side from velocity terms), ``rv``/``ra`` (driver's velocity/acceleration terms),
    ``res`` (residual, for Newton).
    """
    ia, ib = mech.index[j.a], mech.index[j.b]
    qa, pb, ang = _geom(mech, j)
    rows: list[dict[str, Any]] = []
    zero = np.zeros(st.n)
    one = zero + 1.0
    if isinstance(j, Revolute):
        wax, way = st.rot(ia, qa)
        wbx, wby = st.rot(ib, pb)
        wa2, wb2 = st.W[ia] ** 2, st.W[ib] ** 2
        res = (st.X[ia] + wax - st.X[ib] - wbx, st.Y[ia] + way - st.Y[ib] - wby)
        rows.append({"ja": (one, zero, -way), "jb": (-one, zero, wby),
                     "gam": wax * wa2 - wbx * wb2, "res": res[0]})
        rows.append({"ja": (zero, one, wax), "jb": (zero, -one, -wbx),
                     "gam": way * wa2 - wby * wb2, "res": res[1]})
        if drv is not None:
            rows.append({"ja": (zero, zero, -one), "jb": (zero, zero, one), "gam": zero,
                         "drive": True, "res": st.T[ib] - st.T[ia]})
        return rows
    # line joints
    wax, way = st.rot(ia, qa)
    wbx, wby = st.rot(ib, pb)
    ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
    nx, ny = -uy, ux
    dx = st.X[ib] + wbx - st.X[ia] - wax
    dy = st.Y[ib] + wby - st.Y[ia] - way

    def line_row(ex: Arr, ey: Arr) -> dict[str, Any]:
        # Phi = e . d with e rotating with body a; k x e = (-ey, ex)
        kex, key_ = -ey, ex
        th_a = kex * dx + key_ * dy - (ex * -way + ey * wax)
        th_b = ex * -wby + ey * wbx
        row: dict[str, Any] = {"ja": (-ex, -ey, th_a), "jb": (ex, ey, th_b),
                               "res": ex * dx + ey * dy}
        if need_gamma:
            wa, wb = st.W[ia], st.W[ib]
            ddx = st.VX[ib] - wb * wby - st.VX[ia] + wa * way
            ddy = st.VY[ib] + wb * wbx - st.VY[ia] - wa * wax
            quad = (-wa * wa * (ex * dx + ey * dy) + 2 * wa * (kex * ddx + key_ * ddy)
                    + ex * (-wb * wb * wbx + wa * wa * wax) + ey * (-wb * wb * wby + wa * wa * way))
            row["gam"] = -quad
        return row

    rows.append(line_row(nx, ny))
    if isinstance(j, Prismatic):
        rows.append({"ja": (zero, zero, -one), "jb": (zero, zero, one), "gam": zero,
                     "res": st.T[ib] - st.T[ia] - j.rel_angle})
        if drv is not None:
            r = line_row(ux, uy)
            r["drive"] = True
            rows.append(r)
    return rows


# ---------------------------------------------------------------------------------------------
# closed-form position solutions
def _fail(st: State, bad: Arr) -> None:
    st.bad |= bad


def _sqrt_checked(st: State, arg: Arr, scale: Arr | float) -> Arr:
    tol = 1e-12 * np.asarray(scale) ** 2
    bad = ~(arg >= -tol)
    _fail(st, bad)
    return np.sqrt(np.where(bad, np.nan, np.maximum(arg, 0.0)))


def _theta_of_prismatic(mech: Mechanism, st: State, j: Joint, body: int) -> Arr:
    """Angle of ``body`` fixed by prismatic joint j to an already-known body."""
    assert isinstance(j, Prismatic)
    ia, ib = mech.index[j.a], mech.index[j.b]
    return st.T[ia] + j.rel_angle if body == ib else st.T[ib] - j.rel_angle


def _locus(mech: Mechanism, st: State, j: Joint, body: int, p_int: tuple[float, float]
           ) -> tuple[str, Any]:
    """Locus of the point ``p_int`` of ``body`` allowed by its external joint j.

    Returns ("circle", (A, radius, p_ext)) with A the world centre, or ("line", (B0, u)) with
    the body's angle set in ``st``: points ``B0 + t u``, ``u`` the guide direction.
    """
    ia, ib = mech.index[j.a], mech.index[j.b]
    k = ia if body == ib else ib
    qa, pb, ang = _geom(mech, j)
    if isinstance(j, Revolute):
        p_ext = qa if body == ia else pb
        p_known = pb if body == ia else qa
        A = st.wpt(k, p_known)
        rad = float(np.hypot(p_int[0] - p_ext[0], p_int[1] - p_ext[1]))
        if rad == 0.0:
            raise StructureError(f"joint {j.name}: body {mech.body_names[body]} has its two "
                                 "joint centres at the same point; the dyad is not determined")
        return "circle", (A, rad, p_ext)
    st.set_angle(body, _theta_of_prismatic(mech, st, j, body))
    if body == ib:  # body is the slider on known guide k = a
        Q = st.wpt(k, qa)
        u = st.rot(k, (np.cos(ang), np.sin(ang)))
        off = st.rot(body, (p_int[0] - pb[0], p_int[1] - pb[1]))
        return "line", ((Q[0] + off[0], Q[1] + off[1]), u)
    # body is the guide; the known body's point X slides on it: B = X + A(pB - qa) - s u
    X = st.wpt(k, pb)
    u = st.rot(body, (np.cos(ang), np.sin(ang)))
    off = st.rot(body, (p_int[0] - qa[0], p_int[1] - qa[1]))
    return "line", ((X[0] + off[0], X[1] + off[1]), u)


def _finish_side(st: State, body: int, kind: str, data: Any, p_int: tuple[float, float],
                 B: Vec) -> None:
    if kind == "circle":
        A, rad, p_ext = data
        ex, ey = (B[0] - A[0]) / rad, (B[1] - A[1]) / rad
        phi0 = float(np.arctan2(p_int[1] - p_ext[1], p_int[0] - p_ext[0]))
        c0, s0 = np.cos(phi0), np.sin(phi0)
        th = np.arctan2(ey, ex)
        if phi0 != 0.0:
            st.set_angle(body, th - phi0, ex * c0 + ey * s0, ey * c0 - ex * s0)
        else:
            st.set_angle(body, th, ex, ey)
    st.place(body, p_int, B)


def _intersect(st: State, l1: tuple[str, Any], l2: tuple[str, Any], branch: int) -> Vec:
    k1, d1 = l1
    k2, d2 = l2
    if k1 == "circle" and k2 == "circle":
        (A, r1, _), (C, r2, _) = d1, d2
        ex, ey = C[0] - A[0], C[1] - A[1]
        dd = np.hypot(ex, ey)
        with np.errstate(invalid="ignore", divide="ignore"):
            a = (r1 * r1 - r2 * r2 + dd * dd) / (2 * dd)
            h = _sqrt_checked(st, r1 * r1 - a * a, r1)
            ux, uy = ex / dd, ey / dd
        return A[0] + a * ux - branch * h * uy, A[1] + a * uy + branch * h * ux
    if k1 == "line" and k2 == "line":
        (P, u), (Q, v) = d1, d2
        den = u[0] * v[1] - u[1] * v[0]
        bad = np.abs(den) < 1e-12
        _fail(st, bad)
        st.parallel |= bool(bad.any())
        with np.errstate(invalid="ignore", divide="ignore"):
            t = ((Q[0] - P[0]) * v[1] - (Q[1] - P[1]) * v[0]) / np.where(bad, np.nan, den)
        return P[0] + t * u[0], P[1] + t * u[1]
    (A, r, _), (B0, u) = (d1, d2) if k1 == "circle" else (d2, d1)
    wx, wy = A[0] - B0[0], A[1] - B0[1]
    t0 = wx * u[0] + wy * u[1]
    perp2 = wx * wx + wy * wy - t0 * t0
    h = _sqrt_checked(st, r * r - perp2, r)
    t = t0 + branch * h
    return B0[0] + t * u[0], B0[1] + t * u[1]


def solve_driver(mech: Mechanism, st: State, g: Group, q: Arr) -> None:
    j = mech.joint(g.joints[0])
    ia, ib = mech.index[j.a], mech.index[j.b]
    u = mech.index[g.bodies[0]]
    qa, pb, ang = _geom(mech, j)
    if isinstance(j, Revolute):
        if u == ib:
            st.set_angle(ib, st.T[ia] + q)
            st.place(ib, pb, st.wpt(ia, qa))
        else:
            st.set_angle(ia, st.T[ib] - q)
            st.place(ia, qa, st.wpt(ib, pb))
        return
    assert isinstance(j, Prismatic)
    if u == ib:
        st.set_angle(ib, st.T[ia] + j.rel_angle)
        Q = st.wpt(ia, qa)
        ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
        st.place(ib, pb, (Q[0] + q * ux, Q[1] + q * uy))
    else:
        st.set_angle(ia, st.T[ib] - j.rel_angle)
        P = st.wpt(ib, pb)
        ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
        st.place(ia, qa, (P[0] - q * ux, P[1] - q * uy))


def _line_condition(mech: Mechanism, st: State, j: Joint, body: int) -> tuple[Vec, Arr]:
    """For a body of known angle: the line constraint of joint j as ``n . r_body = c``."""
    ia, ib = mech.index[j.a], mech.index[j.b]
    qa, pb, ang = _geom(mech, j)
    ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
    nx, ny = -uy, ux
    if body == ia:  # body carries the line; known point X of b
        X = st.wpt(ib, pb)
        w = st.rot(ia, qa)
        return (nx, ny), nx * (X[0] - w[0]) + ny * (X[1] - w[1])
    Q = st.wpt(ia, qa)
    w = st.rot(ib, pb)
    return (nx, ny), nx * (Q[0] - w[0]) + ny * (Q[1] - w[1])


def _solve_two_lines(mech: Mechanism, st: State, body: int, j1: Joint, j2: Joint) -> None:
    (n1, c1), (n2, c2) = _line_condition(mech, st, j1, body), _line_condition(mech, st, j2, body)
    den = n1[0] * n2[1] - n1[1] * n2[0]
    bad = np.abs(den) < 1e-12
    _fail(st, bad)
    st.parallel |= bool(bad.any())
    den = np.where(bad, np.nan, den)
    st.X[body] = (c1 * n2[1] - c2 * n1[1]) / den
    st.Y[body] = (n1[0] * c2 - n2[0] * c1) / den


def _rotating_line(mech: Mechanism, st: State, g_body: int, A: Vec, a_loc: tuple[float, float],
                   line_q: tuple[float, float], ang: float, h: Arr | float, X: Vec,
                   branch: int) -> None:
    """Angle of body g pinned at A whose line (through q at angle ang) must pass through X.

    Solves ``(A(theta) n_loc) . (X - A) = h``; ``branch=+1`` makes the line's direction u
    point from A towards X (``u . (X - A) > 0``).
    """
    dx, dy = X[0] - A[0], X[1] - A[1]
    d = np.hypot(dx, dy)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = h / d
    bad = ~(np.abs(c) <= 1.0 + 1e-12)
    _fail(st, bad)
    acos = np.arccos(np.clip(np.where(bad, np.nan, c), -1.0, 1.0))
    th = np.arctan2(dy, dx) + branch * acos - ang - np.pi / 2
    st.set_angle(g_body, th)
    st.place(g_body, a_loc, A)


def solve_dyad(mech: Mechanism, st: State, g: Group, branch: int) -> None:
    j1, j2, j3 = (mech.joint(n) for n in g.joints)
    b1, b2 = (mech.index[b] for b in g.bodies)
    i2a, i2b = mech.index[j2.a], mech.index[j2.b]
    qa2, pb2, ang2 = _geom(mech, j2)
    if isinstance(j2, Revolute):
        p1 = qa2 if b1 == i2a else pb2
        p2 = pb2 if b2 == i2b else qa2
        L1 = _locus(mech, st, j1, b1, p1)
        L2 = _locus(mech, st, j3, b2, p2)
        B = _intersect(st, L1, L2, branch)
        _finish_side(st, b1, L1[0], L1[1], p1, B)
        _finish_side(st, b2, L2[0], L2[1], p2, B)
        return
    # internal prismatic: guide body ga, slider body sb
    assert isinstance(j2, Prismatic)
    ga, sb = i2a, i2b
    ext = {b1: j1, b2: j3}
    jg: Joint = ext[ga]
    js: Joint = ext[sb]
    if isinstance(jg, Revolute) and isinstance(js, Revolute):  # RPR
        A, a_loc = _pivot(mech, st, jg, ga)
        C, c_loc = _pivot(mech, st, js, sb)
        rel = j2.rel_angle
        cr, sr = np.cos(rel), np.sin(rel)
        px, py = pb2[0] - c_loc[0], pb2[1] - c_loc[1]
        rpx, rpy = cr * px - sr * py, sr * px + cr * py
        nlx, nly = -np.sin(ang2), np.cos(ang2)
        h = nlx * (qa2[0] - a_loc[0] - rpx) + nly * (qa2[1] - a_loc[1] - rpy)
        _rotating_line(mech, st, ga, A, a_loc, qa2, ang2, h, C, branch)
        st.set_angle(sb, st.T[ga] + rel)
        st.place(sb, c_loc, C)
        return
    # one or both external joints prismatic: both angles known
    if isinstance(jg, Prismatic) and isinstance(js, Prismatic):
        raise StructureError(f"dyad {g.bodies} with three prismatic pairs {g.joints} is not "
                             "determined (the sliding along the common direction is free)")
    jp: Joint
    jf: Joint
    if isinstance(jg, Prismatic):
        st.set_angle(ga, _theta_of_prismatic(mech, st, jg, ga))
        st.set_angle(sb, st.T[ga] + j2.rel_angle)
        pinned, free, jp, jf = sb, ga, js, jg
    else:  # jg is the revolute
        st.set_angle(sb, _theta_of_prismatic(mech, st, js, sb))
        st.set_angle(ga, st.T[sb] - j2.rel_angle)
        pinned, free, jp, jf = ga, sb, jg, js
    P, p_loc = _pivot(mech, st, jp, pinned)
    st.place(pinned, p_loc, P)
    _solve_two_lines(mech, st, free, jf, j2)


def _pivot(mech: Mechanism, st: State, j: Joint, body: int) -> tuple[Vec, tuple[float, float]]:
    """World centre of revolute j (from its known side) and its local point on ``body``."""
    ia = mech.index[j.a]
    qa, pb, _ = _geom(mech, j)
    if body == ia:
        return st.wpt(mech.index[j.b], pb), qa
    return st.wpt(ia, qa), pb


def solve_slot_group(mech: Mechanism, st: State, g: Group, branch: int) -> None:
    jt, js = (mech.joint(n) for n in g.joints)
    b = mech.index[g.bodies[0]]
    ia, ib = mech.index[js.a], mech.index[js.b]
    qa, pb, ang = _geom(mech, js)
    if isinstance(jt, Prismatic):
        st.set_angle(b, _theta_of_prismatic(mech, st, jt, b))
        _solve_two_lines(mech, st, b, jt, js)
        return
    A, a_loc = _pivot(mech, st, jt, b)
    if b == ia:  # the body carries the slot; known pin X
        X = st.wpt(ib, pb)
        nlx, nly = -np.sin(ang), np.cos(ang)
        h = nlx * (qa[0] - a_loc[0]) + nly * (qa[1] - a_loc[1])
        _rotating_line(mech, st, b, A, a_loc, qa, ang, h, X, branch)
        return
    # the body carries the pin; slot in known body a
    rad = float(np.hypot(pb[0] - a_loc[0], pb[1] - a_loc[1]))
    if rad == 0.0:  # as for a dyad whose two joint centres coincide
        raise StructureError(f"joint {js.name}: the pin of body {g.bodies[0]} is at its pivot "
                             f"({jt.name}), so the slot cannot turn it; its angle is not "
                             "determined")
    Q = st.wpt(ia, qa)
    u = st.rot(ia, (np.cos(ang), np.sin(ang)))
    P = _intersect(st, ("circle", (A, rad, a_loc)), ("line", (Q, u)), branch)
    _finish_side(st, b, "circle", (A, rad, a_loc), pb, P)


# ---------------------------------------------------------------------------------------------
# Newton for general groups
def group_rows(mech: Mechanism, st: State, g: Group, need_gamma: bool
                ) -> list[tuple[int, int, dict[str, Any]]]:
    out = []
    for name in g.joints:
        j = mech.joint(name)
        drv = mech.driver if name == mech.driver.joint else None
        for r in constraint_rows(mech, st, j, drv, None, need_gamma):
            out.append((mech.index[j.a], mech.index[j.b], r))
    return out


def assemble_jacobian(mech: Mechanism, st: State, g: Group,
                      rows: list[tuple[int, int, dict[str, Any]]]
                      ) -> tuple[Arr, list[tuple[int, int, dict[str, Any]]]]:
    cols = {mech.index[b]: 3 * k for k, b in enumerate(g.bodies)}
    m = 3 * len(g.bodies)
    J = np.zeros((st.n, m, m))
    for r, (ia, ib, row) in enumerate(rows):
        for body, key in ((ia, "ja"), (ib, "jb")):
            if body in cols:
                c = cols[body]
                for k in range(3):
                    J[:, r, c + k] += row[key][k]
    return J, rows



def _newton_state(mech: Mechanism, st: State, members: list[int], pos: Arr) -> State:
    """A state holding the known bodies at positions ``pos`` (group members to be set)."""
    sub = State(len(mech.body_names), pos.shape[0])
    for bi in range(len(mech.body_names)):
        if bi not in members:
            sub.X[bi], sub.Y[bi] = st.X[bi][pos], st.Y[bi][pos]
            sub.set_angle(bi, st.T[bi][pos], st.C[bi][pos], st.S[bi][pos])
    return sub


def _newton_iterate(mech: Mechanism, sub: State, g: Group, members: list[int], q: Arr,
                    z: Arr, tol: float, max_iter: int) -> tuple[Arr, Arr]:
    """Newton on all positions of ``sub`` at once from ``z`` (n, k, 3); returns (z, converged)."""
    n = sub.n
    done = np.zeros(n, dtype=bool)
    z = z.copy()
    for _ in range(max_iter):
        for k, bi in enumerate(members):
            sub.X[bi], sub.Y[bi] = z[:, k, 0], z[:, k, 1]
            sub.set_angle(bi, z[:, k, 2])
        rows = group_rows(mech, sub, g, need_gamma=False)
        J, _ = assemble_jacobian(mech, sub, g, rows)
        res = np.stack([r["res"] - (q if r.get("drive") else 0.0) for _, _, r in rows], axis=1)
        with np.errstate(invalid="ignore"):
            done = np.max(np.abs(res), axis=1) < tol
        todo = ~done & np.isfinite(res).all(axis=1)
        if not todo.any():
            break
        with np.errstate(all="ignore"):
            det = np.linalg.det(J[todo])
            ok = np.abs(det) > 1e-300
            dz = np.full((int(todo.sum()), res.shape[1]), np.nan)
            if ok.any():
                dz[ok] = np.linalg.solve(J[todo][ok], -res[todo][ok][..., None])[..., 0]
        z[todo] = z[todo] + dz.reshape(-1, *z.shape[1:])
    return z, done


def solve_newton(mech: Mechanism, st: State, g: Group, q: Arr, tol: float = 1e-12,
                  max_iter: int = 30) -> None:
    """Newton for a general group, continued over the positions.

    Up to 100 positions are solved one after the other, each from the previous solution (the
    first from the bodies' ``guess`` poses). For longer arrays a coarse subset of about 100
    positions is continued that way, then every position is solved at once (batched Newton)
    starting from the coarse solution just before it; positions that still fail are retried
    one by one from their predecessor.
    """
    members = [mech.index[b] for b in g.bodies]
    n = st.n
    nm = len(members)
    tol = tol * length_scale(mech)
    z0 = np.empty((nm, 3))
    for k, bname in enumerate(g.bodies):
        gs = mech.body(bname).guess
        z0[k] = gs if gs is not None else (0.0, 0.0, 0.0)

    def sequential(pos: Arr, start: Arr) -> tuple[Arr, Arr]:
        out = np.full((pos.shape[0], nm, 3), np.nan)
        okk = np.zeros(pos.shape[0], dtype=bool)
        z = start
        for t, i in enumerate(pos):
            sub = _newton_state(mech, st, members, np.array([i]))
            zi, conv = _newton_iterate(mech, sub, g, members, q[i:i + 1], z[None], tol,
                                       max_iter)
            if conv[0]:
                out[t], okk[t] = zi[0], True
                z = zi[0]
        return out, okk

    if n <= 100:
        sol, good = sequential(np.arange(n), z0)
    else:
        idx = np.unique(np.r_[np.arange(0, n, int(np.ceil(n / 100))), n - 1])
        zc, okc = sequential(idx, z0)
        idx, zc = idx[okc], zc[okc]
        if idx.size == 0:
            sol, good = np.full((n, nm, 3), np.nan), np.zeros(n, dtype=bool)
        else:
            j = np.clip(np.searchsorted(idx, np.arange(n), side="right") - 1, 0, None)
            sub = _newton_state(mech, st, members, np.arange(n))
            sol, good = _newton_iterate(mech, sub, g, members, q, zc[j], tol, max_iter)
            for i in np.flatnonzero(~good):
                if i > 0 and good[i - 1]:
                    zi, conv = sequential(np.array([i]), sol[i - 1])
                    if conv[0]:
                        sol[i], good[i] = zi[0], True
    sol[~good] = np.nan
    st.bad |= ~good
    for k, bi in enumerate(members):
        st.X[bi], st.Y[bi] = sol[:, k, 0], sol[:, k, 1]
        st.set_angle(bi, sol[:, k, 2])


def length_scale(mech: Mechanism) -> float:
    pts = [abs(c) for b in (mech.frame, *mech.bodies) for p in b.points.values() for c in p]
    return max(max(pts, default=1.0), 1e-3)
