"""The d'Alembert loads of the engine (:func:`linkwork.planar.inertia.inertia_wrenches`) against
the motion differentiated numerically, and the shaking force and moment built from them against
the whole-machine equilibrium of inverse dynamics and the per-link formulas
``F_sh = -sum m_i a_Ci``, ``M_P = -sum [(r_Ci - P) x m_i a_Ci + J_Ci eps_i]``."""

from __future__ import annotations

import numpy as np
import pytest

from linkwork.balancing import shaking_force, shaking_loads, shaking_moment
from linkwork.errors import ParameterError
from linkwork.planar import crank_slider_mechanism, fourbar_mechanism, inverse_dynamics, kinematics
from linkwork.planar.inertia import InertiaWrenches, inertia_wrenches
from linkwork.redundancy.mechanism import body_wrenches

G = (0.8, -9.81)


def _fourbar():
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0),
                             coms=(0.04, (0.12, 0.03), None), omega1=12.0)
    return mech, kinematics(mech, np.linspace(0.0, 2 * np.pi, 37))


def test_wrenches_are_mass_times_finite_difference_acceleration():
    """m (g - a_C) and -J eps with a_C and eps from central differences of the centre of mass
    and the body angle over time at constant crank speed (h = 1e-4 rad: truncation ~1e-8 of
    the accelerations, rounding ~1e-16/h^2 ~ 1e-8 m/s^2 relative to |r| ~ 0.1 m; rtol 1e-5)."""
    mech, kin = _fourbar()
    w = 12.0
    iw = inertia_wrenches(kin, G)
    assert isinstance(iw, InertiaWrenches)
    assert iw.bodies == ("crank", "coupler", "rocker")
    assert iw.fx.shape == (3, kin.n)  # positions last
    h = 1e-4
    kp = kinematics(mech, kin.phi1 + h, w)
    km = kinematics(mech, kin.phi1 - h, w)
    for k, b in enumerate(mech.bodies):
        c, cp, cm = kin.point(b.name), kp.point(b.name), km.point(b.name)
        ax = (cp.x - 2 * c.x + cm.x) / h**2 * w**2
        ay = (cp.y - 2 * c.y + cm.y) / h**2 * w**2
        th = np.unwrap(np.stack([km.angle(b.name), kin.angle(b.name), kp.angle(b.name)]), axis=0)
        eps = (th[2] - 2 * th[1] + th[0]) / h**2 * w**2
        scale_f = b.mass * (np.max(np.hypot(ax, ay)) + 9.9)
        np.testing.assert_allclose(iw.fx[k], b.mass * (G[0] - ax), atol=1e-5 * scale_f)
        np.testing.assert_allclose(iw.fy[k], b.mass * (G[1] - ay), atol=1e-5 * scale_f)
        np.testing.assert_allclose(iw.mz[k], -b.inertia * eps,
                                   atol=1e-5 * b.inertia * np.max(np.abs(eps)) + 1e-12)
        np.testing.assert_allclose(iw.cx[k], c.x, rtol=0, atol=0)
        np.testing.assert_allclose(iw.cy[k], c.y, rtol=0, atol=0)


def test_without_gravity_the_resultant_is_the_shaking_force_and_moment_of_inverse_dynamics():
    """Without loads and gravity the frame takes -sum m a_C and the moment of the inertia
    wrenches (reactions and motor torque included): the reaction solver against the sum."""
    mech = crank_slider_mechanism(0.05, 0.2, 0.01, masses=(1.2, 2.5, 8.0), omega1=15.0, eps1=4.0)
    kin = kinematics(mech, np.linspace(0.0, 2 * np.pi, 49))
    about = (0.03, -0.07)
    dyn = inverse_dynamics(kin, about=about)
    fx, fy, mz = inertia_wrenches(kin).resultant(about)
    scale_f = float(np.max(np.hypot(fx, fy)))
    np.testing.assert_allclose(dyn.shaking_fx, fx, atol=1e-9 * scale_f)
    np.testing.assert_allclose(dyn.shaking_fy, fy, atol=1e-9 * scale_f)
    np.testing.assert_allclose(dyn.shaking_m, mz, atol=1e-9 * scale_f * 0.25)


