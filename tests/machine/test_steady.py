"""The periodic steady state (linkwork.machine.steady) against an independent integration.

Reference: tests/_machine_lagrange.py, the whole mechanism as a constrained multibody system
(body coordinates, constraint equations and Lagrange multipliers written in the tests),
integrated over the crank angle by DOP853 at rtol 1e-11 and made periodic by the secant method
to 1e-11. omega(phi) at every node must agree to 1e-6 relative (it does to about 1e-9 at 360
positions: the collocation is fourth order) and so must the period. Energy over a cycle: the
motor's work equals the work on the loads plus the joint friction and gear losses to 1e-8 of
the motor's work (the solve's own balance), and with friction the mean torque at the crank is
the frictionless one plus the friction losses / 2 pi.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _machine_lagrange import Multibody

from linkwork import io
from linkwork.errors import DriveError
from linkwork.machine import (
    ConstantSpeed,
    DCMotor,
    Gear,
    InductionMotor,
    machine,
    steady_state,
)
from linkwork.planar import BodyTorque, Damper, Mechanism, PointForce, Revolute, kinematics

RPM = math.pi / 30
G = (0.0, -9.81)


def _wrap(x):
    return np.mod(x + np.pi, 2 * np.pi) - np.pi


def fourbar_case(motor, gear, flywheel):
    mech = io.load("examples/fourbar_paper001.toml").mechanism()

    def fy(phi):  # a smooth working load on the coupler point, -40 N peak near 200 deg
        return -40.0 * np.exp(-(_wrap(phi - np.radians(200)) / 0.5) ** 2) - 5.0

    return mech, (lambda p: [PointForce("coupler", "P", 0.0, fy(p))]), (
        lambda p: [("force", "coupler", (0.15, 0.1), 0.0, float(fy(p)))]), motor, gear, flywheel


def sixbar_case(motor, gear, flywheel):
    mech = io.load("examples/loom_sixbar.toml").mechanism()

    def fy(phi):  # a smooth coining force on the ram, 20 kN peak at 170 deg
        return 20e3 * np.exp(-(_wrap(phi - np.radians(170)) / 0.2) ** 2)

    return mech, (lambda p: [PointForce("ram", "R", 0.0, fy(p))]), (
        lambda p: [("force", "ram", (0.0, 0.0), 0.0, float(fy(p)))]), motor, gear, flywheel


CASES = {
    "fourbar-dc": lambda: fourbar_case(DCMotor(20.0, 12.0, inertia=0.01), Gear(), 0.0),
    "fourbar-induction-flywheel": lambda: fourbar_case(
        InductionMotor(250.0, 1500 * RPM, 1420 * RPM, 2.5, inertia=2e-4), Gear(15.0), 0.02),
    "sixbar-dc": lambda: sixbar_case(DCMotor(40.0, 160.0, inertia=0.01), Gear(36.0, 1.0, 0.002),
                                     0.0),
    "sixbar-induction-flywheel": lambda: sixbar_case(
        InductionMotor(4000.0, 1500 * RPM, 1440 * RPM, 2.8, inertia=0.012),
        Gear(36.0, 1.0, 0.002), 2.0),
}


@pytest.fixture(scope="module", params=list(CASES))
def compared(request):
    mech, loads, ref_loads, motor, gear, fw = CASES[request.param]()
    ss = steady_state(mech, motor, loads=loads, gravity=G, flywheel=fw, gear=gear, n=360)
    rotors = (motor.inertia + gear.inertia) * gear.ratio**2 + fw
    mb = Multibody(mech, lambda p, w: gear.ratio * float(motor.torque(gear.ratio * w)),
                   rotors=rotors, gravity=G, loads=ref_loads)
    _w0, end, vals = mb.periodic(float(ss.phi1[0]), float(ss.omega[0]) * 1.001, phis=ss.phi1)
    return request.param, ss, vals, end


@pytest.mark.slow
def test_omega_of_phi_against_lagrange_multipliers(compared):
    name, ss, vals, end = compared
    rel = np.max(np.abs(vals[0] - ss.omega) / ss.omega)
    assert rel <= 1e-6, (name, rel)
    assert ss.period == pytest.approx(end[1], rel=1e-6)
    np.testing.assert_allclose(ss.t, vals[1], rtol=0, atol=1e-6 * ss.period)
    assert ss.error_estimate <= 1e-6
    assert 0.0 < ss.delta < 2.0
    # the real-speed dynamics carry the same driving torque as the reduced equation
    scale = np.max(np.abs(ss.Q))
    assert np.max(np.abs(ss.dynamics.Q - ss.Q)) <= 1e-8 * scale


@pytest.mark.slow
def test_delta_against_lagrange_multipliers(compared):
    """delta from the reference's dense omega(phi) (sampled 20 times finer) against ours (the
    extremes refined on the collocation's cubic): 1e-6 of delta."""
    _name, ss, vals, end = compared
    assert ss.omega_max >= np.max(vals[0]) - 1e-9 * ss.omega_mean
    assert ss.omega_min <= np.min(vals[0]) + 1e-9 * ss.omega_mean
    assert ss.omega_mean == pytest.approx(2 * np.pi / end[1], rel=1e-9)


