"""The planar engine on the four-bar and the offset crank-slider.

Independent references: plain trigonometry written here (circle intersection, the slider's
quadratic), central finite differences of positions, the power balance and the momentum
theorems.
"""

from __future__ import annotations

import numpy as np
import pytest

from linkwork.planar import (
    BodyTorque,
    PointForce,
    crank_slider_mechanism,
    fourbar_mechanism,
    inverse_dynamics,
    kinematics,
)

PHI = np.linspace(0.0, 2 * np.pi, 37)


def _fourbar_B_reference(phi, a, b, c, d, branch):
    """B by intersecting circle(A, b) and circle(O4, c), written independently."""
    Ax, Ay = a * np.cos(phi), a * np.sin(phi)
    ex, ey = d - Ax, -Ay
    f = np.hypot(ex, ey)
    # angle at A between A->O4 and A->B from the cosine rule
    gam = np.arccos((b * b + f * f - c * c) / (2 * b * f))
    ang = np.arctan2(ey, ex) + branch * gam
    return Ax + b * np.cos(ang), Ay + b * np.sin(ang)


@pytest.mark.parametrize("branch", [1, -1])
def test_fourbar_positions_against_trigonometry(branch):
    """Reference: circle-circle intersection written out here (``_fourbar_B_reference``).
    Tolerance: 1e-14 m on B (links of 0.1-0.3 m), 1e-13 relative on the coupler length."""
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    k = kinematics(fourbar_mechanism(a, b, c, d, branch=branch), PHI)
    Bx, By = _fourbar_B_reference(PHI, a, b, c, d, branch)
    for body in ("coupler", "rocker"):
        B = k.point(body, "B")
        np.testing.assert_allclose(B.x, Bx, atol=1e-14)
        np.testing.assert_allclose(B.y, By, atol=1e-14)
    # loop closure and link lengths
    A = k.point("crank", "A")
    np.testing.assert_allclose(np.hypot(Bx - A.x, By - A.y), b, rtol=1e-13)
    np.testing.assert_allclose(k.angle("crank"), PHI, atol=1e-15)


def _fd_check(mech, phi, w, e, h=1e-5, rtol=1e-7):
    """Velocities/accelerations against central differences of positions (d/dt = w d/dphi)."""
    k = kinematics(mech, phi, omega1=w, eps1=e)
    kp = kinematics(mech, phi + h, omega1=w, eps1=e)
    km = kinematics(mech, phi - h, omega1=w, eps1=e)
    scale_v = np.max(np.abs(k.vx)) + np.max(np.abs(k.omega))
    for name in ("x", "y", "theta"):
        d1 = (getattr(kp, name) - getattr(km, name)) / (2 * h)
        d2 = (getattr(kp, name) - 2 * getattr(k, name) + getattr(km, name)) / h**2
        vel = {"x": k.vx, "y": k.vy, "theta": k.omega}[name]
        acc = {"x": k.ax, "y": k.ay, "theta": k.eps}[name]
        np.testing.assert_allclose(vel, d1 * w, atol=rtol * scale_v * 10)
        np.testing.assert_allclose(acc, d2 * w * w + d1 * e,
                                   atol=1e-4 * (np.max(np.abs(acc)) + 1))


def test_fourbar_velocity_acceleration_finite_differences():
    _fd_check(fourbar_mechanism(0.1, 0.3, 0.2, 0.3), PHI, 10.0, 3.0)


def test_crank_slider_velocity_acceleration_finite_differences():
    _fd_check(crank_slider_mechanism(0.1, 0.35, 0.04, guide_angle=0.3), PHI, 7.0, -2.0)


@pytest.mark.parametrize("branch", [1, -1])
def test_crank_slider_positions_against_quadratic(branch):
    """Reference: the slider's quadratic solved here in closed form. Tolerance: 1e-14 m on B
    (crank 0.1 m, rod 0.35 m)."""
    r, l, e = 0.1, 0.35, 0.04
    k = kinematics(crank_slider_mechanism(r, l, e, branch=branch), PHI)
    Ax, Ay = r * np.cos(PHI), r * np.sin(PHI)
    xb = Ax + branch * np.sqrt(l**2 - (e - Ay) ** 2)
    B = k.point("slider", "B")
    np.testing.assert_allclose(B.x, xb, atol=1e-14)
    np.testing.assert_allclose(B.y, e, atol=1e-15)
    np.testing.assert_allclose(k.point("rod", "B").x, xb, atol=1e-14)


