"""Independent references for the planar engine and the closed-form four-bar: the loop equations
solved by a Newton iteration of our own, rates by complex-step and finite differences in time,
and Newton-Euler free-body equations of every body written out per mechanism.  ``_close``:
tolerance 1e-6 relative (``RTOL``) with a floor of the quantity's scale; ``_angle_close``
compares angles modulo 2 pi; both record the largest deviation per quantity in ``DEV``."""

from __future__ import annotations

import math

import numpy as np

from linkwork.planar import (
    BodyTorque,
    Crank,
    GearPair,
    PointForce,
    Prismatic,
    Revolute,
    inverse_dynamics,
    kinematics,
)

RTOL = 1e-6


DEV: dict[str, float] = {}


def _close(actual, expected, scale, name):
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    err = np.abs(actual - expected)
    lim = RTOL * np.abs(expected) + 1e-9 * scale
    rel = float(np.max(err / np.maximum(np.abs(expected), 1e-9 * scale)))
    DEV[name] = max(DEV.get(name, 0.0), rel)
    assert np.all(err <= lim), (name, actual, expected, rel)


def _angle_close(actual, expected, name, tol=1e-9):
    d = np.remainder(np.asarray(actual) - np.asarray(expected) + np.pi, 2 * np.pi) - np.pi
    DEV[name] = max(DEV.get(name, 0.0), float(np.max(np.abs(d))))
    assert np.all(np.abs(d) <= tol), (name, actual, expected)


def _newton(residual, q0, t, iters=60):
    """Root of residual(q, t) near real q0; t may be complex (complex step)."""
    qr = np.asarray(q0, dtype=float)
    n = len(qr)
    for _ in range(iters):
        r0 = np.real(residual(qr, t.real))
        jac = np.empty((len(r0), n))
        for k in range(n):
            dq = np.zeros(n)
            dq[k] = 1e-7 * max(1.0, abs(qr[k]))
            jac[:, k] = (np.real(residual(qr + dq, t.real)) - r0) / dq[k]
        step = np.linalg.lstsq(jac, r0, rcond=None)[0]
        qr = qr - step
        if np.all(np.abs(step) <= 1e-15 * (1 + np.abs(qr))):
            break
    assert np.max(np.abs(residual(qr, t.real))) < 1e-12
    q = qr.astype(complex)
    pinv = np.linalg.pinv(jac)
    for _ in range(iters):
        q = q - pinv @ residual(q, t)
    return q


def _motion(position, hc=1e-30, hd=1e-3):
    def vel(t):
        return np.imag(position(t + 1j * hc)) / hc
    x = np.real(position(0j))
    v = vel(0.0)
    a = (-vel(2 * hd) + 8 * vel(hd) - 8 * vel(-hd) + vel(-2 * hd)) / (12 * hd)
    return x, v, a


def _rot(th, p):
    c, s = np.cos(th), np.sin(th)
    return np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])


def gear_geometry(mech, j):
    """A gear pair as written: (carrier, centre of a on a, centre of b on b, r_a, r_b, s) with
    the centres the pivots on the carrier and the radii from the teeth and the centres'
    distance (or as given)."""
    carrier = j.carrier or mech.frame.name
    on_gear, on_carrier = [], []
    for gear in (j.a, j.b):
        piv = next(p for p in mech.joints if isinstance(p, Revolute) and {p.a, p.b} ==
                   {gear, carrier})
        pa, pb, _ = mech.joint_geometry(piv)
        on_gear.append(pa if piv.a == gear else pb)
        on_carrier.append(pb if piv.a == gear else pa)
    d = math.dist(on_carrier[0], on_carrier[1])
    s = -1.0 if j.internal else 1.0
    if j.teeth is not None:
        za, zb = j.teeth
        ra = d * za / (zb - za if j.internal else za + zb)
        rb = ra * zb / za
    else:
        ra, rb = j.radii
    return carrier, on_gear[0], on_gear[1], ra, rb, s


