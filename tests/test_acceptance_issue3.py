"""Acceptance check of issue 3 (planar engine, four-bar, kinetostatics) as a checker does it.

Reference values are computed here by independent routes:

* four-bar: the bare loop equation ``a e^{j t2} + b e^{j t3} - c e^{j t4} - d = 0`` solved by
  Newton from several starts, the assembly chosen by the side of B relative to the directed line
  A -> O4 (the issue's definition of ``branch``);
* any engine mechanism: every body pose ``(x, y, theta)`` solved at once from the raw joint
  constraints (revolute: coincident points; prismatic: point on line + fixed relative angle;
  pin-in-slot: point on line; driver: ``theta_b - theta_a = phi1(t)``), by Newton started from
  the engine's pose, with the residual checked;
* velocities: complex-step derivative of those Newton solves in time; accelerations: 4th-order
  central differences of the complex-step velocities (truncation ~1e-12), with
  ``phi1(t) = phi10 + omega1 t + eps1 t^2 / 2`` (eps1 != 0);
* reactions: Newton-Euler for every body (force and moment balance about the world origin),
  unknowns = joint reaction components and the driving torque, solved with numpy.linalg.lstsq.

Tolerance 1e-6 relative with an absolute floor of 1e-9 of the quantity's scale.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from linkwork.errors import AssemblyError, LinkworkError, ParameterError, StructureError
from linkwork.models import fourbar as fb
from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    Mechanism,
    PinInSlot,
    PointForce,
    Prismatic,
    Revolute,
    bar,
    inverse_dynamics,
    kinematics,
)
from linkwork.planar.model import crank_slider as engine_crank_slider
from linkwork.planar.model import fourbar as engine_fourbar

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


# ------------------------------------------------------------------------------------------
# four-bar in closed form
# ------------------------------------------------------------------------------------------

def _fourbar_solutions(a, b, c, d, t2):
    """All assemblies (theta3, theta4) at real t2 from the loop equation."""
    def res(q, t):
        return np.array([a * np.cos(t2) + b * np.cos(q[0]) - c * np.cos(q[1]) - d,
                         a * np.sin(t2) + b * np.sin(q[0]) - c * np.sin(q[1])])
    sols = []
    for s3 in np.linspace(-np.pi, np.pi, 8, endpoint=False):
        for s4 in np.linspace(-np.pi, np.pi, 8, endpoint=False):
            q = np.array([s3, s4])
            for _ in range(80):
                r = res(q, 0)
                J = np.array([[-b * np.sin(q[0]), c * np.sin(q[1])],
                              [b * np.cos(q[0]), -c * np.cos(q[1])]])
                if abs(np.linalg.det(J)) < 1e-14:
                    break
                q = q - np.linalg.solve(J, r)
            if np.max(np.abs(res(q, 0))) < 1e-13:
                q = np.remainder(q + np.pi, 2 * np.pi) - np.pi
                if not any(np.allclose(q, s, atol=1e-8) for s in sols):
                    sols.append(q)
    return sols


def _fourbar_reference(a, b, c, d, w2, e2, branch, t20, pq=(0.0, 0.0), step=2e-3):
    """theta3, theta4, points and their rates; branch = side of B w.r.t. A -> O4."""
    sols = _fourbar_solutions(a, b, c, d, t20)
    A = np.array([a * math.cos(t20), a * math.sin(t20)])
    chosen = None
    for q in sols:
        B = A + b * np.array([math.cos(q[0]), math.sin(q[0])])
        u = np.array([d, 0.0]) - A
        cross = u[0] * (B - A)[1] - u[1] * (B - A)[0]
        if np.sign(cross) == branch:
            chosen = q
    assert chosen is not None, "no assembly on the requested branch"

    def res(q, t):
        t2 = t20 + w2 * t + 0.5 * e2 * t * t
        return np.array([a * np.cos(t2) + b * np.cos(q[0]) - c * np.cos(q[1]) - d,
                         a * np.sin(t2) + b * np.sin(q[0]) - c * np.sin(q[1])])

    def position(t):
        q = _newton(res, chosen, np.asarray(t, dtype=complex))
        t2 = t20 + w2 * t + 0.5 * e2 * t * t
        xa, ya = a * np.cos(t2), a * np.sin(t2)
        xb, yb = xa + b * np.cos(q[0]), ya + b * np.sin(q[0])
        p, qq = pq
        xp = xa + p * np.cos(q[0]) - qq * np.sin(q[0])
        yp = ya + p * np.sin(q[0]) + qq * np.cos(q[0])
        # a rocker point (0.07, 0.03) in the rocker's frame (origin O4, x along O4 -> B)
        xr = d + 0.07 * np.cos(q[1]) - 0.03 * np.sin(q[1])
        yr = 0.07 * np.sin(q[1]) + 0.03 * np.cos(q[1])
        return np.array([q[0], q[1], xa, ya, xb, yb, xp, yp, xr, yr])

    x, v, acc = _motion(position, hd=step / max(abs(w2), 1.0))
    return x, v, acc


FOURBARS = [  # a, b, c, d, omega2, alpha2, angles
    (0.1, 0.3, 0.2, 0.3, 10.0, 0.0, None),                     # paper 001 (crank-rocker)
    (0.1, 0.3, 0.2, 0.3, -7.0, 25.0, None),
    (0.3, 0.25, 0.28, 0.1, 5.0, -12.0, None),                  # double-crank
    (0.2, 0.2, 0.2, 0.45, 3.0, 4.0, "triple"),                 # non-Grashof triple rocker
]


def _angles_for(a, b, c, d, kind):
    if kind == "triple":
        # assembles for cos t2 >= ((a^2 + d^2) - (b + c)^2) / (2 a d); toggles at +-t
        tg = math.acos((a * a + d * d - (b + c) ** 2) / (2 * a * d))
        return np.array([-tg + 1e-3, -0.8, -0.3, 0.0, 0.4, 0.9, tg - 1e-3])
    lim = fb.limit_positions(a, b, c, d)
    return np.array([lim.theta2_rocker_extended + 1e-4, lim.theta2_rocker_folded - 1e-4,
                     0.2, 1.3, 2.5, 3.8, 5.2]) if not math.isnan(lim.theta2_rocker_extended) \
        else np.array([0.0, 0.7, 1.5, 2.5, 3.3, 4.4, 5.6])


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("a,b,c,d,w2,e2,kind", FOURBARS)
def test_fourbar_against_loop_equation(a, b, c, d, w2, e2, kind, branch):
    angles = _angles_for(a, b, c, d, kind)
    pq = (0.12, -0.05)
    res = fb.fourbar(angles, a, b, c, d, w2, e2, branch, coupler_point=pq)
    L = max(a, b, c, d)
    W = max(abs(w2), 1.0) * 3
    for k, t2 in enumerate(angles):
        step = 1e-5 if kind == "triple" else 2e-3
        x, v, acc = _fourbar_reference(a, b, c, d, w2, e2, branch, float(t2), pq, step)
        _angle_close(res.theta3[k], x[0], "theta3")
        _angle_close(res.theta4[k], x[1], "theta4")
        _close(res.omega3[k], v[0], W, "omega3")
        _close(res.omega4[k], v[1], W, "omega4")
        _close(res.alpha3[k], acc[0], W * W + abs(e2), "alpha3")
        _close(res.alpha4[k], acc[1], W * W + abs(e2), "alpha4")
        for name, i in (("xA", 2), ("yA", 3), ("xB", 4), ("yB", 5), ("xP", 6), ("yP", 7)):
            _close(getattr(res, name)[k], x[i], L, "points")
        for link, (p_, q_), i in (("coupler", pq, 6), ("rocker", (0.07, 0.03), 8)):
            px, py, pvx, pvy, pax, pay = (np.asarray(z)[k] for z in res.point(link, p_, q_))
            _close([px, py], x[i:i + 2], L, "point()")
            _close([pvx, pvy], v[i:i + 2], L * W, "point() velocity")
            _close([pax, pay], acc[i:i + 2], L * (W * W + abs(e2)), "point() acceleration")
        # transmission angle: angle A-B-O4 between coupler and rocker at B
        BA = x[2:4] - x[4:6]
        BO = np.array([d, 0.0]) - x[4:6]
        mu = math.acos(np.dot(BA, BO) / np.linalg.norm(BA) / np.linalg.norm(BO))
        _close(fb.transmission_angle(t2, a, b, c, d), mu, 1.0, "transmission_angle")
        _close(fb.transmission_angle(t2, a, b, c, d, acute=True), min(mu, np.pi - mu), 1.0,
               "transmission_angle")
    # theta3/theta4 in (-pi, pi] as documented
    assert np.all(res.theta3 > -np.pi) and np.all(res.theta3 <= np.pi)


def _rotates(a, b, c, d, which):
    """Brute force: can link 'a' (crank) or 'c' (rocker) turn a full circle?"""
    t = np.linspace(0, 2 * np.pi, 20001)
    if which == "crank":
        f = np.sqrt(a * a + d * d - 2 * a * d * np.cos(t))
        return bool(np.all((f <= b + c + 1e-12) & (f >= abs(b - c) - 1e-12)))
    f = np.sqrt(c * c + d * d - 2 * c * d * np.cos(t))
    return bool(np.all((f <= a + b + 1e-12) & (f >= abs(a - b) - 1e-12)))


@pytest.mark.parametrize("abcd,motion", [
    ((0.1, 0.3, 0.2, 0.3), "crank-rocker"),
    ((0.3, 0.25, 0.28, 0.1), "double-crank"),
    ((0.28, 0.1, 0.22, 0.25), "double-rocker"),
    ((0.22, 0.25, 0.15, 0.3), "rocker-crank"),
    ((0.2, 0.2, 0.2, 0.45), "triple-rocker"),
    ((0.1, 0.3, 0.2, 0.2), "change-point"),
])
def test_grashof_type_against_brute_force(abcd, motion):
    g = fb.grashof(*abcd)
    assert g.motion == motion
    assert bool(g.crank_rotates) == _rotates(*abcd, "crank")
    assert bool(g.rocker_rotates) == _rotates(*abcd, "rocker")
    s, l = min(abcd), max(abcd)
    rest = sorted(abcd)[1:3]
    expected_class = "I" if s + l < sum(rest) - 1e-12 else ("II" if s + l > sum(rest) + 1e-12
                                                          else "III")
    assert g.grashof_class == expected_class


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("abcd", [(0.1, 0.3, 0.2, 0.3), (0.05, 0.2, 0.12, 0.18)])
def test_fourbar_limit_positions_by_search(abcd, branch):
    a, b, c, d = abcd
    lim = fb.limit_positions(a, b, c, d, branch)

    def t4(t2):
        return float(fb.fourbar(t2, a, b, c, d, branch=branch).theta4)
    grid = np.linspace(0, 2 * np.pi, 721)
    vals = np.unwrap([t4(t) for t in grid])
    found = []
    for sgn in (1.0, -1.0):
        i = int(np.argmax(sgn * vals))
        ref0 = vals[i]
        r = minimize_scalar(
            lambda t, sgn=sgn, ref0=ref0: -sgn * (ref0 + math.remainder(t4(t) - ref0, 2 * np.pi)),
            bounds=(grid[i] - 0.02, grid[i] + 0.02), method="bounded", options={"xatol": 1e-11})
        found.append((r.x, t4(r.x)))
    # which extreme is 'extended': |O2 B| = a + b there
    for t2_, t4_ in found:
        B = np.array([d + c * math.cos(t4_), c * math.sin(t4_)])
        if abs(np.linalg.norm(B) - (a + b)) < 1e-6:
            ext = (t2_, t4_)
        else:
            assert abs(np.linalg.norm(B) - abs(a - b)) < 1e-6
            fold = (t2_, t4_)
    _angle_close(lim.theta2_rocker_extended, ext[0], "limit theta2", tol=1e-5)
    _angle_close(lim.theta4_rocker_extended, ext[1], "limit theta4", tol=1e-9)
    _angle_close(lim.theta2_rocker_folded, fold[0], "limit theta2", tol=1e-5)
    _angle_close(lim.theta4_rocker_folded, fold[1], "limit theta4", tol=1e-9)
    swing = abs(math.remainder(ext[1] - fold[1], 2 * np.pi))
    _close(lim.rocker_swing, swing, 1.0, "rocker_swing")
    fwd = (ext[0] - fold[0]) % (2 * np.pi)
    _close(lim.time_ratio, fwd / (2 * np.pi - fwd), 1.0, "time_ratio")


def test_fourbar_input_toggles_by_root_finding():
    a, b, c, d = 0.2, 0.2, 0.2, 0.45
    lim = fb.limit_positions(a, b, c, d)

    def f(t, L):
        return math.hypot(a * math.cos(t) - d, a * math.sin(t)) - L
    t_ext = brentq(f, 0.0, np.pi, args=(b + c,), xtol=1e-15)
    _close(lim.theta2_toggle_extended, t_ext, 1.0, "toggle")
    assert math.isnan(lim.theta2_toggle_folded)  # |b - c| = 0 is never reached (d - a > 0)
    ext = fb.transmission_angle_extremes(a, b, c, d)
    t = np.linspace(-t_ext, t_ext, 20001)
    mus = fb.transmission_angle(t, a, b, c, d)
    _close(ext.mu_min, np.nanmin(mus), 1.0, "transmission extremes")
    _close(ext.mu_max, np.nanmax(mus), 1.0, "transmission extremes")


# ------------------------------------------------------------------------------------------
# Newton-Euler reference for any engine mechanism (revolute, prismatic, pin-in-slot)
# ------------------------------------------------------------------------------------------

def _rot(th, p):
    c, s = np.cos(th), np.sin(th)
    return np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])


def _pose_reference(mech, kin, k, w1, e1, step=2e-3):
    """Poses and their rates of all moving bodies at position k, from the raw constraints."""
    names = mech.body_names
    idx = {n: i for i, n in enumerate(names)}
    nb = len(names) - 1
    phi0 = float(kin.phi1[k])
    drv = mech.joint(mech.driver.joint)

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
            if isinstance(j, Revolute):
                out.extend(world(q, ia, qa) - world(q, ib, pb))
            else:
                tha = pose(q, ia)[2]
                nvec = _rot(tha, (-math.sin(ang), math.cos(ang)))
                dvec = world(q, ib, pb) - world(q, ia, qa)
                out.append(dvec[0] * nvec[0] + dvec[1] * nvec[1])
                if isinstance(j, Prismatic):
                    out.append(pose(q, ib)[2] - tha - j.rel_angle)
        phi = phi0 + w1 * t + 0.5 * e1 * t * t
        if isinstance(mech.driver, Crank):
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

    return _motion(position, hd=step / max(abs(w1), 1.0))


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
    for ji, j in enumerate(mech.joints):
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
    cols.append((-1, "Q", None, None))
    A = np.zeros((3 * nb, len(cols)))
    rhs = np.zeros(3 * nb)

    def add(i, col, f, P, m=0.0):
        if i == 0:
            return
        r = slice(3 * i - 3, 3 * i)
        A[r, col] += [f[0], f[1], P[0] * f[1] - P[1] * f[0] + m]

    drv = mech.joint(mech.driver.joint)
    for c, (ji, kind, P, dvec) in enumerate(cols):
        if kind == "Q" and isinstance(mech.driver, Crank):
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
    Q = sol[-1]
    # force and moment of the moving bodies on the frame (about 'about'), motor included
    sf = np.zeros(2)
    sm = 0.0
    fr = mech.frame.name
    for ji, j in enumerate(mech.joints):
        if fr not in (j.a, j.b):
            continue
        sgn = -1.0 if j.a == fr else 1.0
        P = world(idx[j.b], mech.joint_geometry(j)[1])
        f = sgn * np.array([fx[ji], fy[ji]])
        sf += f
        sm += (P[0] - about[0]) * f[1] - (P[1] - about[1]) * f[0] + sgn * mz[ji]
    if isinstance(mech.driver, Crank):
        if fr == drv.a:
            sm -= Q
        elif fr == drv.b:
            sm += Q
    elif fr in (drv.a, drv.b):  # the actuator's reaction on the frame
        sgn = -1.0 if drv.a == fr else 1.0
        _qa, pb, ang = mech.joint_geometry(drv)
        u = _rot(pose(idx[drv.a])[2], (math.cos(ang), math.sin(ang)))
        P = world(idx[drv.b], pb)
        f = sgn * Q * u
        sf += f
        sm += (P[0] - about[0]) * f[1] - (P[1] - about[1]) * f[0]
    return dict(fx=fx, fy=fy, mz=mz, Q=Q, sf=sf, sm=sm, T=T)


def _check_engine(mech, phi, w1, e1, gravity, loads, about=(0.0, 0.0), label="", step=2e-3):
    kin = kinematics(mech, phi, w1, e1)
    dyn = inverse_dynamics(kin, gravity=gravity, loads=loads, about=about)
    L = max(max(abs(v) for p in b.points.values() for v in p) for b in mech.bodies) + 1e-3
    for k in range(len(phi)):
        q, v, acc = _pose_reference(mech, kin, k, w1, e1, step)
        nb = len(mech.bodies)
        for i in range(1, nb + 1):
            _close(kin.x[i, k], q[3 * i - 3], L, label + "engine x,y")
            _close(kin.y[i, k], q[3 * i - 2], L, label + "engine x,y")
            _angle_close(kin.theta[i, k], q[3 * i - 1], label + "engine theta")
            W = max(abs(w1), 1.0) * 5
            _close(kin.vx[i, k], v[3 * i - 3], L * W, label + "engine v")
            _close(kin.vy[i, k], v[3 * i - 2], L * W, label + "engine v")
            _close(kin.omega[i, k], v[3 * i - 1], W, label + "engine omega")
            _close(kin.ax[i, k], acc[3 * i - 3], L * (W * W + abs(e1)), label + "engine a")
            _close(kin.ay[i, k], acc[3 * i - 2], L * (W * W + abs(e1)), label + "engine a")
            _close(kin.eps[i, k], acc[3 * i - 1], W * W + abs(e1), label + "engine eps")
        ref = _newton_euler(mech, q, v, acc, gravity, [
            PointForce(ld.body, ld.point, float(np.broadcast_to(ld.fx, phi.shape)[k]),
                       float(np.broadcast_to(ld.fy, phi.shape)[k]))
            if isinstance(ld, PointForce) else
            BodyTorque(ld.body, float(np.broadcast_to(ld.mz, phi.shape)[k])) for ld in loads],
            about)
        F = max(np.max(np.abs(ref["fx"])), np.max(np.abs(ref["fy"])), 1.0)
        _close(dyn.fx[:, k], ref["fx"], F, label + "reactions")
        _close(dyn.fy[:, k], ref["fy"], F, label + "reactions")
        _close(dyn.mz[:, k], ref["mz"], F * L, label + "reactions mz")
        _close(dyn.Q[k], ref["Q"], F * L, label + "Q")
        _close(dyn.shaking_fx[k], ref["sf"][0], F, label + "shaking force")
        _close(dyn.shaking_fy[k], ref["sf"][1], F, label + "shaking force")
        _close(dyn.shaking_m[k], ref["sm"], F * L, label + "shaking moment")
        _close(dyn.T[k], ref["T"], 1e-3, label + "kinetic energy")
    return kin, dyn


PHI7 = np.array([0.05, 0.9, 1.7, 2.6, 3.5, 4.6, 5.9])


@pytest.mark.parametrize("branch", [1, -1])
def test_engine_fourbar_inverse_dynamics_gravity_loads_eps(branch):
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    mech = engine_fourbar(a, b, c, d, masses=(1.0, 3.0, 2.0), inertias=(0.004, 0.03, 0.01),
                          coms=((0.04, 0.01), 0.12, (0.09, -0.02)), branch=branch)
    mech = Mechanism(mech.frame, (
        mech.bodies[0], Body("coupler", {"A": (0, 0), "B": (b, 0), "P": (0.1, 0.05)}, mass=3.0,
                             com=(0.12, 0.0), inertia=0.03), mech.bodies[2]),
        mech.joints, mech.driver, mech.branches)
    loads = [PointForce("coupler", "P", fx=15.0, fy=-40.0), PointForce("rocker", "B", fx=-8.0,
                                                                       fy=5.0),
             BodyTorque("rocker", 3.5), BodyTorque("crank", -1.2)]
    _check_engine(mech, PHI7, 8.0, 30.0, (0.0, -9.81), loads, about=(0.05, -0.02),
                  label="fourbar ")


def test_engine_crank_slider_with_press_force():
    mech = engine_crank_slider(0.05, 0.2, 0.03, guide_angle=math.radians(90), masses=(2, 3, 10),
                               branch=1)
    load = np.where((PHI7 > 1) & (PHI7 < 3), -2000.0, 0.0)
    loads = [PointForce("slider", "B", fx=0.0, fy=load), BodyTorque("rod", 2.0)]
    _check_engine(mech, PHI7, 12.0, -40.0, (0.0, -9.81), loads, label="crank-slider ")


def test_engine_sine_press_pin_in_slot():
    alpha = math.radians(60)
    frame = Body("frame", {"A": (0, 0)})
    crank = Body("crank", {"A": (0, 0), "B": (0.05, 0)}, mass=6, com=(0.01, 0), inertia=0.02)
    ram = Body("ram", {"S": (0, 0)}, mass=25, com=(-0.15, 0.01), inertia=0.5)
    joints = (Revolute("A", "frame", "crank"),
              Prismatic("guide", "frame", "ram", angle=0.0, through=(0, 0), point="S"),
              PinInSlot("slot", "ram", "crank", angle=alpha, through="S", point="B"))
    mech = Mechanism(frame, (crank, ram), joints, Crank("A"))
    loads = [PointForce("ram", "S", fx=8000.0, fy=0.0), BodyTorque("ram", 4.0)]
    _check_engine(mech, PHI7, 12.566, 50.0, (-9.81, 0.0), loads, label="sine press ")


def test_engine_sixbar_example_file():
    from linkwork.files import load
    doc = load("examples/loom_sixbar.toml")
    mech = doc.mechanism()
    phi = PHI7
    _check_engine(mech, phi, 9.0, 20.0, (0.0, -9.81), [BodyTorque(mech.bodies[-1].name, 5.0)],
                  label="six-bar ")


def test_engine_class_three_group_by_newton():
    """A crank driving a class-III Assur group (triad: ternary body c and three binary links,
    two of them pivoted in the frame), solved by the engine's Newton continuation.  The triad
    locks near phi1 = 0.164 rad (checked with an independent continuation), so 7 positions in
    [-0.5, 0.12] rad; a finer reference step near that singular position."""
    P, R = np.array([0.7, -0.1]), np.array([0.3, 0.6])
    A, X = np.array([0.1, 0.0]), np.array([0.35, 0.25])
    Y, Z = np.array([0.55, 0.2]), np.array([0.45, 0.45])

    def link(name, s, e, S, E):
        d = E - S
        ln = float(np.hypot(*d))
        return Body(name, {s: (0.0, 0.0), e: (ln, 0.0)}, mass=1.0, com=(ln / 2, 0.0),
                    inertia=0.01, guess=(S[0], S[1], math.atan2(d[1], d[0])))
    frame = Body("frame", {"O": (0.0, 0.0), "P": tuple(P), "R": tuple(R)})
    bodies = (bar("crank", "O", "A", 0.1, mass=1.0), link("l1", "A", "X", A, X),
              link("l2", "P", "Y", P, Y), link("l3", "R", "Z", R, Z),
              Body("c", {"X": (0, 0), "Y": tuple(Y - X), "Z": tuple(Z - X)}, mass=2.0,
                   com=(0.1, 0.05), inertia=0.02, guess=(X[0], X[1], 0.0)))
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "l1"),
              Revolute("X", "l1", "c"), Revolute("Y", "c", "l2"), Revolute("P", "frame", "l2"),
              Revolute("Z", "c", "l3"), Revolute("R", "frame", "l3"))
    mech = Mechanism(frame, bodies, joints, Crank("O"))
    assert [g.cls for g in mech.structure.groups] == [1, 3]
    loads = [PointForce("c", "Z", fx=10.0, fy=3.0), BodyTorque("l2", 1.0)]
    _check_engine(mech, np.linspace(-0.5, 0.12, 7), 5.0, 10.0, (0.0, -9.81), loads,
                  label="class III ", step=1e-4)


# ------------------------------------------------------------------------------------------
# four-bar kinetostatics in closed form against Newton-Euler
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("branch", [1, -1])
def test_fourbar_kinetostatics_against_newton_euler(branch):
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    w2, e2 = -9.0, 35.0
    masses = (1.0, 3.0, 2.0)
    inert = (0.004, 0.03, 0.01)
    coms = ((0.04, 0.01), (0.12, -0.03), (0.09, 0.02))
    forces = ((3.0, -2.0), (15.0, -40.0), (-8.0, 5.0))
    fpts = ((0.1, 0.0), (0.2, 0.05), (0.2, 0.0))
    moments = (-1.2, 0.7, 3.5)
    g = (0.0, -9.81)
    res = fb.fourbar_kinetostatics(PHI7, a, b, c, d, w2, e2, branch, mass=masses,
                                   inertia=inert, com=coms, gravity=g, force=forces,
                                   force_point=fpts, moment=moments)
    for k, t2 in enumerate(PHI7):
        x, v, acc = _fourbar_reference(a, b, c, d, w2, e2, branch, float(t2))
        th = (float(t2), x[0], x[1])
        om = (w2, v[0], v[1])
        al = (e2, acc[0], acc[1])
        origin = [np.zeros(2), x[2:4], np.array([d, 0.0])]
        aorig = [np.zeros(2), acc[2:4], np.zeros(2)]
        # unknowns: R_O(2), R_A(2), R_B(2), R_C(2), Q: by frame on crank at O2, crank on
        # coupler at A, coupler on rocker at B, frame on rocker at O4; Q motor on crank
        M = np.zeros((9, 9))
        rhs = np.zeros(9)
        O2, A, B, O4 = np.zeros(2), x[2:4], x[4:6], np.array([d, 0.0])

        def put(body, col, f, P, m=0.0, M=M):
            M[3 * body:3 * body + 3, col] += [f[0], f[1], P[0] * f[1] - P[1] * f[0] + m]
        ex, ey = np.array([1.0, 0.0]), np.array([0.0, 1.0])
        for base, P, on, by in ((0, O2, 0, None), (2, A, 1, 0), (4, B, 2, 1), (6, O4, 2, None)):
            for col, e_ in ((base, ex), (base + 1, ey)):
                put(on, col, e_, P)
                if by is not None:
                    put(by, col, -e_, P)
        put(0, 8, (0, 0), (0, 0), 1.0)
        for i in range(3):
            p = coms[i]
            r = _rot(th[i], p)
            C = origin[i] + r
            ac = aorig[i] + al[i] * np.array([-r[1], r[0]]) - om[i] ** 2 * r
            m = masses[i]
            W = m * np.array(g)
            fp = origin[i] + _rot(th[i], fpts[i])
            Fe = np.array(forces[i])
            rhs[3 * i:3 * i + 3] = [m * ac[0] - W[0] - Fe[0], m * ac[1] - W[1] - Fe[1],
                                    C[0] * m * ac[1] - C[1] * m * ac[0] + inert[i] * al[i]
                                    - (C[0] * W[1] - C[1] * W[0])
                                    - (fp[0] * Fe[1] - fp[1] * Fe[0]) - moments[i]]
        sol = np.linalg.lstsq(M, rhs, rcond=None)[0]
        assert np.max(np.abs(M @ sol - rhs)) < 1e-9 * np.max(np.abs(rhs))
        F = np.max(np.abs(sol[:8]))
        for name, val in zip(("R_Ox", "R_Oy", "R_Ax", "R_Ay", "R_Bx", "R_By", "R_Cx", "R_Cy"),
                             sol[:8], strict=True):
            _close(getattr(res, name)[k], val, F, "fourbar_kinetostatics R")
        _close(res.Q[k], sol[8], F * d, "fourbar_kinetostatics Q")
        # shaking: force of the moving links on the frame, moment about O2
        sf = -(sol[0:2] + sol[6:8])
        sm = -sol[8] - (O4[0] * sol[7] - O4[1] * sol[6])
        _close(res.shaking_force_x[k], sf[0], F, "fourbar_kinetostatics shaking")
        _close(res.shaking_force_y[k], sf[1], F, "fourbar_kinetostatics shaking")
        _close(res.shaking_moment[k], sm, F * d, "fourbar_kinetostatics shaking")


# ------------------------------------------------------------------------------------------
# failure policy of the functions and the engine
# ------------------------------------------------------------------------------------------

def _fb_full():
    return np.linspace(0, 2 * np.pi, 361)


@pytest.mark.parametrize("call,words", [
    (lambda: fb.fourbar(_fb_full(), 0.2, 0.2, 0.2, 0.45), ["assembl", "deg"]),
    (lambda: fb.fourbar(0.3, -0.1, 0.3, 0.2, 0.3), ["a", "-0.1", "> 0"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.0, 0.2, 0.3), ["b", "0", "> 0"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.3, np.nan, 0.3), ["c", "nan"]),
    (lambda: fb.fourbar(np.nan, 0.1, 0.3, 0.2, 0.3), ["theta2", "nan"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.3, 0.2, 0.3, omega2=np.inf), ["omega2", "inf"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.3, 0.2, 0.3, branch=2), ["branch", "2"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.3, 0.2, 0.3, on_fail="ignore"), ["on_fail", "ignore"]),
    (lambda: fb.grashof(0.1, -0.3, 0.2, 0.3), ["b", "-0.3"]),
    (lambda: fb.limit_positions(0.1, 0.3, 0.2, np.nan), ["d", "nan"]),
    (lambda: fb.transmission_angle_extremes(0.1, 0.1, 0.1, 1.0), ["assembled"]),
    (lambda: fb.fourbar_kinetostatics(0.3, 0.1, 0.3, 0.2, 0.3, mass=(1, -2, 1)),
     ["mass[1]", "-2"]),
    (lambda: fb.fourbar_kinetostatics(0.3, 0.1, 0.3, 0.2, 0.3, mass=(1, 2)), ["mass"]),
    (lambda: fb.fourbar_kinetostatics(0.3, 0.1, 0.3, 0.2, 0.3, gravity=(0, np.nan)),
     ["gravity", "nan"]),
    (lambda: fb.fourbar_kinetostatics(0.3, 0.1, 0.3, 0.2, 0.3, moment=(0, 0, np.nan)),
     ["moment[2]", "nan"]),
    (lambda: bar("crank", "O", "A", -0.1), ["crank.length", "-0.1"]),
    (lambda: Body("crank", {"A": (0, 0)}, mass=-1.0), ["crank.mass", "-1"]),
    (lambda: Body("crank", {"A": (0, np.nan)}), ["crank.points.A", "nan"]),
    (lambda: Mechanism(Body("frame", {"O": (0, 0)}), (bar("crank", "O", "A", 0.1),),
                       (Revolute("O", "frame", "krank"),), Crank("O")), ["krank", "unknown"]),
    (lambda: Mechanism(Body("frame", {"O": (0, 0)}), (bar("crank", "O", "A", 0.1),),
                       (Revolute("O", "frame", "crank"),), Crank("X")), ["driver.joint", "X"]),
    (lambda: Mechanism(Body("frame", {"O": (0, 0)}), (bar("crank", "O", "A", 0.1),),
                       (Revolute("Z", "frame", "crank"),), Crank("Z")), ["Z", "no such point"]),
    (lambda: kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.0, np.nan]), ["phi1", "nan"]),
    (lambda: kinematics(engine_fourbar(0.2, 0.2, 0.2, 0.45), _fb_full()), ["assembl", "deg"]),
    (lambda: inverse_dynamics(kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.1]),
                              loads=[PointForce("rokker", "B", fx=1.0)]), ["rokker"]),
    (lambda: inverse_dynamics(kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.1]),
                              loads=[PointForce("rocker", "Q", fx=1.0)]), ["Q", "no such point"]),
    (lambda: inverse_dynamics(kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.1]),
                              gravity=(0, np.nan)), ["gravity", "nan"]),
    (lambda: inverse_dynamics(kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.1, 0.2]),
                              loads=[PointForce("rocker", "B", fx=[1.0, 2.0, 3.0])]), ["fx"]),
])
def test_impossible_parameters_give_clear_errors(call, words):
    with pytest.raises(LinkworkError) as ei:
        call()
    msg = str(ei.value).lower()
    for w in words:
        assert w.lower() in msg, (w, msg)


def test_non_grashof_full_rotation_lists_the_ranges():
    a, b, c, d = 0.2, 0.2, 0.2, 0.45
    with pytest.raises(AssemblyError) as ei:
        fb.fourbar(_fb_full(), a, b, c, d)
    tg = math.degrees(math.acos((a * a + d * d - (b + c) ** 2) / (2 * a * d)))
    lo, hi = (math.degrees(v) for v in ei.value.ranges[0])
    assert lo == pytest.approx(tg, abs=1.01) and hi == pytest.approx(360 - tg, abs=1.01)
    r = fb.fourbar(_fb_full(), a, b, c, d, on_fail="nan")
    assert np.all(np.isnan(r.theta3[~r.assembled])) and np.all(np.isfinite(r.theta3[r.assembled]))


def test_structure_errors_name_bodies_and_joints():
    frame = Body("frame", {"O": (0, 0), "C": (0.3, 0)})
    crank = bar("crank", "O", "A", 0.1)
    rod = bar("rod", "A", "C", 0.3)
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "rod"),
              Revolute("C", "rod", "frame"))
    with pytest.raises(StructureError) as ei:
        kinematics(Mechanism(frame, (crank, rod), joints, Crank("O")), [0.0])
    assert "locked" in str(ei.value) and "rod" in str(ei.value)
    # a body with no joint at all: under-driven
    frame = Body("frame", {"O": (0, 0), "O4": (0.3, 0)})
    m = engine_fourbar(0.1, 0.3, 0.2, 0.3)
    lonely = Body("lonely", {"X": (0, 0)})
    with pytest.raises(StructureError) as ei:
        Mechanism(m.frame, (*m.bodies, lonely), m.joints, m.driver).validate()
    assert "lonely" in str(ei.value)


def test_misspelt_branch_key_is_an_error_not_ignored():
    """branches={"Z": -1} (no such group) used to be ignored silently: the linkage stayed on
    branch +1 although the user asked for the other assembly."""
    m = engine_fourbar(0.1, 0.3, 0.2, 0.3)
    with pytest.raises(ParameterError) as ei:
        kinematics(m, [0.1], branches={"Z": -1})
    assert "'Z'" in str(ei.value) or "Z " in str(ei.value)
    assert "['B']" in str(ei.value)
    with pytest.raises(ParameterError, match="branches"):
        kinematics(m.with_branches(b=-1), [0.1])


# ------------------------------------------------------------------------------------------
# broken files to `linkwork analyze`: one line on stderr, exit code 2
# ------------------------------------------------------------------------------------------

def _variant(tmp_path, example, old, new, name="case.toml"):
    from pathlib import Path
    text = (Path(__file__).resolve().parents[1] / "examples" / example).read_text()
    assert old in text, old
    p = tmp_path / name
    p.write_text(text.replace(old, new, 1))
    return p


PLANAR_BROKEN = [
    ("fourbar_paper001.toml", 'length = "100 mm"', 'length = "100 kg"', ["body.0.length", "kg"]),
    ("fourbar_paper001.toml", 'length = "100 mm"', 'length = "-100 mm"', ["crank.length",
                                                                          "-0.1"]),
    ("fourbar_paper001.toml", 'b = "crank"', 'b = "krank"', ["krank"]),
    ("fourbar_paper001.toml", 'joint = "O"\nomega1', 'joint = "O9"\nomega1', ["O9"]),
    ("fourbar_paper001.toml", 'type = "revolute"', 'type = "ball"', ["joint.0.type", "ball"]),
    ("fourbar_paper001.toml", 'type = "planar"', 'type = "planer"', ["type", "planer"]),
    ("fourbar_paper001.toml", 'branches = { B = 1 }', 'branches = { Z = 1 }', ["branches",
                                                                               "Z"]),
    ("fourbar_paper001.toml", 'n = 361', 'n = 0', ["analysis.n"]),
    ("fourbar_paper001.toml", 'omega1 = "10 rad/s"', 'omega1 = "10 m"', ["driver.omega1"]),
    ("fourbar_paper001.toml", 'length = "300 mm"\nmass = "3 kg"',
     'length = "30 mm"\nmass = "3 kg"', ["assembled", "deg"]),
    ("fourbar_paper001.toml", "[driver]",
     '[[joint]]\nname = "X"\ntype = "revolute"\na = "frame"\nb = "coupler"\npoint_a = "C"\n'
     'point_b = "B"\n\n[driver]', ["locked", "[[joint]] as written is invalid"]),
    ("fourbar_paper001.toml", 'about = [0, 0]',
     'about = [0, 0]\n\n[[load]]\ntype = "force"\nbody = "rokker"\npoint = "B"\nfx = 1\nfy = 0',
     ["load.0.body", "rokker"]),
    ("fourbar_paper001.toml", 'about = [0, 0]',
     'about = [0, 0]\n\n[[load]]\ntype = "force"\nbody = "rocker"\npoint = "Z"\nfx = 1\nfy = 0',
     ["load.0.point", "Z", "rocker"]),
    ("fourbar_paper001.toml", 'about = [0, 0]',
     'about = [0, 0]\n\n[[load]]\ntype = "torque"\nbody = "frame"\nmz = 1',
     ["load.0.body", "frame"]),
    ("fourbar_paper001.toml", 'name = "crank"', 'name = "crank"\ncolour = "red"', ["colour"]),
    ("sine_press_planar.toml", 'angle = "60 deg"', 'angle = "60 mm"', ["joint.2.angle"]),
    ("loom_sixbar.toml", 'type = "planar"', 'type = "planar"\n[oops', ["TOML"]),
]


@pytest.mark.parametrize("example,old,new,words", PLANAR_BROKEN)
def test_cli_broken_planar_files_one_line_exit_2(example, old, new, words, tmp_path, capsys):
    from linkwork.cli import main
    p = _variant(tmp_path, example, old, new)
    rc = main(["analyze", str(p), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for w in words:
        assert w.lower() in err.lower(), (w, err)


def test_cli_missing_file_and_directory(tmp_path, capsys):
    from linkwork.cli import main
    for path in (tmp_path / "nope.toml", tmp_path):
        rc = main(["analyze", str(path)])
        err = capsys.readouterr().err
        assert rc == 2 and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("old,new", [('length = "100 mm"', 'length = "-100 mm"'),
                                     ('b = "crank"', 'b = "krank"')])
def test_cli_model_level_errors_are_short_and_keyed(old, new, tmp_path, capsys):
    from linkwork.cli import main
    p = _variant(tmp_path, "fourbar_paper001.toml", old, new)
    assert main(["analyze", str(p)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err) < 300 and "{'type'" not in err, err


@pytest.mark.parametrize("example", ["fourbar_paper001.toml", "loom_sixbar.toml",
                                     "sine_press_planar.toml"])
def test_cli_examples_write_reactions_and_torque(example, tmp_path, capsys, monkeypatch):
    import csv
    import json
    from pathlib import Path

    from linkwork.cli import main
    from linkwork.files import load
    monkeypatch.setenv("COLUMNS", "250")
    src = Path(__file__).resolve().parents[1] / "examples" / example
    out = tmp_path / "out"
    assert main(["analyze", str(src), "--out", str(out)]) == 0
    table = capsys.readouterr().out
    assert "Q [N·m]" in table and "|R" in table
    with (out / "planar_dynamics.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    doc = load(src)
    mech = doc.mechanism()
    for j in mech.joints:
        assert f"R_{j.name}.x [N]" in rows[0] and f"R_{j.name}.y [N]" in rows[0]
    assert "Q [N*m]" in rows[0]
    data = json.loads((out / "planar.json").read_text())
    assert "Q" in data["columns"]
    for png in ("planar_driving_torque.png", "planar_reactions.png", "planar_shaking.png"):
        assert (out / png).stat().st_size > 10_000
    # the CSV's numbers are the engine's, recomputed here from the file
    phi = doc.positions()
    kin = kinematics(mech, phi)
    dyn = inverse_dynamics(kin, gravity=doc.analysis.gravity, loads=doc.loads(phi),
                           about=doc.analysis.about)
    q_csv = np.array([float(r["Q [N*m]"]) for r in rows])
    np.testing.assert_allclose(q_csv, dyn.Q, rtol=1e-12, atol=1e-12)


def test_fourbar_singular_position_is_never_silent_nan():
    """a = d, b = c (a kite): at theta2 = 0 the crank pin A lies on O4 and B is undetermined.
    The closed form returned NaN there with ``assembled`` True and no error."""
    t = np.array([0.0, 1.0, np.pi])
    with pytest.raises(AssemblyError) as ei:
        fb.fourbar(t, 0.1, 0.2, 0.2, 0.1)
    assert "singular" in str(ei.value) and ei.value.ranges == [(0.0, 0.0)]
    r = fb.fourbar(t, 0.1, 0.2, 0.2, 0.1, on_fail="nan", coupler_point=(0.1, 0.02))
    assert list(r.assembled) == [False, True, True]
    for name in ("theta3", "theta4", "omega3", "omega4", "alpha3", "alpha4", "xB", "yB", "xP"):
        v = getattr(r, name)
        assert np.isnan(v[0]) and np.all(np.isfinite(v[1:])), name
    with pytest.raises(AssemblyError):
        fb.fourbar_kinetostatics(0.0, 0.1, 0.2, 0.2, 0.1, mass=(1, 1, 1))
    # the engine agrees: the same position is refused
    with pytest.raises(AssemblyError):
        kinematics(engine_fourbar(0.1, 0.2, 0.2, 0.1), t)


@pytest.mark.parametrize("branch", [1, -1])
def test_engine_dead_centres_are_exact(branch):
    """The engine's dead centres were linearly interpolated between samples (6e-6 rad off at
    1 deg sampling); they must agree with the closed forms' limit positions."""
    from linkwork.models import crank_slider as cs
    from linkwork.planar import dead_centres
    lim = fb.limit_positions(0.1, 0.3, 0.2, 0.3, branch)
    kin = kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3, branch=branch),
                     np.linspace(0, 2 * np.pi, 361))
    got = sorted(d.phi1 for d in dead_centres(kin))
    want = sorted(float(np.mod(x, 2 * np.pi)) for x in (lim.theta2_rocker_extended,
                                                        lim.theta2_rocker_folded))
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-10)
    # crank-slider with the guide along +y at x = e (paper 000's idle mode)
    mech = engine_crank_slider(0.05, 0.2, -0.025, guide_angle=math.radians(90), branch=branch)
    kin = kinematics(mech, np.linspace(0, 2 * np.pi, 361))
    dc = cs.dead_centres(4.0, 0.5, branch)
    got = {d.kind: d.phi1 for d in dead_centres(kin)}
    np.testing.assert_allclose([got["max"], got["min"]],
                               [float(dc.phi1_top), float(dc.phi1_bottom)], rtol=0, atol=1e-10)