def test_shaking_loads_match_the_per_link_formula():
    """balancing.shaking_loads against F = -sum m a_C, M_P = -sum[(r_C - P) x m a_C + J eps]
    written out from kin.point (the existing tests' formula)."""
    mech, kin = _fourbar()
    P = (0.05, 0.02)
    sl = shaking_loads(kin, P)
    fx, fy, m = np.zeros(kin.n), np.zeros(kin.n), np.zeros(kin.n)
    for b in mech.bodies:
        c = kin.point(b.name)
        Fx, Fy = -b.mass * c.ax, -b.mass * c.ay
        fx += Fx
        fy += Fy
        m += (c.x - P[0]) * Fy - (c.y - P[1]) * Fx - b.inertia * kin.eps[mech.index[b.name]]
    np.testing.assert_allclose(sl.fx, fx, rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(sl.fy, fy, rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(sl.moment, m, rtol=1e-13, atol=1e-12)


def test_array_shaking_force_and_moment_match_the_per_link_formula():
    """balancing.shaking_force / shaking_moment on arrays (b, n, 2) against the written-out sum."""
    rng = np.random.default_rng(5)
    b, n = 4, 7
    m, J = rng.uniform(1, 3, b), rng.uniform(0.01, 0.1, b)
    pos, acc, eps = rng.normal(size=(b, n, 2)), rng.normal(size=(b, n, 2)), rng.normal(size=(b, n))
    P = np.array([0.3, -0.1])
    F_ref, M_ref = np.zeros((n, 2)), np.zeros(n)
    for i in range(b):
        Fi = -m[i] * acc[i]
        F_ref += Fi
        d = pos[i] - P
        M_ref += d[:, 0] * Fi[:, 1] - d[:, 1] * Fi[:, 0] - J[i] * eps[i]
    np.testing.assert_allclose(shaking_force(m, acc), F_ref, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(shaking_moment(m, J, pos, acc, eps, P), M_ref, rtol=1e-13,
                               atol=1e-14)


def test_redundancy_body_wrenches_carry_the_inertia_wrenches():
    """The spatial adapter's forces are m (g - a_C) and its z moments (about the origin) are
    r_C x F - J eps: compared with the formula from kin.point."""
    mech, kin = _fourbar()
    w = body_wrenches(mech, kin, gravity=G)
    assert w.shape == (kin.n, 3, 6)
    for k, b in enumerate(mech.bodies):
        c = kin.point(b.name)
        Fx, Fy = b.mass * (G[0] - c.ax), b.mass * (G[1] - c.ay)
        np.testing.assert_allclose(w[:, k, 0], Fx, rtol=1e-13, atol=1e-12)
        np.testing.assert_allclose(w[:, k, 1], Fy, rtol=1e-13, atol=1e-12)
        Mz = c.x * Fy - c.y * Fx - b.inertia * kin.eps[mech.index[b.name]]
        np.testing.assert_allclose(w[:, k, 5], Mz, rtol=1e-12, atol=1e-12)


def test_massless_bodies_add_nothing_and_bad_arguments_are_refused():
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(0.0, 3.0, 0.0), inertias=(0.0, None, 0.0))
    kin = kinematics(mech, np.linspace(0.0, 2 * np.pi, 13))
    iw = inertia_wrenches(kin)
    assert np.all(iw.fx[0] == 0.0) and np.all(iw.mz[2] == 0.0)
    fx, _, _ = iw.resultant()
    np.testing.assert_array_equal(fx, iw.fx[1])
    with pytest.raises(ParameterError, match="gravity"):
        inertia_wrenches(kin, (0.0, -9.81, 0.0))
    with pytest.raises(ParameterError, match="kin"):
        inertia_wrenches(mech)  # type: ignore[arg-type]


def test_centres_of_mass_equal_point_motion_of_each_body():
    """Kinematics.centres_of_mass() (all bodies at once, the rows of inertia_wrenches) gives
    bit for bit what Kinematics.point(body, "com") gives body by body."""
    mech, kin = _fourbar()
    com = kin.centres_of_mass()
    for k, b in enumerate(mech.bodies):
        one = kin.point(b.name, "com")
        for name in ("x", "y", "vx", "vy", "ax", "ay"):
            np.testing.assert_array_equal(getattr(com, name)[k], getattr(one, name),
                                          err_msg=f"{b.name}.{name}")
