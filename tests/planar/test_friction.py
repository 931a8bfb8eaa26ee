"""Coulomb friction in the planar engine's joints (linkwork.planar.friction, joints.py).

References, none produced by the code under test:

* the frictionless engine at f = 0, bit for bit (``np.array_equal``);
* the power balance ``Q omega1 = dT/dt - P_loads + sum friction_power``, with ``dT/dt``
  written here from the kinematics (``sum m a_C . v_C + I omega eps``), to 1e-9 relative, on
  every group kind of ``tests/_mechanisms.py`` with friction in every joint;
* each joint's friction law checked on the solution (friction = f x normal force, against the
  relative velocity; the friction circle ``f r |R|``);
* a crank-slider and a four-bar with friction solved from scratch here: the Newton-Euler
  equations of each link written by hand and solved per position with
  ``scipy.optimize.fsolve`` (rtol 1e-9);
* self-locking reported and undefined near paper 000's jamming limit (the limit itself over
  alpha against the closed form: ``tests/planar/test_self_locking.py``).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from _mechanisms import BUILDERS, kinetic_energy_rate, sine_mechanism, with_friction

from linkwork.errors import ParameterError
from linkwork.models import sine
from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    Linear,
    Mechanism,
    PinInSlot,
    PointForce,
    Prismatic,
    Revolute,
    bar,
    crank_slider_mechanism,
    fourbar_mechanism,
    inverse_dynamics,
    kinematics,
)

FIELDS = ("fx", "fy", "mz", "px", "py", "Q", "shaking_fx", "shaking_fy", "shaking_m", "T")


def _loads(mech: Mechanism, kin) -> list[PointForce]:
    """A load on the last body against its motion, and a constant one on the first."""
    last = mech.bodies[-1].name
    v = kin.point(last, "com")
    return [PointForce(last, "com", fx=-300.0 * np.tanh(v.vx / 0.01), fy=-100.0),
            PointForce(mech.bodies[0].name, "com", fx=20.0, fy=-40.0)]


def _power_balance(mech, kin, dyn, loads, g):
    """Residual of Q omega1 = dT/dt - P_loads - P_gravity + sum friction_power, and its scale."""
    dT, pl = kinetic_energy_rate(mech, kin, g)
    for ld in loads:
        p = kin.point(ld.body, ld.point)
        pl += np.asarray(ld.fx) * p.vx + np.asarray(ld.fy) * p.vy
    lhs = dyn.Q * kin.omega1
    rhs = dT - pl + dyn.friction_power.sum(axis=0)
    scale = max(np.max(np.abs(lhs)), np.max(np.abs(dT)), np.max(np.abs(pl)))
    return np.max(np.abs(lhs - rhs)), scale


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda b: b.__name__)
def test_zero_friction_is_todays_result_bit_for_bit(builder):
    """f = 0 (with a journal radius and a block length given) is the frictionless engine."""
    mech, phi, _ = builder()
    m0 = with_friction(mech, f_rev=0.0, f_line=0.0)
    g = (0.0, -9.81)
    k, k0 = kinematics(mech, phi), kinematics(m0, phi)
    d = inverse_dynamics(k, gravity=g, loads=_loads(mech, k))
    d0 = inverse_dynamics(k0, gravity=g, loads=_loads(mech, k0))
    for name in FIELDS:
        assert np.array_equal(getattr(d, name), getattr(d0, name), equal_nan=True), name
    assert np.array_equal(d0.Q_frictionless, d0.Q)
    assert not d0.friction_power.any() and not d0.locked.any() and d0.friction_iterations == 0


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda b: b.__name__)
def test_power_balance_with_friction(builder):
    """Driving power = dT/dt - power of loads and gravity + sum of the friction powers, with
    friction in every joint of every group kind (inertia, gravity, loads), to 1e-9."""
    mech, phi, _ = builder()
    mf = with_friction(mech)
    kin = kinematics(mf, phi)
    g = (0.0, -9.81)
    loads = _loads(mf, kin)
    dyn = inverse_dynamics(kin, gravity=g, loads=loads)
    assert not dyn.locked.any()
    assert np.all(dyn.friction_power >= 0)
    assert dyn.friction_power.sum() > 0
    res, scale = _power_balance(mf, kin, dyn, loads, g)
    assert res <= 1e-9 * scale
    # friction changes the result (the test would not see a solver that ignored it)
    assert np.max(np.abs(dyn.Q - dyn.Q_frictionless)) > 1e-4 * np.max(np.abs(dyn.Q))


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda b: b.__name__)
def test_friction_does_not_shake_the_frame(builder):
    """Friction is internal to the machine (frame included): the shaking force and moment,
    the resultant of the frame-joint reactions and the motor's reaction, equal the
    frictionless ones to round-off, although every reaction and Q changed."""
    mech, phi, _ = builder()
    mf = with_friction(mech)
    k0, k1 = kinematics(mech, phi), kinematics(mf, phi)
    g = (0.0, -9.81)
    d0 = inverse_dynamics(k0, gravity=g, loads=_loads(mech, k0))
    d1 = inverse_dynamics(k1, gravity=g, loads=_loads(mf, k1))
    for name in ("shaking_fx", "shaking_fy", "shaking_m"):
        a, b = getattr(d1, name), getattr(d0, name)
        assert np.max(np.abs(a - b)) <= 1e-11 * max(np.max(np.abs(b)), 1.0), name


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda b: b.__name__)
def test_each_joint_obeys_its_friction_law(builder):
    """On the solution: revolute couple = f r |R| + M0 against omega_b - omega_a (friction
    circle); prismatic force along the guide = f (|N1| + |N2|) against the slide; pin-in-slot
    force = f |N| against the slip at the contact, couple -r f N sign(slip)."""
    mech, phi, _ = builder()
    mf = with_friction(mech, torque=0.02)
    kin = kinematics(mf, phi)
    dyn = inverse_dynamics(kin, gravity=(0.0, -9.81), loads=_loads(mf, kin))
    st_w = {b: kin.omega[mf.index[b]] for b in mf.body_names}
    for k, j in enumerate(mf.joints):
        dw = st_w[j.b] - st_w[j.a]
        ffx, ffy, fmz = dyn.friction_fx[k], dyn.friction_fy[k], dyn.friction_mz[k]
        if isinstance(j, Revolute):
            R = np.hypot(dyn.fx[k], dyn.fy[k])
            moving = np.abs(dw) > 0.05 * np.max(np.abs(dw))  # the smooth sign is +-1 there
            assert np.allclose(np.abs(fmz[moving]), (j.friction * j.radius * R + 0.02)[moving],
                               rtol=1e-9)
            assert np.all(fmz[moving] * dw[moving] < 0)
            assert not ffx.any() and not ffy.any()
            continue
        th_a = kin.theta[mf.index[j.a]]
        u = np.array([np.cos(th_a + j.angle), np.sin(th_a + j.angle)])
        nrm = np.array([-u[1], u[0]])
        Ft = ffx * u[0] + ffy * u[1]
        assert np.allclose(ffx * nrm[0] + ffy * nrm[1], 0.0, atol=1e-9 * np.max(np.abs(Ft)))
        N = (dyn.fx[k] - ffx) * nrm[0] + (dyn.fy[k] - ffy) * nrm[1]
        # relative velocity of b's point on the line against a's material point there
        P = kin.point(j.b, j.point if j.point is not None else j.name)
        ia = mf.index[j.a]
        wa = kin.omega[ia]
        va = (kin.vx[ia] - wa * (P.y - kin.y[ia]), kin.vy[ia] + wa * (P.x - kin.x[ia]))
        v = (P.vx - va[0]) * u[0] + (P.vy - va[1]) * u[1]
        if isinstance(j, Prismatic):
            m = dyn.mz[k] - fmz
            normal = np.abs(N / 2 - m / j.length) + np.abs(N / 2 + m / j.length)
            slip = v
        else:
            normal = np.abs(N)
            slip = v + j.radius * np.sign(N) * dw
            moving = np.abs(slip) > 0.05 * np.max(np.abs(slip))
            assert np.allclose(fmz[moving], -j.radius * j.friction * (N * np.sign(slip))[moving],
                               rtol=1e-9, atol=1e-12)
        moving = np.abs(slip) > 0.05 * np.max(np.abs(slip))
        assert np.allclose(np.abs(Ft[moving]), j.friction * normal[moving], rtol=1e-9)
        assert np.all(Ft[moving] * slip[moving] <= 0)


# -- independent solutions written from scratch ------------------------------------------------

def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _sign(dw, omega1):
    """The documented sign of a relative rotation (docs/friction.md): ``v / sqrt(v^2 + w^2)``
    with ``w = 1e-9 omega1``; a joint whose links turn alike (``dw = 0``) has no friction."""
    w = 1e-9 * omega1
    return dw / np.sqrt(dw * dw + w * w)


def test_crank_slider_against_newton_euler_by_hand():
    """Quasi-static offset crank-slider, friction circles at O, A, B and a guide of length l
    at the slider: the 9 equilibrium equations of crank, rod and slider written here, solved by
    scipy.optimize.fsolve at each position, against the engine (rtol 1e-9)."""
    fsolve = pytest.importorskip("scipy.optimize").fsolve
    r, l, e = 0.1, 0.35, 0.02
    fr, rad, fg, blk, P = 0.1, 0.015, 0.15, 0.06, 1000.0
    mech = crank_slider_mechanism(r, l, e, omega1=10.0)
    js = [dataclasses.replace(j, friction=fr, radius=rad) if isinstance(j, Revolute)
          else dataclasses.replace(j, friction=fg, length=blk) for j in mech.joints]
    mf = Mechanism(mech.frame, mech.bodies, tuple(js), mech.driver, mech.branches)
    phi = np.linspace(0.05, 2 * np.pi, 40)
    kin = kinematics(mf, phi)
    vB = kin.point("slider", "B").vx
    dyn = inverse_dynamics(kin, loads=[PointForce("slider", "B", fx=-P * np.sign(vB))])
    w_rod = kin.omega[mf.index["rod"]]
    for i, ph in enumerate(phi):
        A = np.array([r * np.cos(ph), r * np.sin(ph)])
        B = np.array([A[0] + np.sqrt(l**2 - (e - A[1])**2), e])
        s1, s2 = _sign(10.0, 10.0), _sign(w_rod[i] - 10.0, 10.0)  # omega_b - omega_a at O, A
        s3, sv = _sign(-w_rod[i], 10.0), np.sign(vB[i])            # at B (slider does not turn)
        load = -P * sv

        def eqs(x, s1=s1, s2=s2, s3=s3, sv=sv, A=A, B=B, load=load):
            RO, RA, RB = x[0:2], x[2:4], x[4:6]
            N, MG, Q = x[6], x[7], x[8]
            MO = -fr * rad * np.hypot(*RO) * s1      # by frame on crank
            MA = -fr * rad * np.hypot(*RA) * s2      # by crank on rod
            MB = -fr * rad * np.hypot(*RB) * s3      # by rod on slider
            N1, N2 = N / 2 - MG / blk, N / 2 + MG / blk
            Ft = -fg * (abs(N1) + abs(N2)) * sv
            return [RO[0] - RA[0], RO[1] - RA[1], _cross(A, -RA) + Q + MO - MA,
                    RA[0] - RB[0], RA[1] - RB[1], _cross(B - A, -RB) + MA - MB,
                    RB[0] + Ft + load, RB[1] + N, MB + MG]

        x0 = np.zeros(9)
        x0[[0, 2, 4]] = -load
        x = fsolve(eqs, x0, xtol=1e-13, full_output=True)[0]
        x = fsolve(eqs, x, xtol=1e-13, full_output=True)[0]  # a restart polishes it
        assert np.max(np.abs(eqs(x))) < 1e-10 * P  # solved (fsolve's flag is not the test)
        assert dyn.Q[i] == pytest.approx(x[8], rel=1e-9, abs=1e-9 * P * r)
        k = [j.name for j in mf.joints].index("A")
        assert dyn.fx[k, i] == pytest.approx(x[2], rel=1e-9, abs=1e-9 * P)
        assert dyn.fy[k, i] == pytest.approx(x[3], rel=1e-9, abs=1e-9 * P)


def test_fourbar_against_newton_euler_by_hand():
    """Quasi-static four-bar O2-A-B-O4 with friction circles in its 4 revolutes, a torque on
    the rocker against its rotation and a force on the coupler: the 9 equations written here,
    fsolve per position, against the engine (rtol 1e-9)."""
    fsolve = pytest.importorskip("scipy.optimize").fsolve
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    f, rad, M4, Fc = 0.12, 0.012, 25.0, (30.0, -80.0)
    mech = fourbar_mechanism(a, b, c, d, omega1=5.0)
    mf = Mechanism(mech.frame, mech.bodies,
                   tuple(dataclasses.replace(j, friction=f, radius=rad) for j in mech.joints),
                   mech.driver, mech.branches)
    phi = np.linspace(0.0, 2 * np.pi, 37)
    kin = kinematics(mf, phi)
    w = {n: kin.omega[mf.index[n]] for n in ("crank", "coupler", "rocker")}
    loads = [PointForce("rocker", "com", fx=0.0), PointForce("coupler", "com", fx=Fc[0],
                                                             fy=Fc[1])]
    from linkwork.planar import BodyTorque
    torque = -M4 * np.sign(w["rocker"])
    dyn = inverse_dynamics(kin, loads=[*loads, BodyTorque("rocker", torque)])
    A_ = kin.point("crank", "A")
    B_ = kin.point("coupler", "B")
    Cc = kin.point("coupler", "com")
    O4 = np.array([d, 0.0])
    for i in range(phi.size):
        A = np.array([A_.x[i], A_.y[i]])
        B = np.array([B_.x[i], B_.y[i]])
        C = np.array([Cc.x[i], Cc.y[i]])
        sO2 = _sign(w["crank"][i], 5.0)
        sA = _sign(w["coupler"][i] - w["crank"][i], 5.0)
        sB = _sign(w["rocker"][i] - w["coupler"][i], 5.0)  # 0 at phi = pi: B's links turn alike
        sO4 = _sign(w["rocker"][i], 5.0)

        def eqs(x, A=A, B=B, C=C, sO2=sO2, sA=sA, sB=sB, sO4=sO4, T4=torque[i]):
            R2, RA, RB, R4, Q = x[0:2], x[2:4], x[4:6], x[6:8], x[8]
            M2 = -f * rad * np.hypot(*R2) * sO2   # frame on crank
            MA = -f * rad * np.hypot(*RA) * sA    # crank on coupler
            MB = -f * rad * np.hypot(*RB) * sB    # coupler on rocker
            M4_ = -f * rad * np.hypot(*R4) * sO4  # frame on rocker
            return [R2[0] - RA[0], R2[1] - RA[1], _cross(A, -RA) + Q + M2 - MA,
                    RA[0] - RB[0] + Fc[0], RA[1] - RB[1] + Fc[1],
                    _cross(B - A, -RB) + _cross(C - A, Fc) + MA - MB,
                    RB[0] + R4[0], RB[1] + R4[1], _cross(B - O4, RB) + MB + M4_ + T4]

        x0 = np.zeros(9)
        x = fsolve(eqs, x0 + 1.0, xtol=1e-13, full_output=True)[0]
        x = fsolve(eqs, x, xtol=1e-13, full_output=True)[0]
        assert np.max(np.abs(eqs(x))) < 1e-10 * M4
        assert dyn.Q[i] == pytest.approx(x[8], rel=1e-9, abs=1e-9 * M4)
        for name, s in (("O2", slice(0, 2)), ("B", slice(4, 6))):
            k = [j.name for j in mf.joints].index(name)
            assert np.allclose([dyn.fx[k, i], dyn.fy[k, i]], x[s], rtol=1e-9, atol=1e-9 * M4)



def _perp(v):
    return np.array([-v[1], v[0]])


def _unit(t):
    return np.array([np.cos(t), np.sin(t)])


def _fsolve(eqs, x0, tries=4):
    """``scipy.optimize.fsolve`` restarted from its result until the residual stops falling
    (its progress flag is not the test: each caller checks the residual)."""
    fsolve = pytest.importorskip("scipy.optimize").fsolve
    x = np.asarray(x0, dtype=float)
    for _ in range(tries):
        x = fsolve(eqs, x, xtol=1e-13, full_output=True)[0]
    return x


def _slotted_lever(r2=0.1, h=0.25, block=None, **fr):
    """Crank O2-A (pin A) and a lever pivoted at O4 = (0, -h) whose x axis is a straight slot
    through O4: the pin runs in the slot (``block=None``), or a block of length ``block``
    pinned to the crank at A slides on the lever (a prismatic pair between two moving
    bodies). Masses, inertias and an offset block centre so that inertia loads matter."""
    frame = Body("frame", {"O2": (0.0, 0.0), "O4": (0.0, -h)})
    crank = bar("crank", "O2", "A", r2, mass=1.2, inertia=2e-3)
    lever = Body("lever", {"O4": (0.0, 0.0), "E": (0.5, 0.0)}, mass=3.0, com=(0.18, 0.0),
                 inertia=0.04)
    joints = [Revolute("O2", "frame", "crank", friction=fr["fO2"], radius=fr["rO2"]),
              Revolute("O4", "frame", "lever", friction=fr["fO4"], radius=fr["rO4"])]
    bodies = [crank, lever]
    if block is None:
        joints.append(PinInSlot("S", "lever", "crank", angle=0.0, through="O4", point="A",
                                friction=fr["fS"], radius=fr["rS"]))
    else:
        bodies.insert(1, Body("block", {"A": (0.0, 0.0)}, mass=0.8, com=(0.012, -0.006),
                              inertia=6e-4))
        joints += [Revolute("A", "crank", "block", friction=fr["fA"], radius=fr["rA"]),
                   Prismatic("P", "lever", "block", angle=0.0, through="O4", point="A",
                             friction=fr["fS"], length=block)]
    return Mechanism(frame, tuple(bodies), tuple(joints), Crank("O2", omega1=8.0))


def _lever_motion(phi, w1, r2=0.1, h=0.25):
    """The slotted lever's motion written out: A on the crank circle at constant omega1, the
    lever along O4 -> A: its angle, rate, acceleration and the slide s = |A - O4| and ds/dt."""
    A = r2 * _unit(phi)
    vA = w1 * r2 * _perp(_unit(phi))
    aA = -w1**2 * A
    d = A - np.array([0.0, -h])
    s = np.hypot(*d)
    w4 = _cross(d, vA) / s**2
    a4 = _cross(d, aA) / s**2 - 2 * _cross(d, vA) * (d @ vA) / s**4
    return A, aA, np.arctan2(d[1], d[0]), w4, a4, d @ vA / s


def test_pin_with_radius_in_a_turning_slot_against_newton_euler_by_hand():
    """The crank's pin A (radius 10 mm, f = 0.12) runs in the slot of a lever that turns about
    O4 (a crank and slotted lever; the slot's rotation makes the pin's contact slip at
    ds/dt + r sign(N) (omega_crank - omega_lever), not at ds/dt), friction circles at O2 and
    O4, inertia, gravity and a load torque cos(phi1) 25 N m on the lever, so that the normal
    force changes sign and the pin changes walls. The 6 Newton-Euler equations of crank and
    lever are written here from the contact (the friction force at the contact point C = A -
    r sign(N) n, against the slip of the pin's material over the slot's), with the lever's
    motion written out, and solved per position by fsolve: Q and every reaction to 1e-9."""
    fr = dict(fO2=0.06, rO2=0.02, fO4=0.08, rO4=0.025, fS=0.12, rS=0.01)
    mech = _slotted_lever(**fr)
    g, w1, m2, m4, I4, c4 = np.array([0.0, -9.81]), 8.0, 1.2, 3.0, 0.04, 0.18  # omega1 const
    phi = np.radians(np.arange(3.0, 360.0, 9.0))
    kin = kinematics(mech, phi)
    dyn = inverse_dynamics(kin, gravity=tuple(g),
                           loads=[BodyTorque("lever", -25.0 * np.cos(phi))])
    O4 = np.array([0.0, -0.25])
    normals = []
    for i, p in enumerate(phi):
        A, _, th, w4, a4, sd = _lever_motion(p, w1)
        assert kin.theta[2, i] == pytest.approx(th, abs=1e-12)
        u, n = _unit(th), _perp(_unit(th))
        C2, aC2 = A / 2, -w1**2 * A / 2
        C4 = O4 + c4 * u
        aC4 = c4 * (a4 * n - w4**2 * u)
        ML = -25.0 * np.cos(p)

        def eqs(x, A=A, u=u, n=n, w4=w4, a4=a4, sd=sd, C2=C2, aC2=aC2, C4=C4, aC4=aC4,
                ML=ML):
            RO2, RO4, N, Q = x[0:2], x[2:4], x[4], x[5]
            sN = np.sign(N)
            slip = sd + fr["rS"] * sN * (w1 - w4)   # pin material over slot material at C
            F = N * n - fr["fS"] * abs(N) * np.sign(slip) * u  # lever on crank, at C
            C = A - fr["rS"] * sN * n
            MO2 = -fr["fO2"] * fr["rO2"] * np.hypot(*RO2) * np.sign(w1)
            MO4 = -fr["fO4"] * fr["rO4"] * np.hypot(*RO4) * np.sign(w4)
            return [*(RO2 + F + m2 * (g - aC2)),
                    Q + MO2 + _cross(C, F) + _cross(C2, m2 * (g - aC2)),
                    *(RO4 - F + m4 * (g - aC4)),
                    MO4 + ML + _cross(C - O4, -F) + _cross(C4 - O4, m4 * (g - aC4))
                    - I4 * a4]

        x = _fsolve(eqs, np.zeros(6))
        assert np.max(np.abs(eqs(x))) < 1e-10 * 200
        normals.append(x[4])
        assert dyn.Q[i] == pytest.approx(x[5], abs=1e-9 * 20)
        for k, (fx, fy) in enumerate((x[0:2], x[2:4])):
            assert (dyn.fx[k, i], dyn.fy[k, i]) == pytest.approx((fx, fy), abs=1e-9 * 200)
    assert min(normals) < 0 < max(normals)          # the pin touched both walls


@pytest.mark.parametrize("block", [0.05, 0.006])
def test_block_on_a_turning_guide_against_newton_euler_by_hand(block):
    """A block pinned to the crank at A (friction circle) slides on the turning lever of the
    slotted-lever mechanism (a prismatic pair between two moving bodies), its length 50 mm or
    6 mm: with 6 mm the guide's couple makes the block press on both sides somewhere (N1 N2 <
    0, the drawer effect). Newton-Euler of crank, block and lever written here (the normal
    force N and couple m of the guide carried by contacts N/2 -+ m/l at the block's ends, the
    friction f (|N1| + |N2|) against the slide), solved by fsolve: Q, reactions, couple to 1e-9.
    """
    fr = dict(fO2=0.06, rO2=0.02, fO4=0.08, rO4=0.025, fA=0.07, rA=0.012, fS=0.12)
    mech = _slotted_lever(block=block, **fr)
    g, w1 = np.array([0.0, -9.81]), 8.0
    m2, mb, Ib, m4, I4, c4 = 1.2, 0.8, 6e-4, 3.0, 0.04, 0.18   # the crank at const omega1
    cb = np.array([0.012, -0.006])
    phi = np.radians(np.arange(3.0, 360.0, 9.0))
    kin = kinematics(mech, phi)
    dyn = inverse_dynamics(kin, gravity=tuple(g),
                           loads=[BodyTorque("lever", -25.0 * np.cos(phi))])
    names = list(dyn.joints)
    O4 = np.array([0.0, -0.25])
    both_sides = 0
    for i, p in enumerate(phi):
        A, aA, th, w4, a4, sd = _lever_motion(p, w1)
        u, n = _unit(th), _perp(_unit(th))
        C2, aC2 = A / 2, -w1**2 * A / 2
        C4, aC4 = O4 + c4 * u, c4 * (a4 * n - w4**2 * u)
        rb = cb[0] * u + cb[1] * n                          # the block turns with the lever
        aCb = aA + a4 * _perp(rb) - w4**2 * rb
        ML = -25.0 * np.cos(p)

        def eqs(x, A=A, u=u, n=n, w4=w4, a4=a4, sd=sd, C2=C2, aC2=aC2, C4=C4, aC4=aC4, rb=rb,
                aCb=aCb, ML=ML):
            RO2, RA, N, m, RO4, Q = x[0:2], x[2:4], x[4], x[5], x[6:8], x[8]
            N1, N2 = N / 2 - m / block, N / 2 + m / block
            F = N * n - fr["fS"] * (abs(N1) + abs(N2)) * np.sign(sd) * u  # lever on block
            MO2 = -fr["fO2"] * fr["rO2"] * np.hypot(*RO2) * np.sign(w1)
            MA = -fr["fA"] * fr["rA"] * np.hypot(*RA) * np.sign(w4 - w1)  # crank on block
            MO4 = -fr["fO4"] * fr["rO4"] * np.hypot(*RO4) * np.sign(w4)
            return [*(RO2 - RA + m2 * (g - aC2)),
                    Q + MO2 - MA + _cross(A, -RA) + _cross(C2, m2 * (g - aC2)),
                    *(RA + F + mb * (g - aCb)),
                    MA + m + _cross(rb, mb * (g - aCb)) - Ib * a4,
                    *(RO4 - F + m4 * (g - aC4)),
                    MO4 - m + ML + _cross(A - O4, -F) + _cross(C4 - O4, m4 * (g - aC4))
                    - I4 * a4]

        x = _fsolve(eqs, np.zeros(9))
        assert np.max(np.abs(eqs(x))) < 1e-10 * 200
        both_sides += (x[4] / 2 - x[5] / block) * (x[4] / 2 + x[5] / block) < 0
        assert dyn.Q[i] == pytest.approx(x[8], abs=1e-9 * 20)
        for j, (fx, fy) in (("O2", x[0:2]), ("A", x[2:4]), ("O4", x[6:8])):
            k = names.index(j)
            assert (dyn.fx[k, i], dyn.fy[k, i]) == pytest.approx((fx, fy), abs=1e-9 * 200)
        assert dyn.mz[names.index("P"), i] == pytest.approx(x[5], abs=1e-9 * 20)
    assert (both_sides > 0) == (block < 0.01)


def test_linear_driver_with_friction_against_newton_euler_by_hand():
    """A slider-crank driven by its slider (a linear driver, v1 = -0.4 m/s, a1 = 0.7 m/s^2),
    the crank the output against a 6 N m torque opposing its rotation; friction circles at O,
    A, B and a 40 mm block in the guide, inertia and gravity. The crank's and rod's motion
    written out from the slide (velocity and acceleration loops solved here), the 9 equations
    of slider, rod and crank solved by fsolve: the driving force Q (along the guide, besides
    the guide's friction, which the guide's reaction carries) and the reactions to 1e-9."""
    r, l, e, v1, a1 = 0.08, 0.3, 0.01, -0.4, 0.7
    fO, rO, fA, rA, fB, rB, fG, lG = 0.05, 0.02, 0.06, 0.012, 0.07, 0.01, 0.1, 0.04
    m2, I2, m3, I3, m4, I4, c4 = 1.0, 1.5e-3, 2.0, 0.02, 3.0, 1e-3, np.array([0.01, 0.015])
    g = np.array([0.0, -9.81])
    frame = Body("frame", {"O": (0.0, 0.0), "G0": (0.0, e)})
    slider = Body("slider", {"B": (0.0, 0.0)}, mass=m4, com=tuple(c4), inertia=I4)
    mech = Mechanism(frame, (slider, bar("rod", "A", "B", l, mass=m3, inertia=I3),
                             bar("crank", "O", "A", r, mass=m2, inertia=I2)),
                     (Prismatic("G", "frame", "slider", angle=0.0, through="G0", point="B",
                                friction=fG, length=lG),
                      Revolute("B", "rod", "slider", friction=fB, radius=rB),
                      Revolute("A", "crank", "rod", friction=fA, radius=rA),
                      Revolute("O", "frame", "crank", friction=fO, radius=rO)),
                     Linear("G", v1=v1, a1=a1))
    s = np.linspace(0.26, 0.36, 21)
    kin = kinematics(mech, s)
    w2_engine = kin.omega[mech.index["crank"]]
    dyn = inverse_dynamics(kin, gravity=tuple(g),
                           loads=[BodyTorque("crank", -6.0 * np.sign(w2_engine))])
    names = list(dyn.joints)
    for i, si in enumerate(s):
        B = np.array([si, e])
        A = r * _unit(kin.theta[mech.index["crank"], i])   # the branch from the engine...
        assert np.hypot(*(B - A)) == pytest.approx(l, abs=1e-12)  # ...checked by the loop
        M = np.column_stack([_perp(A), _perp(B - A)])
        w2, w3 = np.linalg.solve(M, [v1, 0.0])
        al2, al3 = np.linalg.solve(M, np.array([a1, 0.0]) + w2**2 * A + w3**2 * (B - A))
        aA = al2 * _perp(A) - w2**2 * A
        aC2 = aA / 2
        aC3 = aA + al3 * _perp((B - A) / 2) - w3**2 * (B - A) / 2
        aC4 = np.array([a1, 0.0])
        ML = -6.0 * np.sign(w2)

        def eqs(x, A=A, B=B, w2=w2, w3=w3, al2=al2, al3=al3, aC2=aC2, aC3=aC3, aC4=aC4,
                ML=ML):
            RO, RA, RB, N, m, F = x[0:2], x[2:4], x[4:6], x[6], x[7], x[8]
            N1, N2 = N / 2 - m / lG, N / 2 + m / lG
            Ft = -fG * (abs(N1) + abs(N2)) * np.sign(v1)
            MO = -fO * rO * np.hypot(*RO) * np.sign(w2)          # frame on crank
            MA = -fA * rA * np.hypot(*RA) * np.sign(w3 - w2)     # crank on rod
            MB = -fB * rB * np.hypot(*RB) * np.sign(0.0 - w3)    # rod on slider
            return [*(RO - RA + m2 * (g - aC2)),
                    MO - MA + ML + _cross(A, -RA) + _cross(A / 2, m2 * (g - aC2)) - I2 * al2,
                    *(RA - RB + m3 * (g - aC3)),
                    MA - MB + _cross(B - A, -RB) + _cross((B - A) / 2, m3 * (g - aC3))
                    - I3 * al3,
                    RB[0] + F + Ft + m4 * (g[0] - aC4[0]), RB[1] + N + m4 * (g[1] - aC4[1]),
                    MB + m + _cross(c4, m4 * (g - aC4))]

        x = _fsolve(eqs, np.zeros(9))
        assert np.max(np.abs(eqs(x))) < 1e-10 * 100
        assert w2_engine[i] == pytest.approx(w2, rel=1e-12)
        assert dyn.Q[i] == pytest.approx(x[8], abs=1e-9 * 100)
        for j, (fx, fy) in (("O", x[0:2]), ("A", x[2:4]), ("B", x[4:6])):
            k = names.index(j)
            assert (dyn.fx[k, i], dyn.fy[k, i]) == pytest.approx((fx, fy), abs=1e-9 * 100)
        k = names.index("G")
        Ft = -fG * (abs(x[6] / 2 - x[7] / lG) + abs(x[6] / 2 + x[7] / lG)) * np.sign(v1)
        assert (dyn.fx[k, i], dyn.fy[k, i], dyn.mz[k, i]) == pytest.approx(
            (Ft, x[6], x[7]), abs=1e-9 * 100)


def _toggle(fr: float = 1.0) -> Mechanism:
    """A slider-driven crank (a toggle): massless crank O-A 80 mm and rod A-B 300 mm, the
    slider B on a guide 10 mm above O, the slider the driver; friction circles f r = 3, 2,
    1.5 mm at O, A, B and f = 0.1 in the guide (point contact), times ``fr``."""
    frame = Body("frame", {"O": (0.0, 0.0), "G0": (0.0, 0.01)})
    return Mechanism(frame, (Body("slider", {"B": (0.0, 0.0)}), bar("rod", "A", "B", 0.3),
                             bar("crank", "O", "A", 0.08)),
                     (Prismatic("G", "frame", "slider", angle=0.0, through="G0", point="B",
                                friction=0.1 * fr),
                      Revolute("B", "rod", "slider", friction=0.1 * fr, radius=0.015),
                      Revolute("A", "crank", "rod", friction=0.1 * fr, radius=0.02),
                      Revolute("O", "frame", "crank", friction=0.1 * fr, radius=0.03)),
                     Linear("G", v1=-0.5))


def _toggle_closed_form(s, theta2, v1=-0.5, M0=10.0):
    """The slider force that turns the toggle's crank against M0 (opposing its rotation), or
    None where no force does: the massless rod is a two-force member whose line of action is
    tangent to the friction circles at A and B (its moment about A and B the two friction
    couples), tilted by asin(k / l) from AB; the crank's moment balance about O, with its
    friction circle, fixes the rod force S (compression or tension, whichever is consistent);
    the slider's balance along the guide adds the guide's friction. Locked where no sign of S
    balances the crank: the rod's line of action passes inside O's friction circle."""
    r, l, e = 0.08, 0.3, 0.01
    rhoO, rhoA, rhoB, fG = 0.003, 0.002, 0.0015, 0.1
    B, A = np.array([s, e]), r * _unit(theta2)
    w2, w3 = np.linalg.solve(np.column_stack([_perp(A), _perp(B - A)]), [v1, 0.0])
    th3 = np.arctan2(*(B - A)[::-1])
    k = rhoA * np.sign(w3 - w2) - rhoB * np.sign(-w3)  # (B - A) x P = k |S|
    forces = []
    for sg in (1.0, -1.0):
        ev = _unit(th3 + np.arcsin(sg * k / l))           # P = S ev, the rod's force on the crank
        c = _cross(A, ev) * sg + rhoA * np.sign(w3 - w2) - rhoO * np.sign(w2)
        S_abs = M0 * np.sign(w2) / c
        if S_abs > 0:
            P = sg * S_abs * ev
            forces.append(P[0] + fG * abs(P[1]) * np.sign(v1))
    return forces, w2


def test_toggle_self_locks_where_its_rod_passes_inside_the_friction_circle():
    """A slider-driven crank near its outer dead centre (the toggle a press's ram cannot back-
    drive): the engine's driving force equals the closed form of ``_toggle_closed_form`` to
    1e-9 where it runs, its ``locked`` positions are exactly the closed form's (no consistent
    rod force), the limit found by bisection on each agrees to 1e-12 m, and towards it kappa ->
    0 and the force grows like 1/kappa; without friction nothing locks."""
    mech = _toggle()
    smax = np.sqrt(0.38**2 - 0.01**2)
    s = np.linspace(smax - 0.01, smax - 1e-7, 200)

    def engine(x):
        kin = kinematics(mech, np.atleast_1d(x))
        w2 = kin.omega[mech.index["crank"]]
        return kin, inverse_dynamics(kin, loads=[BodyTorque("crank", -10.0 * np.sign(w2))])

    kin, dyn = engine(s)
    th2 = kin.theta[mech.index["crank"]]
    closed = [_toggle_closed_form(x, t) for x, t in zip(s, th2, strict=True)]
    assert all(len(f) <= 1 for f, _ in closed)           # one consistent rod force, or none
    locked = np.array([not f for f, _ in closed])
    assert 0 < locked.sum() < s.size // 4 and np.array_equal(dyn.locked, locked)
    for i in np.flatnonzero(~locked):
        assert kin.omega[mech.index["crank"], i] == pytest.approx(closed[i][1], rel=1e-12)
        assert dyn.Q[i] == pytest.approx(closed[i][0][0], rel=1e-9)

    def bisect(is_locked):
        lo, hi = s[~locked][-1], s[locked][0]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if is_locked(mid) else (mid, hi)
        return 0.5 * (lo + hi)

    def closed_locked(x):
        return not _toggle_closed_form(x, engine(x)[0].theta[mech.index["crank"], 0])[0]

    limit = bisect(lambda x: bool(engine(x)[1].locked[0]))
    assert limit == pytest.approx(bisect(closed_locked), abs=1e-12)
    near = engine(limit - np.array([1e-4, 1e-6, 1e-8]))[1]
    assert np.all(np.diff(near.kappa) < 0) and near.kappa[-1] > 0
    assert np.all(np.diff(np.abs(near.Q)) > 0)
    assert np.abs(near.Q * near.kappa).max() < 2 * np.abs(near.Q * near.kappa).min()
    kin0 = kinematics(_toggle(0.0), s)
    assert not inverse_dynamics(kin0, loads=[BodyTorque("crank", -10.0)]).locked.any()

def test_eccentric_and_rod_worked_example_with_friction_circles():
    """A worked friction-circle example of an imperial-units machine-theory text, as
    transcribed in the FOSSEE Scilab Textbook Companion project (its Scilab solution; the
    book, edition and page are not identified here, see docs/friction.md): an eccentric of
    throw OC = 8 in (stroke 16 in) at 60 deg from the dead centre, rod CP = 80 in, a 6 ton
    force along the line of stroke driving, friction coefficient 0.05 in the shaft journal
    (r = 7 in), the eccentric sheave (r = 15 in, larger than the throw) and the pin
    (r = 4.4 in), frictionless guide. The construction: the rod's line of force tangent to
    the friction circles at C and P (tilted by alpha = asin(f (r_C + r_P) / CP)), the shaft's
    reaction tangent to its friction circle. Turning moment on OC 3.638 ton ft without
    friction and 3.062 with (efficiency 0.842); the engine gives both to 1e-12."""
    inch, P, f = 0.0254, 6.0, 0.05
    OC, CP, rO, rC, rP = 8 * inch, 80 * inch, 7 * inch, 15 * inch, 4.4 * inch
    th = np.radians(60.0)
    # the companion's closed form of the construction
    phi = np.arcsin(OC * np.sin(th) / CP)
    alpha = np.arcsin(f * (rC + rP) / CP)
    Ma = P / np.cos(phi) * OC * np.cos(np.radians(30.0) - phi)
    Mb = P / np.cos(phi - alpha) * (OC * np.cos(np.radians(30.0) - (phi - alpha))
                                    - f * (rC + rO))
    assert (Ma / inch / 12, Mb / inch / 12) == pytest.approx((3.638, 3.062), abs=5e-4)
    frame = Body("frame", {"O": (0.0, 0.0), "G": (0.0, 0.0)})
    joints = (Revolute("O", "frame", "crank", friction=f, radius=rO),
              Revolute("C", "crank", "rod", friction=f, radius=rC),
              Revolute("P", "rod", "crosshead", friction=f, radius=rP),
              Prismatic("G", "frame", "crosshead", through="G", point="P"))
    mech = Mechanism(frame, (bar("crank", "O", "C", OC), bar("rod", "C", "P", CP),
                             Body("crosshead", {"P": (0.0, 0.0)})), joints, Crank("O", 1.0))
    kin = kinematics(mech, np.array([th]))
    # the force drives: it pushes the crosshead towards the shaft while the crank turns on
    dyn = inverse_dynamics(kin, loads=[PointForce("crosshead", "P", fx=-P)])
    assert kin.point("crosshead", "P").vx[0] < 0
    assert -dyn.Q_frictionless[0] == pytest.approx(Ma, rel=1e-12)
    assert -dyn.Q[0] == pytest.approx(Mb, rel=1e-12)


# -- self-locking (paper 000's jamming range over alpha: tests/planar/test_self_locking.py) ------

def test_short_guide_block_jams_drawer_effect():
    """The yoke of a sine mechanism in a two-contact guide: a block 30 mm long (its load's
    couple split into end forces |N1| + |N2| >> |N|) self-locks at some positions, with kappa
    falling to 0 and the driving torque growing without bound towards them; 300 mm long, or a
    point contact (length 0, the couple carries no friction), it runs."""
    from _mechanisms import m_rpp

    mech, phi, _ = m_rpp()
    locked = {}
    for length in (0.0, 0.03, 0.3):
        mf = with_friction(mech, length=length)
        kin = kinematics(mf, phi)
        locked[length] = inverse_dynamics(kin, gravity=(0.0, -9.81),
                                          loads=_loads(mf, kin)).locked.any()
    assert locked == {0.0: False, 0.03: True, 0.3: False}
    phi = np.linspace(1.92, 2.5, 11)
    mf = with_friction(mech, length=0.03)
    kin = kinematics(mf, phi)
    d = inverse_dynamics(kin, gravity=(0.0, -9.81), loads=_loads(mf, kin))
    assert not d.locked.any()
    assert np.all(np.diff(d.kappa) > 0) and d.kappa[0] < 0.01 < d.kappa[-1]
    assert np.all(np.diff(np.abs(d.Q)) < 0)


def test_self_locking_is_reported_and_undefined():
    """Outside the working range the locked positions are NaN (undefined), named by
    ``locked`` and ``self_locking_ranges``; the driving torque grows like 1/kappa towards
    the limit."""
    f1, f2 = 0.12, 0.10
    lo = float(sine.working_range(f1, f2)[0])
    phi = np.linspace(0.0, 2 * np.pi, 73)[:-1] + 0.01
    kin = kinematics(sine_mechanism(lo - 0.01, f1, f2), phi)
    v = kin.point("slider", "G").vx
    dyn = inverse_dynamics(kin, loads=[PointForce("slider", "G", fx=-1000.0 * np.sign(v))])
    assert dyn.locked.any() and not dyn.locked.all()
    assert np.all(np.isnan(dyn.Q[dyn.locked])) and np.all(np.isfinite(dyn.Q[~dyn.locked]))
    ranges = dyn.self_locking_ranges()
    assert ranges and all(a <= b for a, b in ranges)
    assert sum(int(np.sum((phi >= a) & (phi <= b))) for a, b in ranges) == dyn.locked.sum()
    assert dyn.efficiency_cycle is None and np.all(np.isnan(dyn.friction_losses))
    peaks = []
    for da in (0.1, 0.01, 0.001):
        kin = kinematics(sine_mechanism(lo + da, f1, f2), phi)
        v = kin.point("slider", "G").vx
        d = inverse_dynamics(kin, loads=[PointForce("slider", "G", fx=-1000.0 * np.sign(v))])
        assert not d.locked.any()
        peaks.append((np.max(np.abs(d.Q)), np.min(d.kappa)))
    assert peaks[0][0] < peaks[1][0] < peaks[2][0]
    assert peaks[0][1] > peaks[1][1] > peaks[2][1] > 0



def test_self_locked_positions_keep_the_shaking_loads():
    """Where the mechanism self-locks the reactions and Q are undefined, but the shaking force
    and moment are not: friction is internal, so they are the frictionless engine's (its
    Newton-Euler resultant, independent of the joint reactions), at every position, to
    round-off (1e-11 of their scale). Balancing takes its shaking moment from them."""
    f1, f2 = 0.12, 0.10
    lo = float(sine.working_range(f1, f2)[0])
    phi = np.linspace(0.0, 2 * np.pi, 73)[:-1] + 0.01
    d = {}
    for tag, (a, b) in (("friction", (f1, f2)), ("none", (0.0, 0.0))):
        kin = kinematics(sine_mechanism(lo - 0.01, a, b), phi)
        v = kin.point("slider", "G").vx
        d[tag] = inverse_dynamics(kin, gravity=(-9.81, 0.0),
                                  loads=[PointForce("slider", "G", fx=-1000.0 * np.sign(v))])
    assert d["friction"].locked.any() and not d["none"].locked.any()
    for name in ("shaking_fx", "shaking_fy", "shaking_m"):
        a, b = getattr(d["friction"], name), getattr(d["none"], name)
        assert np.all(np.isfinite(a)), name
        assert np.max(np.abs(a - b)) <= 1e-11 * max(np.max(np.abs(b)), 1.0), name

# -- efficiency and losses --------------------------------------------------------------------

def test_efficiency_and_losses():
    """Cycle efficiency = 1 - losses / driving work; the losses are the time integral of the
    friction power (trapezoid over phi1 of P_f / omega1); instantaneous efficiency undefined
    (NaN) where the driving power is not positive; frictionless: 1 where defined."""
    mech = crank_slider_mechanism(0.1, 0.35, 0.02, omega1=20.0)
    mf = with_friction(mech, length=0.05)
    phi = np.linspace(0.0, 2 * np.pi, 721)
    kin = kinematics(mf, phi)
    v = kin.point("slider", "B").vx
    dyn = inverse_dynamics(kin, loads=[PointForce("slider", "B", fx=-500.0 * np.tanh(v / 0.05))])
    losses = dyn.friction_losses
    assert losses.shape == (4,) and np.all(losses > 0)
    t_int = np.trapezoid(dyn.friction_power / 20.0, phi / 1.0, axis=1)
    assert np.allclose(losses, t_int, rtol=1e-12)
    wd = np.trapezoid(dyn.Q, phi)
    eta = dyn.efficiency_cycle
    assert eta is not None and 0.5 < eta < 1.0
    assert eta == pytest.approx((wd - losses.sum()) / wd, rel=1e-12)
    # the useful work is the work done against the load: the frictionless driving work
    assert wd - losses.sum() == pytest.approx(np.trapezoid(dyn.Q_frictionless, phi), rel=1e-6)
    inst = dyn.efficiency
    pos = dyn.power > 0
    assert np.all(np.isnan(inst[~pos])) and np.all(inst[pos] <= 1.0)
    d0 = inverse_dynamics(kinematics(mech, phi), loads=[PointForce(
        "slider", "B", fx=-500.0 * np.tanh(v / 0.05))])
    assert d0.efficiency_cycle == pytest.approx(1.0, abs=1e-12)
    assert np.all(d0.efficiency[d0.power > 0] == 1.0)


def test_losses_and_work_do_not_depend_on_the_listing_order():
    """The crank turning backwards (omega1 < 0) over increasing phi1, or the positions listed
    backwards: the same positive losses and driving work (the time integral in the order the
    driver passes the positions)."""
    phi = np.linspace(0.0, 2 * np.pi, 361)
    out = []
    for w, ph in ((20.0, phi), (-20.0, phi), (20.0, phi[::-1]), (-20.0, phi[::-1])):
        mech = with_friction(crank_slider_mechanism(0.1, 0.35, 0.02, omega1=w), length=0.05)
        kin = kinematics(mech, ph)
        v = kin.point("slider", "B").vx
        d = inverse_dynamics(kin, loads=[PointForce("slider", "B", fx=-500.0 * np.sign(v))])
        out.append((d.friction_losses, d.driving_work, d.efficiency_cycle))
    for losses, wd, eta in out:
        assert np.all(losses > 0) and wd > 0 and 0 < eta < 1
        assert np.allclose(losses, out[0][0], rtol=1e-6)
        assert wd == pytest.approx(out[0][1], rel=1e-6)
    mech = with_friction(crank_slider_mechanism(0.1, 0.35, 0.02))
    kin = kinematics(mech, phi, omega1=np.cos(phi))  # the crank stops and reverses
    d = inverse_dynamics(kin)
    assert np.all(np.isnan(d.friction_losses)) and d.efficiency_cycle is None


def test_static_driver_has_no_friction():
    """omega1 = 0 at every position: friction undetermined, set to zero and said so."""
    mech = with_friction(crank_slider_mechanism(0.1, 0.35, 0.02, omega1=0.0))
    kin = kinematics(mech, np.linspace(0.1, 1.0, 5))
    dyn = inverse_dynamics(kin, gravity=(0.0, -9.81))
    assert dyn.friction_static and not dyn.friction_power.any()
    assert dyn.efficiency_cycle is None


# -- bad input --------------------------------------------------------------------------------

@pytest.mark.parametrize(("make", "match"), [
    (lambda: Revolute("O", "frame", "crank", friction=-0.1, radius=0.01), "friction = -0.1"),
    (lambda: Revolute("O", "frame", "crank", friction=1.2, radius=0.01), "< 1"),
    (lambda: Revolute("O", "frame", "crank", friction=0.1), "radius = 0.*> 0"),
    (lambda: Revolute("O", "frame", "crank", friction=0.1, radius=-1.0), "radius"),
    (lambda: Revolute("O", "frame", "crank", friction_torque=-1.0), "friction_torque"),
    (lambda: Prismatic("G", "frame", "s", friction=float("nan")), "friction"),
    (lambda: Prismatic("G", "frame", "s", friction=0.1, length=-0.01), "length = -0.01"),
    (lambda: PinInSlot("S", "frame", "s", friction=1.0), "friction = 1"),
    (lambda: PinInSlot("S", "frame", "s", friction=0.1, radius=-0.01), "radius"),
])
def test_bad_friction_parameters(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


def test_journal_larger_than_the_link():
    """Refused when larger than every moving link it joins (O: the crank alone; A: crank and
    rod); an eccentric (sheave larger than the crank, smaller than the rod) is accepted."""
    mech = crank_slider_mechanism(0.1, 0.35, 0.02)
    for name, r, match in (("O", 0.12, r"joint O\.radius = 0\.12.*< 0\.1 m.*'crank'"),
                           ("A", 0.4, r"joint A\.radius = 0\.4.*< 0\.35 m.*'rod'")):
        js = tuple(dataclasses.replace(j, friction=0.1, radius=r) if j.name == name else j
                   for j in mech.joints)
        with pytest.raises(ParameterError, match=match):
            Mechanism(mech.frame, mech.bodies, js, mech.driver, mech.branches)
    js = tuple(dataclasses.replace(j, friction=0.1, radius=0.12) if j.name == "A" else j
               for j in mech.joints)
    assert Mechanism(mech.frame, mech.bodies, js, mech.driver, mech.branches).joint("A").radius


# -- chunks of positions ----------------------------------------------------------------------

_ALL_FIELDS = ("fx", "fy", "mz", "px", "py", "Q", "shaking_fx", "shaking_fy", "shaking_m", "T",
               "Q_frictionless", "friction_fx", "friction_fy", "friction_mz", "friction_power",
               "locked", "kappa")


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda b: b.__name__)
@pytest.mark.parametrize("fric", [False, True], ids=["frictionless", "friction"])
def test_chunks_of_positions_change_nothing(builder, fric, monkeypatch):
    """inverse_dynamics in chunks of 7 positions (partial last chunk; per-position loads and a
    driver speed that varies, so the friction law's sign width must come from the whole
    cycle) gives the unchunked result bit for bit, every field (NaN where undefined), the
    Newton count of the friction solve included."""
    import linkwork.planar.dynamics as dynamics

    mech, phi, _ = builder()
    if fric:
        mech = with_friction(mech)
    w1 = mech.driver.omega1 * (1.0 + 0.5 * np.sin(np.linspace(0.0, 3.0, phi.size)))
    kin = kinematics(mech, phi, w1, on_failure="nan")
    g = (0.0, -9.81)
    loads = _loads(mech, kin)
    whole = inverse_dynamics(kin, gravity=g, loads=loads, about=(0.02, -0.01))
    monkeypatch.setattr(dynamics, "CHUNK", 7)
    chunked = inverse_dynamics(kin, gravity=g, loads=loads, about=(0.02, -0.01))
    for name in _ALL_FIELDS:
        a, b = getattr(whole, name), getattr(chunked, name)
        assert a.shape == b.shape and np.array_equal(a, b, equal_nan=True), name
    assert chunked.friction_iterations == whole.friction_iterations
    assert chunked.friction_static == whole.friction_static
    assert chunked.kinematics is kin and chunked.joints == whole.joints
    if fric:
        assert whole.friction_iterations > 0 and whole.friction_power.any()


def test_chunks_check_per_position_loads_against_the_whole_cycle(monkeypatch):
    """A load array of the wrong length is refused naming the load, before any chunk."""
    import linkwork.planar.dynamics as dynamics

    mech, phi, _ = BUILDERS[0]()
    kin = kinematics(mech, phi)
    monkeypatch.setattr(dynamics, "CHUNK", 7)
    bad = PointForce(mech.bodies[0].name, "com", fx=np.zeros(phi.size + 1))
    with pytest.raises(ParameterError, match=r"loads\[0\]\.fx"):
        inverse_dynamics(kin, loads=[bad])