@pytest.mark.parametrize("branch", [1, -1])
def test_engine_transmission_angle_full_precision(branch):
    """mu from the law of cosines (closed form) and the engine's mu, delta agree to 1e-14 over
    the cycle; the engine's arccos lost half the digits near mu = 90 deg (1.5e-8 rad)."""
    phi = np.linspace(0, 2 * np.pi, 37)
    kin = kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3, branch=branch), phi)
    from linkwork.planar import transmission_angles
    mu, delta = transmission_angles(kin)["B"]
    # independent: angle at B between B->A and B->O4, from the engine's own points
    A = kin.point("coupler", "A")
    B = kin.point("coupler", "B")
    ux, uy = A.x - B.x, A.y - B.y
    vx, vy = 0.3 - B.x, -B.y
    ang = np.arctan2(np.abs(ux * vy - uy * vx), ux * vx + uy * vy)
    ref = np.minimum(ang, np.pi - ang)
    np.testing.assert_allclose(mu, ref, rtol=0, atol=1e-14)
    np.testing.assert_allclose(delta, np.pi / 2 - ref, rtol=0, atol=1e-14)


def test_fourbar_empty_and_non_broadcasting_inputs():
    """An empty theta2 raised NumPy's 'zero-size array to reduction operation'; lengths that
    do not broadcast against the angles raised NumPy's broadcast error."""
    r = fb.fourbar(np.array([]), 0.1, 0.3, 0.2, 0.3)
    assert r.theta3.shape == (0,) and r.assembled.shape == (0,)
    assert fb.fourbar_kinetostatics(np.array([]), 0.1, 0.3, 0.2, 0.3).Q.shape == (0,)
    for n in (2, 20000):
        with pytest.raises(ParameterError, match=r"shapes.*'a': \(3,\)"):
            fb.fourbar(np.zeros(n), np.array([0.1, 0.2, 0.3]), 0.3, 0.2, 0.3)