def _pose_reference(mech, kin, k, w1, e1, step=2e-3):
    """Poses and their rates of all moving bodies at position k, from the raw constraints.

    ``w1, e1``: the drivers' speeds and accelerations (a number for one driver, one per driver
    for several); the drivers move as phi_d(t) = phi_d + w_d t + e_d t^2 / 2."""
    names = mech.body_names
    idx = {n: i for i, n in enumerate(names)}
    nb = len(names) - 1
    drivers = mech.drivers
    phi0 = np.atleast_2d(kin.phi1)[:, k].astype(float)
    w1v = np.broadcast_to(np.asarray(w1, dtype=float), (len(drivers),))
    e1v = np.broadcast_to(np.asarray(e1, dtype=float), (len(drivers),))

    def pose(q, i):
        if i == 0:
            return 0.0, 0.0, 0.0
        return q[3 * i - 3], q[3 * i - 2], q[3 * i - 1]

    def world(q, i, p):
        x, y, th = pose(q, i)
        r = _rot(th, p)
        return np.array([x + r[0], y + r[1]])

    def residual(q, t):
        out = []
        for j in mech.joints:
            ia, ib = idx[j.a], idx[j.b]
            qa, pb, ang = mech.joint_geometry(j)
            if isinstance(j, GearPair):
                carrier, _, _, ra, rb, s = gear_geometry(mech, j)
                tc = pose(q, idx[carrier])[2]
                out.append(pose(q, ib)[2] - tc + s * ra / rb * (pose(q, ia)[2] - tc)
                           - j.offset)
            elif isinstance(j, Revolute):
                out.extend(world(q, ia, qa) - world(q, ib, pb))
            else:
                tha = pose(q, ia)[2]
                nvec = _rot(tha, (-math.sin(ang), math.cos(ang)))
                dvec = world(q, ib, pb) - world(q, ia, qa)
                out.append(dvec[0] * nvec[0] + dvec[1] * nvec[1])
                if isinstance(j, Prismatic):
                    out.append(pose(q, ib)[2] - tha - j.rel_angle)
        for d, p0, w, e in zip(drivers, phi0, w1v, e1v, strict=True):
            drv = mech.joint(d.joint)
            phi = p0 + w * t + 0.5 * e * t * t
            if isinstance(d, Crank):
                out.append(pose(q, idx[drv.b])[2] - pose(q, idx[drv.a])[2] - phi)
            else:  # linear driver: slide coordinate u . (P_b - Q_a)
                qa, pb, ang = mech.joint_geometry(drv)
                u = _rot(pose(q, idx[drv.a])[2], (math.cos(ang), math.sin(ang)))
                dvec = world(q, idx[drv.b], pb) - world(q, idx[drv.a], qa)
                out.append(dvec[0] * u[0] + dvec[1] * u[1] - phi)
        return np.array(out)

    q0 = np.concatenate([[kin.x[i, k], kin.y[i, k], kin.theta[i, k]] for i in range(1, nb + 1)])

    def position(t):
        return _newton(residual, q0, np.asarray(t, dtype=complex))

    return _motion(position, hd=step / max(float(np.max(np.abs(w1v))), 1.0))