def _with_friction(mech, f=0.08, r=0.012):
    joints = tuple(Revolute(j.name, j.a, j.b, j.point_a, j.point_b, friction=f, radius=r)
                   if isinstance(j, Revolute) else j for j in mech.joints)
    return Mechanism(mech.frame, mech.bodies, joints, mech.driver, mech.branches)


def test_energy_balance_over_a_cycle_with_friction_gear_and_jumping_loads():
    """The sine press in the engine: 8 kN over phi1 = 100..150 deg (jumps there: nodes with
    one-sided values), friction in the revolutes, a gear of efficiency 0.9."""
    doc = io.load("examples/sine_press_planar.toml")
    mech = _with_friction(doc.mechanism())
    motor = InductionMotor(1500.0, 1500 * RPM, 1410 * RPM, 2.6, inertia=0.004)
    ss = steady_state(mech, motor, loads=doc.loads, gravity=doc.analysis.gravity,
                      gear=Gear(1410 / 120, 0.9, 0.001), flywheel=1.5, n=360,
                      breaks=np.radians([100.0, 150.0]))
    e = ss.energy
    assert e["friction"] > 0 and e["gear"] > 0 and e["loads"] > 0
    assert abs(e["residual"]) <= 1e-8 * e["motor"]
    assert e["motor"] == pytest.approx(e["loads"] + e["gravity"] + e["friction"] + e["gear"],
                                       rel=1e-8)
    # the press force's work: 8 kN over the ram's travel between 100 and 150 deg
    x = kinematics(mech, np.radians([100.0, 150.0])).point("ram", "S").x
    assert e["loads"] == pytest.approx(-8e3 * (x[1] - x[0]), rel=1e-9)  # Simpson, one-sided
    assert ss.error_estimate < 1e-7
    # without the jumps as nodes the same solve is first-order near them
    rough = steady_state(mech, motor, loads=doc.loads, gravity=doc.analysis.gravity,
                         gear=Gear(1410 / 120, 0.9, 0.001), flywheel=1.5, n=362,
                         dynamics=False)
    assert rough.error_estimate > 10 * ss.error_estimate


@pytest.mark.parametrize("motor", [ConstantSpeed(12.0), DCMotor(30.0, 13.0)])
def test_friction_adds_its_losses_over_two_pi_to_the_mean_torque(motor):
    """Issue 16 item 5: with friction, mean motor torque = frictionless one + W_f / (2 pi),
    W_f the cycle's friction losses (from the engine's friction powers of the real motion)."""
    doc = io.load("examples/fourbar_paper001.toml")
    loads = [PointForce("coupler", "P", 0.0, -30.0), ]
    base = doc.mechanism()
    mech = _with_friction(base)
    free = steady_state(base, motor, loads=loads, gravity=G, flywheel=0.05)
    fric = steady_state(mech, motor, loads=loads, gravity=G, flywheel=0.05)
    losses = fric.energy["friction"]
    assert losses > 0
    assert fric.torque_mean == pytest.approx(free.torque_mean + losses / (2 * np.pi),
                                             rel=1e-9)
    # the losses are those the engine's friction powers give over the real motion's time
    dyn = fric.dynamics
    w_f = np.sum(dyn.friction_power, axis=0)
    trapezoid = float(np.sum(w_f * np.gradient(fric.t, edge_order=2)))
    assert losses == pytest.approx(trapezoid, rel=1e-3)
    assert fric.friction_iterations >= 1