def test_skeleton_plot_draws_guides_and_slots():
    """A press designer reading the skeleton of the sine press must see the ram's guide and
    the inclined slot (only joint points were drawn: the slot was invisible)."""
    from linkwork.files import load
    from linkwork.plot.planar import plot_skeleton
    doc = load(_example("sine_press_planar.toml"))
    kin = kinematics(doc.mechanism(), doc.positions())
    out = plot_skeleton(kin, [0, 30])
    labels = sorted(ln.get_label() for ln in out["guides"])
    assert labels == ["guide", "slot"]
    slot = next(ln for ln in out["guides"] if ln.get_label() == "slot")
    x, y = slot.get_data()
    assert math.degrees(math.atan2(y[1] - y[0], x[1] - x[0])) == pytest.approx(60.0)
    import matplotlib.pyplot as plt
    plt.close("all")


def _example(name):
    from pathlib import Path
    return Path(__file__).resolve().parents[1] / "examples" / name


def _group_builders():
    import _mechanisms as tg
    return [(b.__name__, b) for b in tg.BUILDERS]


@pytest.mark.parametrize("name,builder", _group_builders())
def test_engine_every_group_kind_against_newton_euler(name, builder):
    """Every group kind of the engine (the seven dyads, both slot groups, a linear driver and a
    triad; mechanisms as built in test_planar_groups) against the raw-constraint reference and
    Newton-Euler, with gravity, a point force, a couple and eps1 != 0."""
    mech, positions, _kind = builder()
    idx = np.linspace(0, len(positions) - 1, 7).round().astype(int)
    phi = np.asarray(positions)[idx]
    last = mech.bodies[-1].name
    loads = [PointForce(last, "com", fx=12.0, fy=-7.0), BodyTorque(mech.bodies[0].name, 0.8)]
    crank = isinstance(mech.driver, Crank)
    _check_engine(mech, phi, 6.0 if crank else 0.7, 15.0 if crank else 0.4, (0.0, -9.81),
                  loads, about=(0.02, 0.01), label="groups ", step=2e-4)