def _newton_euler(mech, q, v, acc, gravity, loads, about=(0.0, 0.0)):
    """Reactions (by a on b), driving torque Q, shaking force/moment, kinetic energy."""
    names = mech.body_names
    idx = {n: i for i, n in enumerate(names)}
    nb = len(names) - 1
    g = np.asarray(gravity, dtype=float)

    def pose(i):
        return (0.0, 0.0, 0.0) if i == 0 else tuple(q[3 * i - 3:3 * i])

    def world(i, p):
        x, y, th = pose(i)
        r = _rot(th, p)
        return np.array([x + r[0], y + r[1]])

    cols = []          # (joint index, kind, application point, direction or None)
    separating = []    # gear pairs: (column, joint index, P, e, tan alpha)
    for ji, j in enumerate(mech.joints):
        if isinstance(j, GearPair):  # the tangential tooth force at the pitch point
            _, ca, cb, ra, _rb, s = gear_geometry(mech, j)
            Oa, Ob = world(idx[j.a], ca), world(idx[j.b], cb)
            e = s * (Ob - Oa) / np.hypot(*(Ob - Oa))
            P = Oa + ra * e
            separating.append((len(cols), ji, P, e, math.tan(j.pressure_angle)))
            cols.append((ji, "n", P, np.array([-e[1], e[0]])))
            continue
        _qa, pb, ang = mech.joint_geometry(j)
        P = world(idx[j.b], pb)
        if isinstance(j, Revolute):
            cols.append((ji, "fx", P, np.array([1.0, 0.0])))
            cols.append((ji, "fy", P, np.array([0.0, 1.0])))
        else:
            nvec = _rot(pose(idx[j.a])[2], (-math.sin(ang), math.cos(ang)))
            cols.append((ji, "n", P, nvec))
            if isinstance(j, Prismatic):
                cols.append((ji, "mz", P, None))
    for di in range(len(mech.drivers)):
        cols.append((-1 - di, "Q", None, None))
    A = np.zeros((3 * nb, len(cols)))
    rhs = np.zeros(3 * nb)

    def add(i, col, f, P, m=0.0):
        if i == 0:
            return
        r = slice(3 * i - 3, 3 * i)
        A[r, col] += [f[0], f[1], P[0] * f[1] - P[1] * f[0] + m]

    for c, (ji, kind, P, dvec) in enumerate(cols):
        if kind == "Q":
            d = mech.drivers[-1 - ji]
            drv = mech.joint(d.joint)
        if kind == "Q" and isinstance(d, Crank):
            add(idx[drv.b], c, (0.0, 0.0), (0.0, 0.0), 1.0)
            add(idx[drv.a], c, (0.0, 0.0), (0.0, 0.0), -1.0)
            continue
        if kind == "Q":  # linear driver: force on b along the guide, at the slider point
            _qa, pb, ang = mech.joint_geometry(drv)
            u = _rot(pose(idx[drv.a])[2], (math.cos(ang), math.sin(ang)))
            P = world(idx[drv.b], pb)
            add(idx[drv.b], c, u, P)
            add(idx[drv.a], c, -u, P)
            continue
        j = mech.joints[ji]
        if kind == "mz":
            add(idx[j.b], c, (0.0, 0.0), (0.0, 0.0), 1.0)
            add(idx[j.a], c, (0.0, 0.0), (0.0, 0.0), -1.0)
        else:
            add(idx[j.b], c, dvec, P)
            add(idx[j.a], c, -dvec, P)
    T = 0.0
    com = {}
    for b in mech.bodies:
        i = idx[b.name]
        x, y, th = pose(i)
        r = _rot(th, b.com)
        C = np.array([x + r[0], y + r[1]])
        w, e = v[3 * i - 1], acc[3 * i - 1]
        vc = v[3 * i - 3:3 * i - 1] + w * np.array([-r[1], r[0]])
        ac = acc[3 * i - 3:3 * i - 1] + e * np.array([-r[1], r[0]]) - w * w * r
        com[b.name] = (C, ac)
        T += 0.5 * b.mass * vc @ vc + 0.5 * b.inertia * w * w
        # m a_c = sum F + m g ; r_c x m a_c + I e = sum M_O (+ weight)
        Fw = b.mass * g
        rhs[3 * i - 3:3 * i] += [b.mass * ac[0] - Fw[0], b.mass * ac[1] - Fw[1],
                                 C[0] * b.mass * ac[1] - C[1] * b.mass * ac[0] + b.inertia * e
                                 - (C[0] * Fw[1] - C[1] * Fw[0])]
    for ld in loads:
        i = idx[ld.body]
        if isinstance(ld, PointForce):
            p = mech.body(ld.body).point(ld.point) if isinstance(ld.point, str) else ld.point
            P = world(i, p)
            rhs[3 * i - 3:3 * i] -= [ld.fx, ld.fy, P[0] * ld.fy - P[1] * ld.fx]
        else:
            rhs[3 * i - 1] -= ld.mz
    sol, *_ = np.linalg.lstsq(A, rhs, rcond=None)
    assert np.linalg.matrix_rank(A) == A.shape[1] == A.shape[0]
    if separating:  # the separating force |F_t| tan(alpha) along e, on b (and -e on a) at P
        for c, ji, P, e, tan_a in separating:
            j = mech.joints[ji]
            fr = abs(sol[c]) * tan_a * e
            for body, f in ((idx[j.b], fr), (idx[j.a], -fr)):
                if body:
                    rhs[3 * body - 3:3 * body] -= [f[0], f[1], P[0] * f[1] - P[1] * f[0]]
        tangential = {ji: sol[c] for c, ji, *_ in separating}
        sol, *_ = np.linalg.lstsq(A, rhs, rcond=None)
        for c, ji, *_ in separating:  # no work at the pitch point: F_t unchanged
            assert abs(sol[c] - tangential[ji]) <= 1e-9 * (1 + abs(tangential[ji]))
    assert np.max(np.abs(A @ sol - rhs)) < 1e-9 * (1 + np.max(np.abs(rhs)))
    nj = len(mech.joints)
    fx, fy, mz = np.zeros(nj), np.zeros(nj), np.zeros(nj)
    for c, (ji, kind, _P, dvec) in enumerate(cols):
        if kind == "fx":
            fx[ji] = sol[c]
        elif kind == "fy":
            fy[ji] = sol[c]
        elif kind == "n":
            fx[ji] += sol[c] * dvec[0]
            fy[ji] += sol[c] * dvec[1]
        elif kind == "mz":
            mz[ji] = sol[c]
    for c, ji, _P, e, tan_a in separating:
        fx[ji] += abs(sol[c]) * tan_a * e[0]
        fy[ji] += abs(sol[c]) * tan_a * e[1]
    nd = len(mech.drivers)
    Qs = sol[len(cols) - nd:]
    Q = Qs[0] if nd == 1 else Qs
    # force and moment of the moving bodies on the frame (about 'about'), motor included
    sf = np.zeros(2)
    sm = 0.0
    fr = mech.frame.name
    for ji, j in enumerate(mech.joints):
        if fr not in (j.a, j.b):
            continue
        sgn = -1.0 if j.a == fr else 1.0
        P = (next(Pg for _c, jg, Pg, *_ in separating if jg == ji) if isinstance(j, GearPair)
             else world(idx[j.b], mech.joint_geometry(j)[1]))
        f = sgn * np.array([fx[ji], fy[ji]])
        sf += f
        sm += (P[0] - about[0]) * f[1] - (P[1] - about[1]) * f[0] + sgn * mz[ji]
    for d, Qd in zip(mech.drivers, Qs, strict=True):
        drv = mech.joint(d.joint)
        if isinstance(d, Crank):
            if fr == drv.a:
                sm -= Qd
            elif fr == drv.b:
                sm += Qd
        elif fr in (drv.a, drv.b):  # the actuator's reaction on the frame
            sgn = -1.0 if drv.a == fr else 1.0
            _qa, pb, ang = mech.joint_geometry(drv)
            u = _rot(pose(idx[drv.a])[2], (math.cos(ang), math.sin(ang)))
            P = world(idx[drv.b], pb)
            f = sgn * Qd * u
            sf += f
            sm += (P[0] - about[0]) * f[1] - (P[1] - about[1]) * f[0]
    return dict(fx=fx, fy=fy, mz=mz, Q=Q, sf=sf, sm=sm, T=T)


