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
from linkwork.planar.joints import ResolvedJoint, design_length, row_entries
from linkwork.planar.state import Arr, State, Vec
from linkwork.planar.structure import CYLINDER, Plan, PlanGroup, length_scale

__all__ = ["assemble_jacobian", "group_rows", "length_scale", "solve_cylinder", "solve_driver",
           "solve_dyad", "solve_gear", "solve_group", "solve_newton", "solve_slot_group"]

#: rows of a group with the indices of their joint's bodies a and b
Rows = list[tuple[int, int, dict[str, Any]]]


# ---------------------------------------------------------------------------------------------
# closed-form position solutions
def _fail(st: State, bad: Arr) -> None:
    st.bad |= bad


def _sqrt_checked(st: State, arg: Arr, scale: Arr | float) -> Arr:
    tol = 1e-12 * np.asarray(scale) ** 2
    bad = ~(arg >= -tol)
    _fail(st, bad)
    return np.sqrt(np.where(bad, np.nan, np.maximum(arg, 0.0)))


def _finish_side(st: State, body: int, kind: str, data: Any, p_int: tuple[float, float],
                 B: Vec) -> None:
    if kind == "circle":
        A, rad, p_ext = data
        ex, ey = (B[0] - A[0]) / rad, (B[1] - A[1]) / rad
        phi0 = np.arctan2(p_int[1] - p_ext[1], p_int[0] - p_ext[0])
        if phi0.ndim == 0:
            phi0 = float(phi0)
        c0, s0 = np.cos(phi0), np.sin(phi0)
        th = np.arctan2(ey, ex)
        if isinstance(phi0, np.ndarray) or phi0 != 0.0:
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


def solve_driver(st: State, g: PlanGroup, q: Arr) -> None:
    """Pose of the driven body for the driver coordinates ``q`` (n_drivers, n)."""
    r = g.joints[0]
    r.joint.place_driven(st, r, g.bodies[0], q[r.drive_index])


def _solve_two_lines(st: State, body: int, r1: ResolvedJoint, r2: ResolvedJoint) -> None:
    """Origin of ``body`` (angle known) from two line joints."""
    (n1, c1), (n2, c2) = r1.joint.line_condition(st, r1, body), r2.joint.line_condition(
        st, r2, body)
    den = n1[0] * n2[1] - n1[1] * n2[0]
    bad = np.abs(den) < 1e-12
    _fail(st, bad)
    st.parallel |= bool(bad.any())
    den = np.where(bad, np.nan, den)
    st.X[body] = (c1 * n2[1] - c2 * n1[1]) / den
    st.Y[body] = (n1[0] * c2 - n2[0] * c1) / den