@pytest.mark.parametrize("branch", [1, -1])
def test_paper004_eqs_8_to_13_against_the_engine(branch):
    """Paper 004's chained planar kinetostatics (8)-(13), corrected, equal the engine's
    reactions and driving moment (paper 001's four-bar, gravity, couples, eps1 != 0); as
    printed, (8) is right and (9), (13) are not (docs/errata.md)."""
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    masses, inert = (1.0, 3.0, 2.0), (0.002, 0.03, 0.008)
    mech = engine_fourbar(a, b, c, d, masses=masses, inertias=inert, branch=branch)
    g = np.array([0.0, -9.81])
    couples = (0.5, -1.5, 2.0)
    kin = kinematics(mech, PHI7, 10.0, 25.0)
    dyn = inverse_dynamics(kin, gravity=g, loads=[BodyTorque(n, m) for n, m in zip(
        ("crank", "coupler", "rocker"), couples, strict=True)])
    F, M = [], []
    for i, name in enumerate(("crank", "coupler", "rocker")):
        s = kin.point(name, "com")                    # the midpoint (bar default)
        F.append((masses[i] * (g[0] - s.ax), masses[i] * (g[1] - s.ay)))
        M.append(-inert[i] * kin.eps[i + 1] + couples[i])
    phi1, phi2 = kin.angle("crank"), kin.angle("coupler")
    phi3 = kin.angle("rocker") + np.pi                # paper 004: phi3 is B -> C
    for printed in (False, True):
        p = fb.paper004_planar(phi1, phi2, phi3, a, b, c, *F, *M, printed=printed)
        scale = np.max(np.abs(dyn.fx))
        got = {"R_B": (p.R_Bx, p.R_By), "R_C": (p.R_Cx, p.R_Cy), "R_A": (p.R_Ax, p.R_Ay),
               "R_0": (p.R_0x, p.R_0y)}
        want = {"R_B": dyn.reaction("B"), "R_C": dyn.reaction("O4"), "R_A": dyn.reaction("A"),
                "R_0": dyn.reaction("O2")}
        if not printed:
            for k in got:
                _close(got[k][0], want[k][0], scale, "paper004 corrected vs engine")
                _close(got[k][1], want[k][1], scale, "paper004 corrected vs engine")
            _close(p.Q, dyn.Q, scale * a, "paper004 corrected vs engine")
        else:
            _close(p.R_Bx, want["R_B"][0], scale, "paper004 printed (8) vs engine")
            assert np.max(np.abs(p.R_By - want["R_B"][1])) > 1e-3 * scale     # (9) wrong
            assert np.max(np.abs(p.Q - dyn.Q)) > 1e-3 * scale * a             # (13) wrong


def test_zz_report_deviations():
    """Print the largest deviation per quantity (relative; absolute [rad] for angles)."""
    for k, v in sorted(DEV.items()):
        print(f"issue3 max deviation {k:40s} {v:.2e}")
