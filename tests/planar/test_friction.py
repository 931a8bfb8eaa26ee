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
    Crank,
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
