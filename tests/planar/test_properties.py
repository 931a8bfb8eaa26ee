"""Hypothesis-generated four-bars and crank-sliders that assemble: closure and FD consistency."""

from __future__ import annotations

import numpy as np
from _strategies import reals
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from linkwork.planar import crank_slider_mechanism, fourbar_mechanism, kinematics

length = st.floats(0.05, 1.0)
PHI = np.linspace(0.0, 2 * np.pi, 24, endpoint=False)


def _fd(mech, phi, h=1e-6, h2=1e-4):
    """Velocities by central differences with step h, accelerations with the larger h2."""
    w, e = 1.7, 0.9
    k = kinematics(mech, phi, omega1=w, eps1=e)
    runs = {hh: (kinematics(mech, phi + hh, omega1=w, eps1=e),
                 kinematics(mech, phi - hh, omega1=w, eps1=e)) for hh in (h, h2)}
    for name, vel, acc in (("x", k.vx, k.ax), ("y", k.vy, k.ay), ("theta", k.omega, k.eps)):
        diffs = {}
        for hh, (kp, km) in runs.items():
            dp = getattr(kp, name) - getattr(k, name)
            dm = getattr(km, name) - getattr(k, name)
            if name == "theta":
                dp, dm = np.angle(np.exp(1j * dp)), np.angle(np.exp(1j * dm))
            diffs[hh] = (dp, dm)
        dp, dm = diffs[h]
        np.testing.assert_allclose(vel, (dp - dm) / (2 * h) * w,
                                   atol=1e-6 * (1 + np.max(np.abs(vel))), err_msg=name)
        dp, dm = diffs[h2]
        np.testing.assert_allclose(acc, (dp + dm) / h2**2 * w * w + (dp - dm) / (2 * h2) * e,
                                   atol=1e-5 * (1 + np.max(np.abs(acc))), err_msg=name)
    return k


@settings(max_examples=60, deadline=None)
@given(t=st.floats(0.05, 0.95), b=length, c=length, d=length, branch=st.sampled_from([1, -1]))
def test_random_fourbar_closure_and_fd(t, b, c, d, branch):
    # a crank that turns fully, 2 % of the size away from the toggles:
    # |b - c| + m <= |A - O4| in [d - a, d + a] <= b + c - m
    m = 0.02 * (b + c + d)
    a_max = min(b + c - d, d - abs(b - c)) - m
    assume(a_max > 0.02)
    a = t * a_max
    k = _fd(fourbar_mechanism(a, b, c, d, branch=branch), PHI)
    A, B = k.point("crank", "A"), k.point("coupler", "B")
    O4 = k.point("rocker", "O4")
    np.testing.assert_allclose(np.hypot(B.x - A.x, B.y - A.y), b, rtol=1e-12)
    np.testing.assert_allclose(np.hypot(B.x - O4.x, B.y - O4.y), c, rtol=1e-12)
    size = a + b + c + d  # round-off of coordinates scales with the mechanism's size
    np.testing.assert_allclose(O4.x, d, atol=1e-12 * size)
    Br = k.point("rocker", "B")
    np.testing.assert_allclose(B.x, Br.x, atol=1e-12 * size)
    # branch: B left of A -> O4 for +1
    cross = (d - A.x) * (B.y - A.y) - (0 - A.y) * (B.x - A.x)
    assert np.all(np.sign(cross) == branch)


@settings(max_examples=60, deadline=None)
@given(r=length, l=length, e=reals(-0.5, 0.5), ang=reals(-3.0, 3.0),
       branch=st.sampled_from([1, -1]))
def test_random_crank_slider_closure_and_fd(r, l, e, ang, branch):
    assume(l - r - abs(e) > 0.02 * (r + l))
    k = _fd(crank_slider_mechanism(r, l, e, guide_angle=ang, branch=branch), PHI)
    A, B = k.point("crank", "A"), k.point("slider", "B")
    np.testing.assert_allclose(np.hypot(B.x - A.x, B.y - A.y), l, rtol=1e-12)
    # B on the guide: distance e from O, normal -sin/cos
    np.testing.assert_allclose(-np.sin(ang) * B.x + np.cos(ang) * B.y, e, atol=1e-12 * (r + l))
    s = np.cos(ang) * B.x + np.sin(ang) * B.y
    sa = np.cos(ang) * A.x + np.sin(ang) * A.y
    assert np.all(np.sign(s - sa) == branch)


@settings(max_examples=40, deadline=None)
@given(t=st.floats(0.05, 0.95), b=length, c=length, d=length,
       masses=st.tuples(*[st.floats(0.1, 10.0)] * 3), gdir=reals(-np.pi, np.pi),
       eps1=reals(-20.0, 20.0))
def test_random_fourbar_power_and_momentum(t, b, c, d, masses, gdir, eps1):
    from linkwork.planar import inverse_dynamics

    m = 0.02 * (b + c + d)
    a_max = min(b + c - d, d - abs(b - c)) - m
    assume(a_max > 0.02)
    mech = fourbar_mechanism(t * a_max, b, c, d, masses=masses)
    g = (9.81 * np.cos(gdir), 9.81 * np.sin(gdir))
    k = kinematics(mech, PHI, omega1=3.0, eps1=eps1)
    dyn = inverse_dynamics(k, gravity=g)
    dT, P, px, py = (np.zeros(k.n) for _ in range(4))
    for body in mech.bodies:
        i = mech.index[body.name]
        cm = k.point(body.name, "com")
        dT += body.mass * (cm.vx * cm.ax + cm.vy * cm.ay) + body.inertia * k.omega[i] * k.eps[i]
        P += body.mass * (g[0] * cm.vx + g[1] * cm.vy)
        px += body.mass * (cm.ax - g[0])
        py += body.mass * (cm.ay - g[1])
    np.testing.assert_allclose(dyn.Q * 3.0, dT - P,
                               atol=1e-9 * (np.max(np.abs(dT)) + np.max(np.abs(P))))
    np.testing.assert_allclose(dyn.shaking_fx, -px, atol=1e-9 * np.max(np.abs(px) + 1e-300))
    np.testing.assert_allclose(dyn.shaking_fy, -py, atol=1e-9 * np.max(np.abs(py) + 1e-300))