def _balances(mech, phi, w, e, g, loads, about=(0.05, -0.02)):
    k = kinematics(mech, phi, omega1=w, eps1=e)
    d = inverse_dynamics(k, gravity=g, loads=loads, about=about)
    n = k.n
    dT, P_ext = np.zeros(n), np.zeros(n)
    mom_x, mom_y, dH = np.zeros(n), np.zeros(n), np.zeros(n)
    Fx, Fy, M_ext = np.zeros(n), np.zeros(n), np.zeros(n)
    for b in mech.bodies:
        i = mech.index[b.name]
        c = k.point(b.name, "com")
        dT += b.mass * (c.ax * c.vx + c.ay * c.vy) + b.inertia * k.eps[i] * k.omega[i]
        P_ext += b.mass * (g[0] * c.vx + g[1] * c.vy)
        mom_x += b.mass * c.ax
        mom_y += b.mass * c.ay
        dH += (c.x - about[0]) * b.mass * c.ay - (c.y - about[1]) * b.mass * c.ax
        dH += b.inertia * k.eps[i]
        Fx += b.mass * g[0]
        Fy += b.mass * g[1]
        M_ext += (c.x - about[0]) * b.mass * g[1] - (c.y - about[1]) * b.mass * g[0]
    for ld in loads:
        if isinstance(ld, PointForce):
            P = k.point(ld.body, ld.point)
            P_ext += ld.fx * P.vx + ld.fy * P.vy
            Fx += ld.fx
            Fy += ld.fy
            M_ext += (P.x - about[0]) * ld.fy - (P.y - about[1]) * ld.fx
        else:
            P_ext += ld.mz * k.omega[mech.index[ld.body]]
            M_ext += ld.mz
    scale = np.max(np.abs(dT)) + np.max(np.abs(P_ext))
    np.testing.assert_allclose(d.Q * k.omega1, dT - P_ext, atol=1e-9 * scale)
    fscale = np.max(np.abs(mom_x)) + np.max(np.abs(Fx)) + np.max(np.abs(mom_y))
    # momentum theorem: sum m a = F_ext + gravity - F_shaking
    np.testing.assert_allclose(d.shaking_fx, Fx - mom_x, atol=1e-9 * fscale)
    np.testing.assert_allclose(d.shaking_fy, Fy - mom_y, atol=1e-9 * fscale)
    mscale = np.max(np.abs(dH)) + np.max(np.abs(M_ext))
    np.testing.assert_allclose(d.shaking_m, M_ext - dH, atol=1e-9 * mscale)
    return k, d


def test_fourbar_power_and_momentum_balance_eps1_gravity_loads():
    m = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0),
                          inertias=(0.001, 0.0225, 0.00567))
    loads = [PointForce("coupler", (0.1, 0.05), 3.0, -2.0 * np.cos(PHI)),
             BodyTorque("rocker", 1.5)]
    _balances(m, PHI, 10.0, 4.0, (0.3, -9.81), loads)


def test_crank_slider_power_and_momentum_balance_press_force():
    m = crank_slider_mechanism(0.1, 0.3, 0.05, masses=(1.0, 2.0, 3.0), guide_angle=0.4)
    tech = np.where(np.sin(PHI) > 0, -500.0, 0.0)
    loads = [PointForce("slider", "B", tech * np.cos(0.4), tech * np.sin(0.4))]
    _balances(m, PHI, 12.0, -3.0, (1.0, -9.81), loads)


