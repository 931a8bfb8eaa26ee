"""Force elements and motion-dependent loads of the planar engine (linkwork.planar.forces).

References, none produced by the code under test:

* the crank-slider's slide, its speed and every element's length, tension and energy written
  out here by trigonometry (rtol 1e-12 of the quantity's scale);
* the power of every element by hand: a spring's ``-dV/dt`` and a damper's ``-c (dL/dt)^2``
  with ``V`` and ``L`` written here and differentiated over the driver by fourth-order
  central differences (step 1e-3 rad, truncation below 1e-12 of the scale), a drag's from the
  velocity of its point, a slide force's ``F ds/dt``;
* the power balance ``Q omega1 = dT/dt - sum P_loads - P_gravity + sum P_friction`` with those
  hand powers, on every group kind of ``tests/_mechanisms.py`` (with and without Coulomb friction
  in every joint, variable ``omega1``, ``eps1 != 0``), to 1e-9 of the largest term;
* Newton-Euler equations of every body with the Lagrange multipliers (``tests/
  _planar_newton_euler.py``), assembled per position with the element forces computed here
  from the poses, to 1e-9 of the largest reaction;
* momentum: springs and dampers are internal to the machine (frame included), so the
  shaking force stays ``-sum m a_C`` (1e-9).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _mechanisms import BUILDERS, kinetic_energy_rate, with_friction
from _planar_newton_euler import _newton_euler
from hypothesis import given, settings
from hypothesis import strategies as st

from linkwork.errors import ParameterError
from linkwork.planar import (
    BodyTorque,
    Damper,
    Drag,
    LoadDiagram,
    PointForce,
    SlideForce,
    Spring,
    crank_slider_mechanism,
    fourbar_mechanism,
    inverse_dynamics,
    kinematics,
)
from linkwork.planar.friction import SIGN_WIDTH

R, L_ROD, E = 0.1, 0.35, 0.03
H = 1e-3  # step of the finite differences over the driver [rad]


def _d1(f, x, h=H):
    """df/dx by fourth-order central differences."""
    return (f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h)


def _slide(phi):
    """Slide of the offset crank-slider (guide along +x through (0, E)), written out."""
    return R * np.cos(phi) + np.sqrt(L_ROD**2 - (E - R * np.sin(phi)) ** 2)


def _crank_slider(**kw):
    return crank_slider_mechanism(R, L_ROD, E, masses=(1.0, 2.0, 3.0), **kw)


PHI = np.linspace(0.0, 2 * np.pi, 73)


# -- each element by hand ------------------------------------------------------------------------
def test_spring_tension_energy_and_power_by_hand():
    """Frame anchor K = (0.6, 0.2) to the slider's B: L, tension, V written out; the power
    -dV/dt by differences of the written-out V; the slider's load changes Q by the virtual
    work -F . dB/dphi."""
    K = (0.6, 0.2)
    k, L0, F0 = 2000.0, 0.3, 15.0
    mech = _crank_slider()

    def length(p):
        return np.hypot(K[0] - _slide(p), K[1] - E)

    def energy(p):
        x = length(p) - L0
        return F0 * x + 0.5 * k * x * x

    w = 7.0
    kin = kinematics(mech, PHI, w, 0.0)
    spring = Spring("frame", K, "slider", "B", stiffness=k, free_length=L0, preload=F0,
                    name="return")
    dyn = inverse_dynamics(kin, loads=[spring])
    d0 = inverse_dynamics(kin)
    ap = dyn.load("return")
    scale_f = np.max(np.abs(F0 + k * (length(PHI) - L0)))
    np.testing.assert_allclose(ap.length, length(PHI), rtol=0, atol=1e-12)
    np.testing.assert_allclose(ap.value, F0 + k * (length(PHI) - L0), rtol=0,
                               atol=1e-12 * scale_f)
    np.testing.assert_allclose(dyn.V, energy(PHI), rtol=0, atol=1e-12 * np.max(energy(PHI)))
    np.testing.assert_allclose(ap.energy, dyn.V, rtol=0, atol=0)
    p_hand = -_d1(energy, PHI) * w
    scale_p = np.max(np.abs(p_hand))
    np.testing.assert_allclose(dyn.load_power[0], p_hand, rtol=0, atol=1e-10 * scale_p)
    # the spring's force on B (along K - B, magnitude T) enters Q by virtual work
    T = F0 + k * (length(PHI) - L0)
    fx = T * (K[0] - _slide(PHI)) / length(PHI)
    dQ = -fx * _d1(_slide, PHI)  # Q omega1 + F . v_B = 0 for this load alone
    np.testing.assert_allclose(dyn.Q - d0.Q, dQ, rtol=0, atol=1e-9 * np.max(np.abs(dQ)))
    assert np.max(np.abs(dQ)) > 5.0  # the load matters (8.5 N m)


def test_damper_drag_and_slide_force_by_hand():
    """A damper between the crank's point (0.05, 0.02) and the slider's B, a drag on B
    (Coulomb 40 N, viscous 6 N s/m), a slide force of 25 N along the guide: tension, drag
    magnitude and every power written out (positions by trigonometry, rates by differences)."""
    c = 80.0
    w = 5.0
    mech = _crank_slider()
    kin = kinematics(mech, PHI, w, 0.0)
    loads = [Damper("crank", (0.05, 0.02), "slider", "B", damping=c),
             Drag("slider", "B", force=40.0, damping=6.0),
             SlideForce("G", force=25.0)]
    dyn = inverse_dynamics(kin, loads=loads)
    assert dyn.loads[0].name == "damper.0" and [a.kind for a in dyn.loads] == [
        "damper", "drag", "slide"]

    def pa(p):  # the crank's point (0.05, 0.02) in the world
        return np.array([0.05 * np.cos(p) - 0.02 * np.sin(p), 0.05 * np.sin(p) + 0.02 * np.cos(p)])

    def length(p):
        a = pa(p)
        return np.hypot(_slide(p) - a[0], E - a[1])

    Ld = _d1(length, PHI) * w
    v = _d1(_slide, PHI) * w  # the slider's speed along +x
    np.testing.assert_allclose(dyn.loads[0].value, c * Ld, rtol=0, atol=1e-10 * c * np.max(Ld))
    np.testing.assert_allclose(dyn.load_power[0], -c * Ld**2, rtol=0,
                               atol=1e-10 * c * np.max(Ld**2))
    width = SIGN_WIDTH * w * mech.plan.length_scale
    mag = 40.0 * np.abs(v) / np.sqrt(v * v + width * width) + 6.0 * np.abs(v)
    np.testing.assert_allclose(dyn.loads[1].value, mag, rtol=0, atol=1e-10 * np.max(mag))
    np.testing.assert_allclose(dyn.load_power[1], -mag * np.abs(v), rtol=0,
                               atol=1e-10 * np.max(mag * np.abs(v)))
    np.testing.assert_allclose(dyn.loads[2].value, 25.0)
    np.testing.assert_allclose(dyn.load_power[2], 25.0 * v, rtol=0, atol=1e-10 * 25 * w * R)
    assert np.all(dyn.load_power[:2] <= 0)
    # the drag is 40 N against the motion wherever the slider moves faster than 1e-6 m/s
    moving = np.abs(v) > 1e-6
    np.testing.assert_allclose(dyn.loads[1].value[moving], 40.0 + 6.0 * np.abs(v[moving]),
                               rtol=1e-9)


def test_zero_free_length_spring_through_its_anchor():
    """A zero-free-length spring pulls with -k d, defined where its points meet: anchored at
    the crank's pivot O, from the crank's own pin A it is a central force (no torque about O,
    so Q is unchanged) of magnitude k r."""
    mech = _crank_slider()
    kin = kinematics(mech, PHI)
    d0 = inverse_dynamics(kin)
    dyn = inverse_dynamics(kin, loads=[Spring("frame", "O", "crank", "A", stiffness=500.0)])
    np.testing.assert_allclose(dyn.Q, d0.Q, rtol=0, atol=1e-12 * np.max(np.abs(d0.Q)))
    np.testing.assert_allclose(dyn.loads[0].value, 500.0 * R, rtol=1e-12)
    np.testing.assert_allclose(dyn.V, 0.5 * 500.0 * R**2, rtol=1e-12)
    # a spring from O to the crank's origin (also O) meets its anchor everywhere: still 0
    Spring("frame", "O", "crank", (0.0, 0.0), stiffness=500.0)
    d2 = inverse_dynamics(kin, loads=[Spring("frame", "O", "crank", (0.0, 0.0),
                                             stiffness=500.0)])
    assert not np.any(d2.loads[0].value) and not np.any(d2.load_power)


# -- Newton-Euler per position ---------------------------------------------------------------
def _hand_point_forces(mech, q, v, elements):
    """The forces of springs, dampers and drags at one position, computed here from the poses
    q and the velocities v of the body origins, as point forces on the moving bodies (and the
    resultant and moment about O of those on the frame)."""
    idx = {n: i for i, n in enumerate(mech.body_names)}

    def at(body, point):
        i = idx[body]
        p = mech.body(body).point(point) if isinstance(point, str) else point
        if i == 0:
            return np.array(p, float), np.zeros(2)
        x, y, th = q[3 * i - 3:3 * i]
        c, s = math.cos(th), math.sin(th)
        r = np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])
        w = v[3 * i - 1]
        return np.array([x, y]) + r, v[3 * i - 3:3 * i - 1] + w * np.array([-r[1], r[0]])

    out, frame = [], [np.zeros(2), 0.0]

    def put(body, point, f, P):
        if body == mech.frame.name:
            frame[0] = frame[0] + f
            frame[1] += P[0] * f[1] - P[1] * f[0]
        else:
            # a point force at the body's local point of the world position P
            i = idx[body]
            x, y, th = q[3 * i - 3:3 * i]
            c, s = math.cos(th), math.sin(th)
            d = P - np.array([x, y])
            out.append(PointForce(body, (c * d[0] + s * d[1], -s * d[0] + c * d[1]),
                                  float(f[0]), float(f[1])))

    for el in elements:
        if isinstance(el, Spring | Damper):
            A, vA = at(el.a, el.point_a)
            B, vB = at(el.b, el.point_b)
            d = B - A
            L = float(np.hypot(*d))
            if isinstance(el, Spring):
                T = el.preload + el.stiffness * (L - el.free_length)
            else:
                T = el.damping * float(d @ (vB - vA)) / L
            put(el.b, el.point_b, -T * d / L, B)
            put(el.a, el.point_a, T * d / L, A)
        else:  # Drag, the point moving fast: the exact Coulomb direction
            P, vP = at(el.body, el.point)
            f = -el.force * vP / np.hypot(*vP) - el.damping * vP
            put(el.body, el.point, f, P)
    return out, frame


def _poses(kin):
    """q, v, a of every body origin (x, y, theta) at each position, from the engine."""
    n = kin.n
    q = np.stack([kin.x[1:], kin.y[1:], kin.theta[1:]], 1).transpose(2, 0, 1).reshape(n, -1)
    v = np.stack([kin.vx[1:], kin.vy[1:], kin.omega[1:]], 1).transpose(2, 0, 1).reshape(n, -1)
    a = np.stack([kin.ax[1:], kin.ay[1:], kin.eps[1:]], 1).transpose(2, 0, 1).reshape(n, -1)
    return q, v, a


CASES = {
    "crank-slider": (lambda: _crank_slider(), [
        Spring("frame", (0.6, 0.2), "slider", "B", stiffness=2000.0, free_length=0.3,
               preload=15.0),
        Damper("crank", (0.05, 0.02), "rod", "com", damping=120.0),
        Drag("rod", (0.1, 0.01), force=30.0, damping=4.0)]),
    "four-bar": (lambda: fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0)), [
        Spring("coupler", (0.1, 0.05), "rocker", "com", stiffness=800.0, free_length=0.12,
               preload=-20.0),
        Damper("frame", (0.1, 0.3), "coupler", "A", damping=60.0),
        Spring("frame", "O4", "coupler", (0.15, 0.0), stiffness=300.0, free_length=0.05),
        Drag("rocker", "B", force=12.0, damping=2.0)]),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_reactions_against_newton_euler_per_position(case):
    """Reactions, Q, shaking force and moment with springs, dampers and drags against the
    Newton-Euler equations of every body, assembled per position with Lagrange multipliers
    (tests/_planar_newton_euler.py), the elements' forces computed here from the poses; the
    motion is the engine's (checked against the raw constraints in test_dynamics); gravity,
    variable omega1, eps1 != 0; to 1e-9 of the largest reaction."""
    make, elements = CASES[case]
    mech = make()
    phi = np.linspace(0.1, 2 * np.pi + 0.1, 13)[:-1]
    w, e = 6.0 + np.cos(phi), -4.0 + 3 * np.sin(2 * phi)
    g = (0.0, -9.81)
    about = (0.05, -0.02)
    kin = kinematics(mech, phi, w, e)
    dyn = inverse_dynamics(kin, gravity=g, loads=elements, about=about)
    q, v, a = _poses(kin)
    for k in range(kin.n):
        # the drag's regularised direction equals the exact one to 1e-12 at these speeds
        loads, (ff, fm) = _hand_point_forces(mech, q[k], v[k], elements)
        ref = _newton_euler(mech, q[k], v[k], a[k], g, loads, about)
        F = max(np.max(np.abs(ref["fx"])), np.max(np.abs(ref["fy"])), 1.0)
        L = mech.plan.length_scale
        np.testing.assert_allclose(dyn.fx[:, k], ref["fx"], rtol=0, atol=1e-9 * F)
        np.testing.assert_allclose(dyn.fy[:, k], ref["fy"], rtol=0, atol=1e-9 * F)
        np.testing.assert_allclose(dyn.Q[k], ref["Q"], rtol=0, atol=1e-9 * F * L)
        # the elements' reactions on the frame join the shaking force and moment
        sf = ref["sf"] + ff
        sm = ref["sm"] + fm - (about[0] * ff[1] - about[1] * ff[0])
        np.testing.assert_allclose([dyn.shaking_fx[k], dyn.shaking_fy[k]], sf, rtol=0,
                                   atol=1e-9 * F)
        np.testing.assert_allclose(dyn.shaking_m[k], sm, rtol=0, atol=1e-9 * F * L)


# -- the power balance ---------------------------------------------------------------------------
def _elements(mech):
    """Elements for any mechanism of tests/_mechanisms.py: a spring from a frame point to the
    last body, a damper between the first and the last body, a drag on the second body, a
    slide force (its value a diagram over the driver) on the first line joint."""
    first, second, last = mech.bodies[0].name, mech.bodies[1].name, mech.bodies[-1].name
    out = [Spring("frame", (0.05, -0.4), last, "com", stiffness=900.0, free_length=0.2,
                  preload=8.0),
           Damper(first, (0.02, 0.01), last, (0.01, 0.03), damping=70.0),
           Drag(second, "com", force=15.0, damping=3.0)]
    line = [j for j in mech.joints if j.has_line and j.name != mech.driver.joint]
    if line:
        lo, hi = (0.0, 2 * np.pi) if mech.driver.kind == "crank" else (0.2, 0.5)
        out.append(SlideForce(line[0].name, LoadDiagram(np.linspace(lo, hi, 7),
                                                        [0, 40, -30, 80, 10, -5, 0])))
    return out


def _hand_powers(mech, phi, w, elements):
    """The power of each element written out: springs -dV/dt, dampers -c (dL/dt)^2 (V and L
    differentiated over the driver), drags -(F |v|^2/sqrt(|v|^2 + w^2) + c |v|^2), slide forces
    F ds/dt (the diagram interpolated here), with the positions of the engine at phi +- k h."""
    h = H if mech.driver.kind == "crank" else H * 0.1

    def pos(p):
        return kinematics(mech, p)

    shifted = {kk: pos(phi + kk * h) for kk in (-2, -1, 1, 2)}

    def d1(fun):
        return (fun(shifted[-2]) - 8 * fun(shifted[-1]) + 8 * fun(shifted[1])
                - fun(shifted[2])) / (12 * h) * w

    kin0 = pos(phi)
    out = []
    for el in elements:
        if isinstance(el, Spring | Damper):
            def length(kn, el=el):
                A, B = kn.point(el.a, el.point_a), kn.point(el.b, el.point_b)
                return np.hypot(B.x - A.x, B.y - A.y)
            if isinstance(el, Spring):
                def energy(kn, el=el):
                    x = length(kn) - el.free_length
                    return el.preload * x + 0.5 * el.stiffness * x * x
                out.append(-d1(energy))
            else:
                out.append(-el.damping * d1(length) ** 2)
        elif isinstance(el, Drag):
            vx = d1(lambda kn, el=el: kn.point(el.body, el.point).x)
            vy = d1(lambda kn, el=el: kn.point(el.body, el.point).y)
            sp2 = vx * vx + vy * vy
            width = SIGN_WIDTH * np.max(np.abs(w)) * (
                mech.plan.length_scale if mech.driver.kind == "crank" else 1.0)
            out.append(-(el.force * sp2 / np.sqrt(sp2 + width**2) + el.damping * sp2))
        else:  # SlideForce with a diagram over the driver
            d = el.force
            F = np.interp(phi, d.position, d.value)
            out.append(F * d1(lambda kn, el=el: kn.slide(el.joint)[0]))
    return kin0, out


@pytest.mark.parametrize("friction", [False, True], ids=["frictionless", "friction"])
@pytest.mark.parametrize("builder", BUILDERS, ids=lambda b: b.__name__)
def test_power_balance_with_springs_dampers_drag_and_diagram(builder, friction):
    """Q omega1 = dT/dt - sum P_loads(hand) - P_gravity + sum P_friction on every group kind,
    variable omega1 and eps1 != 0, gravity, to 1e-9 of the largest term; the elements' powers
    are the hand ones (each also equal to the engine's load_power to 1e-9)."""
    mech, phi, _ = builder()
    if friction:
        mech = with_friction(mech)
    span = phi[-1] - phi[0]
    w = (6.0 + np.cos(2 * np.pi * (phi - phi[0]) / span)) * (1 if mech.driver.kind == "crank"
                                                              else 0.1)
    e = 2.0 * np.sin(2 * np.pi * (phi - phi[0]) / span) * (1 if mech.driver.kind == "crank"
                                                            else 0.1)
    g = (0.0, -9.81)
    elements = _elements(mech)
    kin = kinematics(mech, phi, w, e)
    dyn = inverse_dynamics(kin, gravity=g, loads=elements)
    assert not dyn.locked.any()
    _, hand = _hand_powers(mech, phi, w, elements)
    dT, pg = kinetic_energy_rate(mech, kin, g)
    pl = np.sum(hand, axis=0)
    lhs = dyn.Q * kin.omega1
    rhs = dT - pl - pg + dyn.friction_power.sum(axis=0)
    scale = max(np.max(np.abs(lhs)), np.max(np.abs(dT)), np.max(np.abs(pl)), np.max(np.abs(pg)))
    assert np.max(np.abs(lhs - rhs)) <= 1e-9 * scale
    for k, p in enumerate(hand):
        assert np.max(np.abs(dyn.load_power[k] - p)) <= 1e-9 * scale, dyn.loads[k].name
    assert np.max(np.abs(pl)) > 1e-2 * scale  # the elements matter


@settings(max_examples=25, deadline=None)
@given(k=st.floats(0.0, 5e4), L0=st.floats(0.0, 0.8), F0=st.floats(-200.0, 200.0),
       c=st.floats(0.0, 500.0), ax=st.floats(-0.5, 0.5), ay=st.floats(-0.5, 0.5))
def test_power_balance_property_of_a_spring_and_damper(k, L0, F0, c, ax, ay):
    """For any rate, free length, preload, damping and frame anchor: the driving power of the
    crank-slider equals the rate of its kinetic energy less the spring's power -dV/dt (V by
    hand, differenced) less the damper's -c (dL/dt)^2, to 1e-9 of the largest term."""
    mech = _crank_slider()
    anchor = (0.3 + ax, 0.6 + ay)  # never on the slider's path (y = E)
    els = [Spring("frame", anchor, "slider", "B", stiffness=k, free_length=L0, preload=F0),
           Damper("frame", anchor, "rod", "com", damping=c)]
    w = 9.0
    kin = kinematics(mech, PHI, w, 0.0)
    dyn = inverse_dynamics(kin, loads=els)
    _, hand = _hand_powers(mech, PHI, np.full(PHI.shape, w), els)
    dT, _ = kinetic_energy_rate(mech, kin)
    lhs, rhs = dyn.Q * w, dT - hand[0] - hand[1]
    scale = max(np.max(np.abs(lhs)), np.max(np.abs(dT)), np.max(np.abs(hand)), 1e-6)
    assert np.max(np.abs(lhs - rhs)) <= 1e-9 * scale


def test_potential_energy_differences_give_the_spring_power():
    """dV/dt of the reported V (differences over the positions of one call, fourth order)
    equals minus the springs' reported power: V is the energy whose loss they deliver."""
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0))
    h = 2 * np.pi / 2000
    phi = np.arange(2000) * h
    kin = kinematics(mech, phi, 4.0, 0.0)
    springs = [Spring("frame", (0.0, 0.25), "coupler", (0.2, 0.02), stiffness=1500.0,
                      free_length=0.1, preload=3.0),
               Spring("crank", "A", "rocker", "com", stiffness=400.0, free_length=0.3)]
    dyn = inverse_dynamics(kin, loads=springs)
    V = dyn.V
    dV = (np.roll(V, 2) - 8 * np.roll(V, 1) + 8 * np.roll(V, -1) - np.roll(V, -2)) / (12 * h)
    p = dyn.load_power.sum(axis=0)
    assert np.max(np.abs(dV * 4.0 + p)) <= 1e-9 * np.max(np.abs(p))
    # V is the sum of the springs' energies
    np.testing.assert_array_equal(V, dyn.loads[0].energy + dyn.loads[1].energy)


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda b: b.__name__)
def test_internal_elements_do_not_shake_the_frame(builder):
    """Springs and dampers (to the frame or between moving bodies) are internal to the
    machine: without gravity and other loads F_sh = -sum m a_C and M_sh = -dH_O/dt as without
    them, while Q and the reactions change. A drag acts from outside (its force adds to F_sh)
    unless it is marked from_frame."""
    mech, phi, _ = builder()
    kin = kinematics(mech, phi, 5.0 if mech.driver.kind == "crank" else 0.5, 0.0)
    d0 = inverse_dynamics(kin)
    els = _elements(mech)
    internal = [x for x in els if not isinstance(x, Drag)]
    d1 = inverse_dynamics(kin, loads=internal)
    scale = max(np.max(np.abs(d1.fx)), np.max(np.abs(d1.fy)))
    for name in ("shaking_fx", "shaking_fy"):
        np.testing.assert_allclose(getattr(d1, name), getattr(d0, name), rtol=0,
                                   atol=1e-9 * scale)
    np.testing.assert_allclose(d1.shaking_m, d0.shaking_m, rtol=0,
                               atol=1e-9 * scale * mech.plan.length_scale)
    assert np.max(np.abs(d1.Q - d0.Q)) > 1e-3 * np.max(np.abs(d1.Q))
    drag = next(x for x in els if isinstance(x, Drag))
    d2 = inverse_dynamics(kin, loads=[drag])
    ap = d2.loads[0]
    fx = sum(wr.fx for wr in ap.wrenches)
    fy = sum(wr.fy for wr in ap.wrenches)
    np.testing.assert_allclose(d2.shaking_fx - d0.shaking_fx, fx, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(d2.shaking_fy - d0.shaking_fy, fy, rtol=0, atol=1e-9 * scale)
    d3 = inverse_dynamics(kin, loads=[Drag(drag.body, drag.point, drag.force, drag.damping,
                                           from_frame=True)])
    np.testing.assert_allclose(d3.shaking_fx, d0.shaking_fx, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(d3.Q, d2.Q, rtol=0, atol=0)


# -- load diagrams ---------------------------------------------------------------------------
def _press():
    """The crank-slider standing up: the ram slides along +y (guide at 90 deg, offset 0), its
    slide s = r sin(phi) + sqrt(l^2 - r^2 cos^2(phi)) lowest at phi = 270 deg."""
    return crank_slider_mechanism(R, L_ROD, 0.0, guide_angle=np.pi / 2, masses=(1.0, 2.0, 30.0))


def _ram(phi):
    return R * np.sin(phi) + np.sqrt(L_ROD**2 - (R * np.cos(phi)) ** 2)


def test_press_force_over_the_last_20_mm_while_the_ram_moves_down():
    """The technological force rises linearly from 0 at 20 mm above the bottom of the stroke
    to 10 kN at the bottom, against the descent (along +u, up), only while the ram moves down
    (ds/dt <= 0) and inside the table: value by hand; its effect on Q by virtual work."""
    s_min = L_ROD - R
    diagram = LoadDiagram([s_min, s_min + 0.02], [10e3, 0.0], over="G", when="decreasing")
    phi = np.radians(np.arange(0.0, 360.0, 0.5))
    w = 10.0
    mech = _press()
    kin = kinematics(mech, phi, w, 0.0)
    d0 = inverse_dynamics(kin)
    dyn = inverse_dynamics(kin, loads=[SlideForce("G", diagram, name="press")])
    s = _ram(phi)
    sd = _d1(_ram, phi) * w
    down = sd <= 1e-9 * w * R
    inside = s <= s_min + 0.02
    F = np.where(down & inside, 10e3 * (s_min + 0.02 - s) / 0.02, 0.0)
    ap = dyn.load("press")
    np.testing.assert_allclose(ap.value, F, rtol=0, atol=1e-9 * 10e3)
    assert np.count_nonzero(F) > 20 and np.all(F[phi < np.pi] == 0)  # acts on the way down
    assert ap.value[np.argmin(np.abs(phi - 1.5 * np.pi))] == pytest.approx(10e3, rel=1e-12)
    np.testing.assert_allclose(dyn.Q - d0.Q, -F * sd / w, rtol=0, atol=1e-9 * 10e3 * R)
    # the reaction on the frame at the bed: not in the shaking force
    np.testing.assert_allclose(dyn.shaking_fy, d0.shaking_fy, rtol=0, atol=1e-9 * 10e3)
    # while moving up (or over the whole table) the same table acts elsewhere
    up = inverse_dynamics(kin, loads=[SlideForce("G", LoadDiagram(
        diagram.position, diagram.value, over="G", when="increasing"))]).loads[0].value
    ups = (sd >= -1e-9 * w * R) & inside
    np.testing.assert_allclose(up, np.where(ups, 10e3 * (s_min + 0.02 - s) / 0.02, 0.0),
                               rtol=0, atol=1e-9 * 10e3)



def _sixbar():
    """A Stephenson-type six-bar: four-bar O2-A-B-O4 whose ternary coupler carries C, and the
    dyad C-D-O6 (link5, rocker6); friction circles (f 0.10..0.13, radii 12..30 mm) in all
    seven revolutes."""
    from linkwork.planar import Body, Crank, Mechanism, Revolute, bar

    frame = Body("frame", {"O2": (0, 0), "O4": (0.30, 0.0), "O6": (0.05, 0.35)})
    bodies = (bar("crank", "O2", "A", 0.10, mass=1.0),
              Body("coupler", {"A": (0, 0), "B": (0.28, 0), "C": (0.12, 0.15),
                               "K": (0.2, -0.05)}, mass=3.0, com=(0.13, 0.04), inertia=0.03),
              bar("rocker", "O4", "B", 0.22, mass=2.0),
              bar("link5", "C", "D", 0.30, mass=1.5, points={"H": (0.1, 0.02)}),
              Body("rocker6", {"O6": (0, 0), "D": (0.25, 0), "S": (0.15, 0.04)}, mass=1.8,
                   com=(0.11, 0.01), inertia=0.015))
    pairs = [("O2", "frame", "crank"), ("A", "crank", "coupler"), ("B", "coupler", "rocker"),
             ("O4", "frame", "rocker"), ("C", "coupler", "link5"), ("D", "link5", "rocker6"),
             ("O6", "frame", "rocker6")]
    radii = (0.02, 0.03, 0.012, 0.025, 0.02, 0.015, 0.018)
    joints = tuple(Revolute(n, a, b, friction=0.1 + 0.005 * i, radius=radii[i])
                   for i, (n, a, b) in enumerate(pairs))
    return Mechanism(frame, bodies, joints, Crank("O2", omega1=6.0), {"B": 1, "D": -1})


def test_sixbar_spring_and_damper_between_moving_links_with_friction_by_hand():
    """A spring from the coupler's K to rocker 6's S and a damper from a point of the crank to
    link 5's H (each between two moving links), Coulomb friction in all seven joints, gravity,
    omega1 = 6 rad/s, eps1 = 1.5 rad/s^2: the spring's tension F0 + k (L - L0) and the
    damper's c dL/dt written out from the poses, then the 15 Newton-Euler equations of the
    five links (each joint's friction couple f r |R| against its relative rotation) solved per
    position by fsolve, against the engine: Q and every reaction to 1e-9 of their scale. The
    poses are the engine's; its velocities are checked here against finite differences."""
    fsolve = pytest.importorskip("scipy.optimize").fsolve
    mech = _sixbar()
    k_, L0, F0, c_ = 4000.0, 0.12, 150.0, 60.0
    loads = [Spring("coupler", "K", "rocker6", "S", stiffness=k_, free_length=L0, preload=F0,
                    name="spring"),
             Damper("crank", (0.06, 0.01), "link5", "H", damping=c_, name="damper")]
    phi = np.radians(np.arange(1.0, 360.0, 15.0))
    g = np.array([0.0, -9.81])
    kin = kinematics(mech, phi, omega1=6.0, eps1=1.5)
    dyn = inverse_dynamics(kin, gravity=tuple(g), loads=loads)
    kp, km = (kinematics(mech, phi + d, omega1=6.0, eps1=1.5) for d in (1e-6, -1e-6))
    np.testing.assert_allclose((kp.theta - km.theta) / 2e-6 * 6.0, kin.omega, atol=1e-7)
    np.testing.assert_allclose((kp.x - km.x) / 2e-6 * 6.0, kin.vx, atol=1e-8)
    body = {b.name: b for b in mech.bodies}
    idx = mech.index

    def point(name, p, k):
        """Position, velocity and acceleration of a point of a body (or of the frame)."""
        if name == "frame":
            return np.array(mech.frame.point(p)), np.zeros(2), np.zeros(2)
        i = idx[name]
        c, sn = np.cos(kin.theta[i, k]), np.sin(kin.theta[i, k])
        lp = body[name].point(p) if isinstance(p, str) else p
        rp = np.array([c * lp[0] - sn * lp[1], sn * lp[0] + c * lp[1]])
        w, al = kin.omega[i, k], kin.eps[i, k]
        return (np.array([kin.x[i, k], kin.y[i, k]]) + rp,
                np.array([kin.vx[i, k], kin.vy[i, k]]) + w * _perp(rp),
                np.array([kin.ax[i, k], kin.ay[i, k]]) + al * _perp(rp) - w**2 * rp)

    def omega(name, k):
        return 0.0 if name == "frame" else kin.omega[idx[name], k]

    for k in range(phi.size):
        PK, PS = point("coupler", "K", k)[0], point("rocker6", "S", k)[0]
        L = np.hypot(*(PS - PK))
        T = F0 + k_ * (L - L0)
        (P1, v1, _), (PH, vH, _) = point("crank", (0.06, 0.01), k), point("link5", "H", k)
        ud = (PH - P1) / np.hypot(*(PH - P1))
        TD = c_ * ud @ (vH - v1)
        assert dyn.load("spring").value[k] == pytest.approx(T, rel=1e-12)
        assert dyn.load("damper").value[k] == pytest.approx(TD, rel=1e-9, abs=1e-9)
        ext = [("coupler", PK, T * (PS - PK) / L), ("rocker6", PS, -T * (PS - PK) / L),
               ("crank", P1, TD * ud), ("link5", PH, -TD * ud)]

        def eqs(x, k=k, ext=ext):
            F = {n: np.zeros(2) for n in body}
            M = {n: 0.0 for n in body}                   # about each body's origin
            for j, jt in enumerate(mech.joints):
                Rv = x[2 * j:2 * j + 2]
                P = point(jt.b, jt.name, k)[0]
                Mf = -jt.friction * jt.radius * np.hypot(*Rv) * np.sign(
                    omega(jt.b, k) - omega(jt.a, k))
                for name, sg in ((jt.b, 1.0), (jt.a, -1.0)):
                    if name != "frame":
                        o = point(name, (0.0, 0.0), k)[0]
                        F[name] = F[name] + sg * Rv
                        M[name] += sg * (_cross(P - o, Rv) + Mf)
            for name, P, f in ext:
                o = point(name, (0.0, 0.0), k)[0]
                F[name] = F[name] + f
                M[name] += _cross(P - o, f)
            M["crank"] += x[14]
            out = []
            for name, b in body.items():
                o = point(name, (0.0, 0.0), k)[0]
                C, _, aC = point(name, "com", k)
                out += [*(F[name] + b.mass * (g - aC)),
                        M[name] + _cross(C - o, b.mass * (g - aC))
                        - b.inertia * kin.eps[idx[name], k]]
            return out

        x = fsolve(eqs, np.zeros(15), xtol=1e-13, full_output=True)[0]
        x = fsolve(eqs, x, xtol=1e-13, full_output=True)[0]
        scale = np.abs(x[:14]).max()
        assert np.max(np.abs(eqs(x))) < 1e-10 * scale
        assert dyn.Q[k] == pytest.approx(x[14], abs=1e-9 * scale * 0.1)
        np.testing.assert_allclose(dyn.fx[:, k], x[0:14:2], atol=1e-9 * scale)
        np.testing.assert_allclose(dyn.fy[:, k], x[1:14:2], atol=1e-9 * scale)


def test_diagram_over_a_turning_slot_acts_when_its_slide_increases():
    """A slide force given as a table over the slide of a pin in a turning slot (the slotted
    lever: s = |A - O4| written out, ds/dt = (A - O4) . vA / s), with when = increasing and
    decreasing: its value is the table interpolated at s where ds/dt >= 0 (<= 0), at the two
    dead centres of s (phi1 = 90, 270 deg, in the positions) for both; its power F ds/dt
    changes the driving torque by exactly -F ds/dt / omega1 (virtual work), to 1e-12."""
    from linkwork.planar import Body, Crank, Mechanism, PinInSlot, Revolute, bar

    frame = Body("frame", {"O2": (0.0, 0.0), "O4": (0.0, -0.25)})
    mech = Mechanism(frame, (bar("crank", "O2", "A", 0.1, mass=1.2),
                             Body("lever", {"O4": (0, 0)}, mass=3.0, com=(0.18, 0),
                                  inertia=0.04)),
                     (Revolute("O2", "frame", "crank"), Revolute("O4", "frame", "lever"),
                      PinInSlot("S", "lever", "crank", angle=0.0, through="O4", point="A")),
                     Crank("O2", omega1=8.0))
    phi = np.radians(np.arange(0.0, 360.0, 2.5))
    kin = kinematics(mech, phi)
    d0 = inverse_dynamics(kin)
    A = 0.1 * np.stack([np.cos(phi), np.sin(phi)])
    D = A - np.array([[0.0], [-0.25]])
    s = np.hypot(*D)
    sd = np.sum(D * 8.0 * 0.1 * np.stack([-np.sin(phi), np.cos(phi)]), axis=0) / s
    table = ([0.14, 0.26, 0.3, 0.36], [100.0, 400.0, -50.0, 300.0])
    full = np.interp(s, *table, left=0.0, right=0.0)
    rest = np.isin(np.round(np.degrees(phi), 9), (90.0, 270.0))
    assert np.abs(sd[rest]).max() < 1e-12 and full[rest].min() > 0
    for when, acts in (("increasing", (sd > 0) | rest), ("decreasing", (sd < 0) | rest)):
        d = LoadDiagram(*table, over="S", when=when)
        dyn = inverse_dynamics(kin, loads=[SlideForce("S", d, name="F")])
        F = np.where(acts, full, 0.0)
        np.testing.assert_allclose(dyn.load("F").value, F, atol=1e-9)
        np.testing.assert_allclose(dyn.Q - d0.Q, -F * sd / 8.0, atol=1e-12 * 400)

def test_diagram_outside_its_range_is_zero_or_refused():
    s_min = L_ROD - R
    mech = _press()
    kin = kinematics(mech, np.radians(np.arange(0.0, 360.0, 5.0)))
    table = ([s_min, s_min + 0.02], [10e3, 0.0])
    with pytest.raises(ParameterError, match=r"loads\[0\]\.force\.position = \[0\.25, 0\.27\] m "
                       r"is invalid: the analysis leaves this range of the diagram over "
                       r"the slide of G while the load acts, at phi1 in .*no extrapolation"):
        inverse_dynamics(kin, loads=[SlideForce("G", LoadDiagram(*table, over="G",
                                                                 outside="error"))])
    # refused only where it would act: up the stroke a downward-only diagram is silent
    full = LoadDiagram([s_min, L_ROD + R], [1.0, 2.0], over="G", when="decreasing",
                       outside="error")
    inverse_dynamics(kin, loads=[SlideForce("G", full)])


def test_diagram_over_the_crank_angle_repeats_every_turn():
    """A couple on the crank from a table over 100..150 deg: at phi and phi + 360 deg the same
    value (linear by hand), zero outside; a table given from -30 to 30 deg wraps through 0."""
    mech = _crank_slider()
    phi = np.radians(np.arange(-360.0, 720.0, 2.5))
    kin = kinematics(mech, phi)
    d = LoadDiagram(np.radians([100.0, 150.0]), [5.0, 15.0])
    dyn = inverse_dynamics(kin, loads=[BodyTorque("crank", d)])
    deg = np.mod(np.degrees(phi), 360.0)
    hand = np.where((deg >= 100 - 1e-9) & (deg <= 150 + 1e-9), 5.0 + (deg - 100.0) / 5.0, 0.0)
    np.testing.assert_allclose(dyn.loads[0].value, hand, rtol=0, atol=1e-12)
    wrap = LoadDiagram(np.radians([-30.0, 30.0]), [1.0, 1.0])
    dw = inverse_dynamics(kin, loads=[PointForce("crank", "A", fx=wrap.times(3.0))])
    near = (deg <= 30 + 1e-9) | (deg >= 330 - 1e-9)
    np.testing.assert_allclose(dw.loads[0].value, np.where(near, 3.0, 0.0), rtol=0, atol=1e-12)
    # a position a round-off below the table's start is at its start, not a turn later
    k2 = kinematics(mech, [-1e-15, 0.0, 1e-15, np.radians(100.0) - 1e-13])
    edge = inverse_dynamics(k2, loads=[BodyTorque("crank", LoadDiagram([0.0, 0.5], [2.0, 3.0])),
                                       BodyTorque("crank", d)])
    np.testing.assert_allclose(edge.loads[0].value, [2.0, 2.0, 2.0, 0.0], rtol=1e-12)
    np.testing.assert_allclose(edge.loads[1].value, [0.0, 0.0, 0.0, 5.0], rtol=1e-12)


def test_diagram_over_a_linear_drivers_slide():
    from _mechanisms import m_linear_driver

    mech, phi, _ = m_linear_driver()
    kin = kinematics(mech, phi)
    d = LoadDiagram([0.3, 0.4], [0.0, 50.0])
    dyn = inverse_dynamics(kin, loads=[SlideForce("G", d)])
    hand = np.where((phi >= 0.3 - 1e-12) & (phi <= 0.4 + 1e-12), 500.0 * (phi - 0.3), 0.0)
    np.testing.assert_allclose(dyn.loads[0].value, hand, rtol=0, atol=1e-9 * 50)
    d0 = inverse_dynamics(kin)
    # the force along the driven guide adds to the driving force with the opposite sign
    np.testing.assert_allclose(dyn.Q - d0.Q, -hand, rtol=0, atol=1e-9 * 50)


# -- bad input -------------------------------------------------------------------------------
@pytest.mark.parametrize("make, match", [
    (lambda: Spring("frame", "O", "slider", "B", stiffness=-5.0),
     r"^stiffness = -5(\.0)? is invalid: must be >= 0"),
    (lambda: Spring("frame", "O", "slider", "B", stiffness=5.0, free_length=-0.1),
     r"^free_length = -0\.1 is invalid: must be >= 0"),
    (lambda: Spring("frame", "O", "slider", "B", stiffness=5.0, preload=np.nan),
     r"^preload = nan is invalid: must be finite"),
    (lambda: Damper("frame", "O", "slider", "B", damping=-1.0),
     r"^damping = -1(\.0)? is invalid: must be >= 0"),
    (lambda: Drag("slider", "B", force=-3.0), r"^force = -3(\.0)? is invalid: must be >= 0"),
    (lambda: Spring("frame", "O", "slider", "B", stiffness=[1.0, 2.0]),
     r"^stiffness = .* must be a single number"),
    (lambda: LoadDiagram([0.0, 0.02, 0.02], [1.0, 2.0, 3.0]),
     r"^position\[2\] = 0\.02 is invalid: must increase strictly: it must be > "
     r"position\[1\] = 0\.02"),
    (lambda: LoadDiagram([0.0, -0.1], [1.0, 2.0]), r"^position\[1\] = -0\.1 .*increase"),
    (lambda: LoadDiagram([0.0], [1.0]), r"^position = \[0\.0\] .*at least 2 positions"),
    (lambda: LoadDiagram([0.0, 1.0], [1.0, 2.0, 3.0]), r"^value = 3 values .*one value per"),
    (lambda: LoadDiagram([0.0, np.inf], [1.0, 2.0]), r"^position = inf .*finite"),
    (lambda: LoadDiagram([0.0, 1.0], [1.0, 2.0], when="down"), r"^when = down .*'decreasing'"),
    (lambda: LoadDiagram([0.0, 1.0], [1.0, 2.0], outside="extrapolate"),
     r"^outside = extrapolate .*no extrapolation"),
    (lambda: LoadDiagram("abc", [1.0, 2.0]), r"^position = abc .*sequence of numbers"),
])
def test_bad_element_parameters(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


@pytest.fixture(scope="module")
def cs_kin():
    return kinematics(_crank_slider(), PHI)


@pytest.mark.parametrize("loads, match", [
    ([SlideForce("G", LoadDiagram([0.0, 1.0], [1.0, 2.0], over="A"))],
     r"^loads\[0\]\.force\.over = A is invalid: must be a prismatic or pin-in-slot joint "
     r"\(a slide position\), or 'driver'; this joint is Revolute"),
    ([SlideForce("G", LoadDiagram([0.0, 1.0], [1.0, 2.0], over="X"))],
     r"^loads\[0\]\.force\.over = X .*known: \['O', 'A', 'B', 'G'\]"),
    ([SlideForce("A", 3.0)], r"^loads\[0\]\.joint = A .*prismatic or pin-in-slot .*Revolute"),
    ([BodyTorque("crank", LoadDiagram([0.0, 7.0], [1.0, 2.0]))],
     r"^loads\[0\]\.mz\.position = 401.07 deg span .*at most one turn"),
    ([Spring("crank", "A", "crank", "O", stiffness=1.0)], r"^loads\[0\]\.b = crank .*differ"),
    ([Spring("frame", "Z", "rod", "B", stiffness=1.0)],
     r"^loads\[0\]\.point_a = Z is invalid: no such point of body 'frame'"),
    ([Damper("frame", "O", "arm", "B", damping=1.0)], r"^loads\[0\]\.b = arm .*no such body"),
    ([Drag("frame", "O", force=1.0)], r"^loads\[0\]\.body = frame .*moving bodies"),
    ([Spring("frame", "O", "crank", "A", stiffness=1.0, name="s"),
      Damper("frame", "O", "rod", "B", damping=1.0, name="s")],
     r"^loads\[1\]\.name = s .*unique"),
    ([Spring("frame", "O", "crank", (0.0, 0.0), stiffness=1.0, free_length=0.1)],
     r"^loads\[0\] = loads\[0\] is invalid: its points 'O' of 'frame' and \(0\.0, 0\.0\) of "
     r"'crank' coincide at phi1 in \[0, 360 deg\], where the direction of its force is "
     r"undefined"),
    ([Damper("crank", "A", "rod", "A", damping=2.0, name="d")],
     r"^loads\[0\] = d is invalid: its points 'A' of 'crank' and 'A' of 'rod' coincide"),
    ([PointForce("crank", "A", fx=[1.0, 2.0])], r"^loads\[0\]\.fx = \(2,\)"),
])
def test_loads_that_do_not_fit_the_mechanism_are_named(cs_kin, loads, match):
    with pytest.raises(ParameterError, match=match):
        inverse_dynamics(cs_kin, loads=loads)


@pytest.mark.parametrize("case", sorted(CASES))
def test_chunks_of_positions_give_the_same_loads_and_reactions(case, monkeypatch):
    """inverse_dynamics in chunks of 7 positions (the loads evaluated over the whole cycle,
    then sliced) gives the unchunked result bit for bit: reactions, Q, shaking, every load's
    value, power, energy, length, and load_power, V; with a press-force diagram that acts only
    on the way down (its band of rest from the whole cycle) and a varying driver speed."""
    import linkwork.planar.dynamics as dynamics

    make, elements = CASES[case]
    mech = make()
    phi = np.linspace(0.1, 2 * np.pi + 0.1, 61)[:-1]
    w, e = 6.0 + np.cos(phi), -4.0 + 3 * np.sin(2 * phi)
    kin = kinematics(mech, phi, w, e)
    loads = list(elements)
    if case == "crank-slider":
        loads.append(SlideForce("G", LoadDiagram([0.0, 0.5], [2e3, 0.0], over="G",
                                                 when="decreasing"), name="press"))
    whole = inverse_dynamics(kin, gravity=(0.0, -9.81), loads=loads, about=(0.05, -0.02))
    monkeypatch.setattr(dynamics, "CHUNK", 7)
    chunked = inverse_dynamics(kin, gravity=(0.0, -9.81), loads=loads, about=(0.05, -0.02))
    for name in ("fx", "fy", "mz", "px", "py", "Q", "shaking_fx", "shaking_fy", "shaking_m",
                 "T", "load_power", "V"):
        assert np.array_equal(getattr(whole, name), getattr(chunked, name), equal_nan=True), name
    assert [ap.name for ap in chunked.loads] == [ap.name for ap in whole.loads]
    for a, b in zip(whole.loads, chunked.loads, strict=True):
        for f in ("value", "power", "energy"):
            assert np.array_equal(getattr(a, f), getattr(b, f)), (a.name, f)
    assert np.any(whole.load_power != 0)


def _perp(v):
    return np.array([-v[1], v[0]])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]