def test_constant_speed_is_the_engines_constant_speed_analysis():
    doc = io.load("examples/loom_sixbar.toml")
    mech = doc.mechanism()
    ss = steady_state(mech, ConstantSpeed(40 * RPM * 36), gear=Gear(36.0), loads=doc.loads,
                      gravity=doc.analysis.gravity, breaks=np.radians([145.0, 184.7]))
    assert ss.delta == 0.0
    assert np.all(ss.eps == 0.0)
    np.testing.assert_allclose(ss.Q, ss.dynamics_constant.Q, rtol=1e-9,
                               atol=1e-9 * np.max(np.abs(ss.Q)))
    # at the jumps of the coining force: the value just after, on both
    k = int(np.argmin(np.abs(ss.phi1 - np.radians(184.7))))
    assert ss.M_loads[k] == 0.0 and ss.M_loads[k - 1] < 0.0
    np.testing.assert_allclose(ss.torque * 36.0, ss.Q, rtol=1e-12)


def test_comparison_of_real_and_constant_speed_peaks():
    mech, loads, _, motor, gear, fw = CASES["fourbar-dc"]()
    ss = steady_state(mech, motor, loads=loads, gravity=G, gear=gear, flywheel=fw)
    rows = {r["name"]: r for r in ss.comparison()}
    assert set(rows) >= {"|Q| max", "|R O| max", "|F_sh| max", "|M_sh| max"}
    for r in rows.values():
        assert r["ratio"] == pytest.approx(r["real"] / r["constant"])
    # the real motion (delta ~ 0.3) differs visibly from the constant-speed assumption
    assert abs(rows["|F_sh| max"]["ratio"] - 1) > 0.05


def test_machine_is_reduced_once_for_many_solves():
    mech, loads, _, motor, _gear, _ = CASES["fourbar-dc"]()
    m = machine(mech, motor, loads=loads, gravity=G)
    deltas = [steady_state(m.with_flywheel(fw), dynamics=False).delta for fw in (0, 0.1, 1.0)]
    assert deltas[0] > deltas[1] > deltas[2] > 0


def test_motor_too_weak_names_mean_load_and_breakdown_torque():
    mech, _loads, _, _, _, _ = CASES["fourbar-dc"]()
    weak = InductionMotor(20.0, 1500 * RPM, 1400 * RPM, 2.0)
    with pytest.raises(DriveError, match=r"mean load torque [\d.]+ N·m \([\d.]+ N·m at the motor "
                       r"through the gear i = 15.*exceeds the motor's breakdown torque"):
        steady_state(mech, weak, loads=[BodyTorque("crank", -30.0)], gear=Gear(15.0))


def test_stall_within_the_cycle_is_an_error_not_a_silent_non_convergence():
    """A constant force has no mean load (it is conservative), but its peak torque throws a
    small motor without inertia off: the crank stops."""
    mech, _, _, _, _, _ = CASES["fourbar-dc"]()
    weak = InductionMotor(20.0, 1500 * RPM, 1400 * RPM, 2.0)
    with pytest.raises(DriveError, match=r"the crank stops at phi1 = [\d.]+ deg.*peak load "
                       r"torque [\d.]+ N·m at the crank"):
        steady_state(mech, weak, loads=[PointForce("coupler", "P", 0, -400.0)], gear=Gear(15.0))


def test_dampers_in_the_steady_state_energy_and_driving_torque():
    """A viscous damper on the rocker: its work (-damping omega over the cycle) is in the
    energy balance, and the engine's driving torque of the real motion (dampers included) is
    the reduced equation's to 1e-8."""
    mech, loads, _, motor, gear, _ = CASES["fourbar-dc"]()

    def lds(p):
        return [*loads(p), Damper("frame", (0.45, 0.2), "rocker", "B", damping=30.0)]

    ss = steady_state(mech, motor, loads=lds, gravity=G, gear=gear, flywheel=0.05)
    free = steady_state(mech, motor, loads=loads, gravity=G, gear=gear, flywheel=0.05)
    assert ss.energy["loads"] > free.energy["loads"]          # the damper takes work
    assert np.all(ss.M_damping <= 0)
    assert abs(ss.energy["residual"]) <= 1e-8 * ss.energy["motor"]
    assert np.max(np.abs(ss.dynamics.Q - ss.Q)) <= 1e-8 * np.max(np.abs(ss.Q))