def test_fourbar_reactions_newton_euler_by_hand():
    """Reactions of the four-bar from Newton-Euler equations written out in the test, with
    gravity in an oblique direction, a force at a coupler point, a couple on the rocker and
    eps1 != 0."""
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    ms = (1.0, 3.0, 2.0)
    Is = (0.002, 0.0225, 0.0067)
    m = fourbar_mechanism(a, b, c, d, masses=ms, inertias=Is)
    w, e, g = 10.0, 5.0, (2.0, -9.81)
    Fp, M3 = (30.0, -20.0), 4.0
    k = kinematics(m, PHI, omega1=w, eps1=e)
    dyn = inverse_dynamics(k, gravity=g, loads=[PointForce("coupler", (0.1, 0.05), *Fp),
                                                BodyTorque("rocker", M3)])
    Pc = k.point("coupler", (0.1, 0.05))
    A = k.point("crank", "A")
    B = k.point("coupler", "B")
    c2, c3 = k.point("coupler", "com"), k.point("rocker", "com")
    e2, e3 = k.eps[2], k.eps[3]
    # unknowns per position: F_AB (crank on coupler, 2), F_BC (coupler on rocker, 2),
    # F_O4 (frame on rocker, 2), F_O2 (frame on crank, 2), Q
    rows = []
    for i in range(k.n):
        M = np.zeros((9, 9))
        rhs = np.zeros(9)
        # coupler: F_A - F_B + m2 g = m2 a2 ; moments about c2
        M[0, 0], M[0, 2] = 1, -1
        M[1, 1], M[1, 3] = 1, -1
        rAx, rAy = A.x[i] - c2.x[i], A.y[i] - c2.y[i]
        rBx, rBy = B.x[i] - c2.x[i], B.y[i] - c2.y[i]
        M[2, 0], M[2, 1] = -rAy, rAx
        M[2, 2], M[2, 3] = rBy, -rBx
        rhs[0] = ms[1] * (c2.ax[i] - g[0]) - Fp[0]
        rhs[1] = ms[1] * (c2.ay[i] - g[1]) - Fp[1]
        rPx, rPy = Pc.x[i] - c2.x[i], Pc.y[i] - c2.y[i]
        rhs[2] = Is[1] * e2[i] - (rPx * Fp[1] - rPy * Fp[0])
        # rocker: F_B + F_O4 + m3 g = m3 a3
        M[3, 2], M[3, 4] = 1, 1
        M[4, 3], M[4, 5] = 1, 1
        rBx, rBy = B.x[i] - c3.x[i], B.y[i] - c3.y[i]
        rOx, rOy = d - c3.x[i], 0.0 - c3.y[i]
        M[5, 2], M[5, 3] = -rBy, rBx
        M[5, 4], M[5, 5] = -rOy, rOx
        rhs[3] = ms[2] * (c3.ax[i] - g[0])
        rhs[4] = ms[2] * (c3.ay[i] - g[1])
        rhs[5] = Is[2] * e3[i] - M3
        # crank: F_O2 - F_A + m1 g = m1 a1; moments about O2 (fixed point)
        c1 = k.point("crank", "com")
        M[6, 6], M[6, 0] = 1, -1
        M[7, 7], M[7, 1] = 1, -1
        M[8, 0], M[8, 1] = A.y[i], -A.x[i]
        M[8, 8] = 1
        rhs[6] = ms[0] * (c1.ax[i] - g[0])
        rhs[7] = ms[0] * (c1.ay[i] - g[1])
        Io = Is[0] + ms[0] * (a / 2) ** 2
        rhs[8] = Io * k.eps[1][i] - (c1.x[i] * ms[0] * g[1] - c1.y[i] * ms[0] * g[0])
        rows.append(np.linalg.solve(M, rhs))
    ref = np.array(rows).T
    tol = 1e-9 * np.max(np.abs(ref))
    np.testing.assert_allclose(dyn.reaction("A")[0], ref[0], atol=tol)
    np.testing.assert_allclose(dyn.reaction("A")[1], ref[1], atol=tol)
    np.testing.assert_allclose(dyn.reaction("B")[0], ref[2], atol=tol)
    np.testing.assert_allclose(dyn.reaction("B")[1], ref[3], atol=tol)
    # joint O4 is Revolute("O4", "frame", "rocker"): force of the frame on the rocker
    np.testing.assert_allclose(dyn.reaction("O4")[0], ref[4], atol=tol)
    np.testing.assert_allclose(dyn.reaction("O2")[0], ref[6], atol=tol)
    np.testing.assert_allclose(dyn.reaction("O2")[1], ref[7], atol=tol)
    np.testing.assert_allclose(dyn.Q, ref[8], atol=tol)


def test_kinetic_energy_lagrange_driving_torque():
    """Q from Lagrange's equation with T(phi) = 1/2 J(phi) omega^2 by finite differences."""
    m = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0))
    h = 1e-4
    w = 1.0
    T0 = inverse_dynamics(kinematics(m, PHI, omega1=w)).T
    Tp = inverse_dynamics(kinematics(m, PHI + h, omega1=w)).T
    Tm = inverse_dynamics(kinematics(m, PHI - h, omega1=w)).T
    Jred = 2 * T0
    dJ = (Tp - Tm) / h  # d(2T)/dphi with w = 1
    w1, e1 = 8.0, 3.0
    Q = inverse_dynamics(kinematics(m, PHI, omega1=w1, eps1=e1)).Q
    np.testing.assert_allclose(Q, Jred * e1 + 0.5 * dJ * w1**2, atol=1e-6 * np.max(np.abs(Q)))