def _rotating_line(st: State, g_body: int, A: Vec, a_loc: tuple[float, float],
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


def solve_dyad(st: State, g: PlanGroup, branch: int, body_names: tuple[str, ...]) -> None:
    """A dyad (J1, J2, J3): each body's external joint gives a locus of its point of J2; a
    revolute J2 intersects the two loci, a prismatic J2 turns or slides a line."""
    r1, r2, r3 = g.joints
    j2 = r2.joint
    b1, b2 = g.bodies
    qa2, pb2, ang2 = r2.qa, r2.pb, r2.ang
    if j2.is_pivot:
        p1 = qa2 if b1 == r2.ia else pb2
        p2 = pb2 if b2 == r2.ib else qa2
        L1 = r1.joint.locus(st, r1, b1, p1, body_names[b1])
        L2 = r3.joint.locus(st, r3, b2, p2, body_names[b2])
        B = _intersect(st, L1, L2, branch)
        _finish_side(st, b1, L1[0], L1[1], p1, B)
        _finish_side(st, b2, L2[0], L2[1], p2, B)
        return
    # internal prismatic (the angle kept): guide body ga, slider body sb
    ga, sb = r2.ia, r2.ib
    ext = {b1: r1, b2: r3}
    rg, rs = ext[ga], ext[sb]
    jg, js = rg.joint, rs.joint
    if jg.is_pivot and js.is_pivot:  # RPR
        A, a_loc = jg.pivot(st, rg, ga)
        C, c_loc = js.pivot(st, rs, sb)
        rel = j2.rel_angle  # type: ignore[attr-defined]  # the internal joint keeps the angle
        cr, sr = np.cos(rel), np.sin(rel)
        px, py = pb2[0] - c_loc[0], pb2[1] - c_loc[1]
        rpx, rpy = cr * px - sr * py, sr * px + cr * py
        nlx, nly = -np.sin(ang2), np.cos(ang2)
        h = nlx * (qa2[0] - a_loc[0] - rpx) + nly * (qa2[1] - a_loc[1] - rpy)
        _rotating_line(st, ga, A, a_loc, qa2, ang2, h, C, branch)
        st.set_angle(sb, j2.angle_of(st, r2, sb))
        st.place(sb, c_loc, C)
        return
    # one or both external joints prismatic: both angles known
    if jg.keeps_angle and js.keeps_angle:
        raise StructureError(f"dyad {g.group.bodies} with three prismatic pairs "
                             f"{g.group.joints} is not determined (the sliding along the "
                             "common direction is free)")
    rp: ResolvedJoint
    rf: ResolvedJoint
    if jg.keeps_angle:
        st.set_angle(ga, jg.angle_of(st, rg, ga))
        st.set_angle(sb, j2.angle_of(st, r2, sb))
        pinned, free, rp, rf = sb, ga, rs, rg
    else:  # jg is the pivot
        st.set_angle(sb, js.angle_of(st, rs, sb))
        st.set_angle(ga, j2.angle_of(st, r2, ga))
        pinned, free, rp, rf = ga, sb, rg, rs
    P, p_loc = rp.joint.pivot(st, rp, pinned)
    st.place(pinned, p_loc, P)
    _solve_two_lines(st, free, rf, r2)


def solve_slot_group(st: State, g: PlanGroup, branch: int) -> None:
    """One body with a revolute or prismatic joint (jt) and a pin-in-slot (js)."""
    rt, rs = g.joints
    jt = rt.joint
    b = g.bodies[0]
    ia, ib = rs.ia, rs.ib
    qa, pb, ang = rs.qa, rs.pb, rs.ang
    if jt.keeps_angle:
        st.set_angle(b, jt.angle_of(st, rt, b))
        _solve_two_lines(st, b, rt, rs)
        return
    A, a_loc = jt.pivot(st, rt, b)
    if b == ia:  # the body carries the slot; known pin X
        X = st.wpt(ib, pb)
        nlx, nly = -np.sin(ang), np.cos(ang)
        h = nlx * (qa[0] - a_loc[0]) + nly * (qa[1] - a_loc[1])
        _rotating_line(st, b, A, a_loc, qa, ang, h, X, branch)
        return
    # the body carries the pin; slot in known body a
    rad = design_length(pb[0] - a_loc[0], pb[1] - a_loc[1])
    if np.any(rad == 0.0):  # as for a dyad whose two joint centres coincide
        raise StructureError(f"joint {rs.joint.name}: the pin of body {g.group.bodies[0]} is at "
                             f"its pivot ({jt.name}), so the slot cannot turn it; its angle is "
                             "not determined")
    Q = st.wpt(ia, qa)
    u = st.rot(ia, rs.u_loc)
    P = _intersect(st, ("circle", (A, rad, a_loc)), ("line", (Q, u)), branch)
    _finish_side(st, b, "circle", (A, rad, a_loc), pb, P)


def solve_group(plan: Plan, st: State, g: PlanGroup, branch: int, q: Arr) -> None:
    """Poses of the bodies of group ``g`` (the groups before it solved) on ``branch``; ``q``
    the driver positions, shape (n_drivers, n)."""
    if g.kind == "driver":
        solve_driver(st, g, q)
    elif g.kind in ("RS", "PS"):
        solve_slot_group(st, g, branch)
    elif g.kind == "newton":
        solve_newton(plan, st, g, q)
    elif g.kind in CYLINDER:
        solve_cylinder(st, g, branch, q, plan.body_names)
    elif g.kind == "RG":
        solve_gear(st, g)
    else:
        solve_dyad(st, g, branch, plan.body_names)


def solve_gear(st: State, g: PlanGroup) -> None:
    """A gear turning on its carrier (revolute ``rt``) against a known gear (pair ``rg``): its
    angle relative to the carrier from ``theta_b' + s k theta_a' = offset``, its centre on the
    pivot."""
    rt, rg = g.joints
    body = g.bodies[0]
    ra, rb, s, off = rg.params
    k = s * ra / rb
    tc = st.T[rg.ic]
    if body == rg.ib:
        st.set_angle(body, tc + off - k * (st.T[rg.ia] - tc))
    else:
        st.set_angle(body, tc + (off - (st.T[rg.ib] - tc)) / k)
    A, a_loc = rt.joint.pivot(st, rt, body)
    st.place(body, a_loc, A)


def solve_cylinder(st: State, g: PlanGroup, branch: int, q: Arr,
                   body_names: tuple[str, ...]) -> None:
    """A driven cylinder with the body X it moves (``cyl-RRR``, ``cyl-RRP``), in closed form.

    For the given slide s of the cylinder's prismatic pair, its two bodies form one rigid
    "virtual link" from the pivot A (hinged to a known body) to the pivot C (on X): the vector
    from A to C in the frame of the pair's body a is ``qa + s u + R(rel) (p - pb)`` for a point
    p of body b (or p itself on body a). C is the intersection of the circle about A with
    radius |AC| and X's locus (a circle about its pivot, or a line along its guide), on the
    branch of the dyad with the virtual link as first body (C on the left of A -> X's pivot;
    further along the guide).
    """
    ra, rd, rc, rx = g.joints
    c1, c2 = rd.ia, rd.ib
    x = next(b for b in g.bodies if b not in (c1, c2))
    s = q[rd.drive_index]
    rel = rd.joint.rel_angle  # type: ignore[attr-defined]  # a prismatic pair's
    cr, sr = np.cos(rel), np.sin(rel)
    ux, uy = rd.u_loc
    ox, oy = rd.qa[0] + s * ux, rd.qa[1] + s * uy  # body b's point pb, in body a's frame

    def in_c1(body: int, p: tuple[float, float]) -> Vec:
        if body == c1:
            return np.full_like(s, p[0]), np.full_like(s, p[1])
        dx, dy = p[0] - rd.pb[0], p[1] - rd.pb[1]
        return ox + cr * dx - sr * dy, oy + sr * dx + cr * dy

    ca = ra.ia if ra.ia in (c1, c2) else ra.ib  # the cylinder body hinged at A
    a_loc = ra.qa if ca == ra.ia else ra.pb
    A, _ = ra.joint.pivot(st, ra, ca)
    cc = rc.ia if rc.ia in (c1, c2) else rc.ib  # the cylinder body hinged at C
    c_loc = rc.qa if cc == rc.ia else rc.pb
    x_loc = rc.pb if cc == rc.ia else rc.qa
    A1 = in_c1(ca, a_loc)
    C1 = in_c1(cc, c_loc)
    vx, vy = C1[0] - A1[0], C1[1] - A1[1]
    ell = np.hypot(vx, vy)
    L2 = rx.joint.locus(st, rx, x, x_loc, body_names[x])
    C = _intersect(st, ("circle", (A, ell, a_loc)), L2, branch)
    _finish_side(st, x, L2[0], L2[1], x_loc, C)
    th1 = np.arctan2(C[1] - A[1], C[0] - A[0]) - np.arctan2(vy, vx)
    st.set_angle(c1, th1)
    c, sn = st.C[c1], st.S[c1]
    st.X[c1] = A[0] - (c * A1[0] - sn * A1[1])
    st.Y[c1] = A[1] - (sn * A1[0] + c * A1[1])
    st.set_angle(c2, th1 + rel)
    st.X[c2] = st.X[c1] + c * (ox - (cr * rd.pb[0] - sr * rd.pb[1])) - sn * (
        oy - (sr * rd.pb[0] + cr * rd.pb[1]))
    st.Y[c2] = st.Y[c1] + sn * (ox - (cr * rd.pb[0] - sr * rd.pb[1])) + c * (
        oy - (sr * rd.pb[0] + cr * rd.pb[1]))


# ---------------------------------------------------------------------------------------------
# Newton for general groups
def group_rows(st: State, g: PlanGroup, need_gamma: bool) -> Rows:
    """The constraint rows of all joints of a group (the driver's row included)."""
    out = []
    for r in g.joints:
        for row in r.joint.constraint_rows(st, r, need_gamma):
            out.append((r.ia, r.ib, row))
    return out


def assemble_jacobian(st: State, g: PlanGroup, rows: Rows) -> tuple[Arr, Rows]:
    """The group's Jacobian (n, m, m) in its bodies' coordinates (x, y, theta each)."""
    cols = {b: 3 * k for k, b in enumerate(g.bodies)}
    m = 3 * len(g.bodies)
    J = np.zeros((st.n, m, m))
    for r, (ia, ib, row) in enumerate(rows):
        for body, coef in row_entries(ia, ib, row):
            if body in cols:
                c = cols[body]
                for k in range(3):
                    J[:, r, c + k] += coef[k]
    return J, rows


def _newton_state(nb: int, st: State, members: list[int], pos: Arr) -> State:
    """A state holding the known bodies at positions ``pos`` (group members to be set)."""
    sub = State(nb, pos.shape[0])
    for bi in range(nb):
        if bi not in members:
            sub.X[bi], sub.Y[bi] = st.X[bi][pos], st.Y[bi][pos]
            sub.set_angle(bi, st.T[bi][pos], st.C[bi][pos], st.S[bi][pos])
    return sub


def _newton_iterate(sub: State, g: PlanGroup, members: list[int], q: Arr,
                    z: Arr, tol: float, max_iter: int) -> tuple[Arr, Arr]:
    """Newton on all positions of ``sub`` at once from ``z`` (n, k, 3); returns (z, converged)."""
    n = sub.n
    done = np.zeros(n, dtype=bool)
    z = z.copy()
    for _ in range(max_iter):
        for k, bi in enumerate(members):
            sub.X[bi], sub.Y[bi] = z[:, k, 0], z[:, k, 1]
            sub.set_angle(bi, z[:, k, 2])
        rows = group_rows(sub, g, need_gamma=False)
        J, _ = assemble_jacobian(sub, g, rows)
        res = np.stack([r["res"] - (q[r["drive_index"]] if r.get("drive") else 0.0)
                        for _, _, r in rows], axis=1)
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


def solve_newton(plan: Plan, st: State, g: PlanGroup, q: Arr, tol: float = 1e-12,
                 max_iter: int = 30) -> None:
    """Newton for a general group, continued over the positions.

    Up to 100 positions are solved one after the other, each from the previous solution (the
    first from the bodies' ``guess`` poses). For longer arrays a coarse subset of about 100
    positions is continued that way, then every position is solved at once (batched Newton)
    starting from the coarse solution just before it; positions that still fail are retried
    one by one from their predecessor.
    """
    members = list(g.bodies)
    n = st.n
    nm = len(members)
    nb = plan.nb
    tol = tol * plan.length_scale
    z0 = np.empty((nm, 3))
    for k, gs in enumerate(g.guesses):
        z0[k] = gs if gs is not None else (0.0, 0.0, 0.0)

    def sequential(pos: Arr, start: Arr) -> tuple[Arr, Arr]:
        out = np.full((pos.shape[0], nm, 3), np.nan)
        okk = np.zeros(pos.shape[0], dtype=bool)
        z = start
        for t, i in enumerate(pos):
            sub = _newton_state(nb, st, members, np.array([i]))
            zi, conv = _newton_iterate(sub, g, members, q[:, i:i + 1], z[None], tol, max_iter)
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
            sub = _newton_state(nb, st, members, np.arange(n))
            sol, good = _newton_iterate(sub, g, members, q, zc[j], tol, max_iter)
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