def _check_engine(mech, phi, w1, e1, gravity, loads, about=(0.0, 0.0), label="", step=2e-3):
    kin = kinematics(mech, phi, w1, e1)
    dyn = inverse_dynamics(kin, gravity=gravity, loads=loads, about=about)
    L = max(max(abs(v) for p in b.points.values() for v in p) for b in mech.bodies) + 1e-3
    n = np.shape(phi)[-1]
    for k in range(n):
        q, v, acc = _pose_reference(mech, kin, k, w1, e1, step)
        nb = len(mech.bodies)
        for i in range(1, nb + 1):
            _close(kin.x[i, k], q[3 * i - 3], L, label + "engine x,y")
            _close(kin.y[i, k], q[3 * i - 2], L, label + "engine x,y")
            _angle_close(kin.theta[i, k], q[3 * i - 1], label + "engine theta")
            W = max(float(np.max(np.abs(w1))), 1.0) * 5
            _close(kin.vx[i, k], v[3 * i - 3], L * W, label + "engine v")
            _close(kin.vy[i, k], v[3 * i - 2], L * W, label + "engine v")
            _close(kin.omega[i, k], v[3 * i - 1], W, label + "engine omega")
            E = float(np.max(np.abs(e1)))
            _close(kin.ax[i, k], acc[3 * i - 3], L * (W * W + E), label + "engine a")
            _close(kin.ay[i, k], acc[3 * i - 2], L * (W * W + E), label + "engine a")
            _close(kin.eps[i, k], acc[3 * i - 1], W * W + E, label + "engine eps")
        ref = _newton_euler(mech, q, v, acc, gravity, [
            PointForce(ld.body, ld.point, float(np.broadcast_to(ld.fx, (n,))[k]),
                       float(np.broadcast_to(ld.fy, (n,))[k]))
            if isinstance(ld, PointForce) else
            BodyTorque(ld.body, float(np.broadcast_to(ld.mz, (n,))[k])) for ld in loads],
            about)
        F = max(np.max(np.abs(ref["fx"])), np.max(np.abs(ref["fy"])), 1.0)
        _close(dyn.fx[:, k], ref["fx"], F, label + "reactions")
        _close(dyn.fy[:, k], ref["fy"], F, label + "reactions")
        _close(dyn.mz[:, k], ref["mz"], F * L, label + "reactions mz")
        _close(dyn.Q[..., k], ref["Q"], F * L, label + "Q")
        _close(dyn.shaking_fx[k], ref["sf"][0], F, label + "shaking force")
        _close(dyn.shaking_fy[k], ref["sf"][1], F, label + "shaking force")
        _close(dyn.shaking_m[k], ref["sm"], F * L, label + "shaking moment")
        _close(dyn.T[k], ref["T"], 1e-3, label + "kinetic energy")
    return kin, dyn


PHI7 = np.array([0.05, 0.9, 1.7, 2.6, 3.5, 4.6, 5.9])


def _fb_full():
    return np.linspace(0, 2 * np.pi, 361)


def energy_rate(mech, kin, g):
    """dT/dt = sum m v_C.a_C + I w eps and the power of gravity sum m g.v_C, from the
    kinematics alone."""
    dT = np.zeros(kin.n)
    p_g = np.zeros(kin.n)
    for b in mech.bodies:
        c = kin.point(b.name, "com")
        i = mech.index[b.name]
        dT += b.mass * (c.vx * c.ax + c.vy * c.ay) + b.inertia * kin.omega[i] * kin.eps[i]
        p_g += b.mass * (g[0] * c.vx + g[1] * c.vy)
    return dT, p_g
