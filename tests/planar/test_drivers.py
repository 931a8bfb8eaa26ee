"""Several drivers (mobility W > 1): kinematics and inverse dynamics against independent
references.

References (``tests/_planar_newton_euler.py``): the loop equations with every driver's
constraint solved by a Newton iteration of the test's own, rates by complex step and
accelerations by finite differences of the complex-step velocities in time (each driver moving as
phi_d + w_d t + e_d t^2/2), and the Newton-Euler equations of every body assembled per position
with one Lagrange multiplier per constraint and one driving load per driver (tolerance 1e-6
relative with a floor of 1e-9 of the quantity's scale). Power balance: the sum of every
driver's power equals the rate of the kinetic energy (from the kinematics, sum m v.a + I w e)
minus the power of gravity and the loads, to 1e-9 of the largest term.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from _mechanisms import crank_and_ram, five_bar
from _planar_newton_euler import _check_engine, energy_rate

from linkwork.errors import ParameterError, StructureError
from linkwork.planar import (
    BodyTorque,
    Crank,
    Linear,
    Mechanism,
    PointForce,
    inverse_dynamics,
    kinematics,
    sketch,
)


def _path(mech, span, n):
    """Driver positions moving from the drawing by ``span`` (per driver) over n positions."""
    t = np.linspace(0.0, 1.0, n)
    return np.array(mech.drawing.positions)[:, None] + np.asarray(span)[:, None] * t


@pytest.mark.parametrize(("build", "span", "w", "e"), [
    (five_bar, (1.2, -0.8), (6.0, -4.0), (20.0, 15.0)),
    (crank_and_ram, (2.0, -0.06), (8.0, -0.3), (-25.0, 0.8)),
])
def test_several_drivers_against_newton_euler(build, span, w, e):
    """Two cranks, and a crank with a linear actuator: poses, velocities, accelerations, every
    reaction, both driving loads, the shaking force and moment and the kinetic energy at 7
    positions against the independent reference (gravity, a point force and a couple)."""
    mech = build()
    phi = _path(mech, span, 7)
    body = mech.bodies[-1].name
    loads = [PointForce(mech.bodies[2].name, "P", fx=30.0, fy=-12.0), BodyTorque(body, 2.5)]
    _check_engine(mech, phi, np.array(w), np.array(e), (0.0, -9.81), loads,
                  about=(0.03, -0.01), label=f"{build.__name__} ")


@pytest.mark.parametrize("build", [five_bar, crank_and_ram])
def test_power_of_all_drivers_balances_kinetic_energy(build):
    """sum_d Q_d w_d = dT/dt - P_gravity - P_loads at every position, with per-position driver
    speeds and accelerations (dT/dt = sum m v_C.a_C + I w eps from the kinematics)."""
    mech = build()
    n = 61
    phi = _path(mech, (1.0, -0.5) if build is five_bar else (1.5, -0.04), n)
    w = np.array([[5.0], [-3.0 if build is five_bar else -0.2]]) * (1 + 0.3 * np.sin(
        np.linspace(0, 3, n)))
    e = np.array([[12.0], [4.0 if build is five_bar else 0.3]]) * np.cos(np.linspace(0, 2, n))
    g = (0.0, -9.81)
    loads = [PointForce(mech.bodies[1].name, "com", fx=-20.0, fy=7.0),
             BodyTorque(mech.bodies[0].name, -1.5)]
    kin = kinematics(mech, phi, w, e)
    dyn = inverse_dynamics(kin, gravity=g, loads=loads)
    assert dyn.Q.shape == (2, n) and dyn.power.shape == (2, n)
    dT, p_ext = energy_rate(mech, kin, g)
    c = kin.point(mech.bodies[1].name, "com")
    p_ext += -20.0 * c.vx + 7.0 * c.vy
    p_ext += -1.5 * kin.omega[mech.index[mech.bodies[0].name]]
    lhs = np.sum(dyn.Q * kin.omega1, axis=0)
    scale = max(np.max(np.abs(dT)), np.max(np.abs(p_ext)), np.max(np.abs(dyn.power)))
    assert np.max(np.abs(lhs - (dT - p_ext))) <= 1e-9 * scale
    assert np.max(np.abs(dyn.total_power - lhs)) <= 1e-12 * scale


def test_driver_fields_have_one_row_per_driver():
    """Positions, speeds, accelerations and driving loads are (n_drivers, n) in the order of
    Mechanism.drivers; a scalar speed is every driver's; units list each driver's."""
    mech = crank_and_ram()
    assert [d.joint for d in mech.drivers] == ["O", "ram"]
    phi = _path(mech, (0.5, 0.01), 5)
    kin = kinematics(mech, phi, [2.0, 0.1], 0.0)
    assert kin.phi1.shape == kin.omega1.shape == kin.eps1.shape == (2, 5)
    assert np.all(kin.omega1[0] == 2.0) and np.all(kin.omega1[1] == 0.1)
    assert kin.units["phi1"] == "rad, m" and kin.units["omega1"] == "rad/s, m/s"
    dyn = inverse_dynamics(kin)
    assert dyn.units["Q"] == "N*m, N"
    assert kin.n == 5
    k2 = kinematics(mech, phi)  # the drivers' own speeds (1 rad/s, 1 m/s)
    assert np.all(k2.omega1 == 1.0)
    with pytest.raises(ParameterError, match=r"phi1 = \(5,\) .*shape \(2, n\)"):
        kinematics(mech, phi[0])
    with pytest.raises(ParameterError, match="omega1"):
        kinematics(mech, phi, np.ones(3))


def test_unassembled_positions_of_several_drivers_name_each_drivers_values():
    """Beyond the reach of the links: the error lists the position indices and each driver's
    values there."""
    mech = five_bar()
    phi = _path(mech, (-3.0, 3.0), 7)
    with pytest.raises(Exception, match=r"cannot assemble at positions .*O1 .*O2 ") as err:
        kinematics(mech, phi)
    assert err.value.ranges and err.value.driver == "position index"


def test_mobility_must_equal_the_number_of_drivers():
    """A five-bar (W = 2) with one driver is under-driven, a four-bar (W = 1) with two
    drivers over-driven: the counts are named."""
    five = five_bar()
    with pytest.raises(StructureError, match=r"under-driven: mobility W = .* = 2 but one "
                       r"driver \(O1\) is given: give 2 drivers"):
        Mechanism(five.frame, five.bodies, five.joints, Crank("O1")).validate()
    pts = {"O": (0, 0), "A": (0.0, 0.1), "B": (0.3, 0.25), "C": (0.35, 0.0)}
    with pytest.raises(StructureError, match=r"over-driven: mobility W = .* = 1 but 2 drivers "
                       r"\(O, C\) are given: give 1 driver"):
        sketch(pts, {"crank": ["O", "A"], "coupler": ["A", "B"], "rocker": ["C", "B"]},
               ground=["O", "C"], drivers=["O", "C"])
    with pytest.raises(ParameterError, match="driven twice"):
        Mechanism(five.frame, five.bodies, five.joints, (Crank("O1"), Crank("O1")))


def test_one_driver_in_a_sequence_is_the_driver():
    """Mechanism(..., [Crank('O')]) is the one-driver mechanism: Q of shape (n,)."""
    mech = crank_and_ram()
    four = sketch({"O": (0, 0), "A": (0.0, 0.1), "B": (0.3, 0.25), "C": (0.35, 0.0)},
                  {"crank": ["O", "A"], "coupler": ["A", "B"], "rocker": ["C", "B"]},
                  ground=["O", "C"], drivers=["O"])
    assert isinstance(four.driver, Crank) and four.n_drivers == 1
    assert isinstance(mech.drivers[1], Linear)
    dyn = inverse_dynamics(kinematics(four, np.linspace(0, 1, 4)))
    assert dyn.Q.shape == (4,) and np.ndim(dyn.Q_mean) == 0
    assert math.isfinite(dyn.Q_mean)


def test_friction_with_two_drivers_balances_power():
    """Coulomb friction in every revolute of the five-bar (f = 0.15, journal 10 mm, 0.2 N m
    pin friction on one): sum_d Q_d w_d = dT/dt - P_gravity + sum of the friction powers
    (each >= 0) to 1e-9 of the largest term, and the drivers' loads differ from the
    frictionless ones."""
    base = five_bar()
    joints = tuple(dataclasses.replace(j, friction=0.15, radius=0.01,
                                       friction_torque=0.2 if j.name == "P" else 0.0)
                   for j in base.joints)
    mech = dataclasses.replace(base, joints=joints)
    n = 41
    phi = _path(mech, (1.0, -0.6), n)
    kin = kinematics(mech, phi, [5.0, -3.0], [10.0, 4.0])
    dyn = inverse_dynamics(kin, gravity=(0.0, -9.81))
    assert not dyn.locked.any()
    dT, p_g = energy_rate(mech, kin, (0.0, -9.81))
    loss = np.sum(dyn.friction_power, axis=0)
    assert np.all(dyn.friction_power >= -1e-12)
    scale = max(np.max(np.abs(dT)), np.max(np.abs(dyn.power)))
    assert np.max(np.abs(dyn.total_power - (dT - p_g + loss))) <= 1e-9 * scale
    assert np.max(np.abs(dyn.Q - dyn.Q_frictionless)) > 1e-3 * np.max(np.abs(dyn.Q))


def test_spatial_reactions_and_shaking_with_two_drivers():
    """The spatial reactions of the five-bar (redundancy.spatial_reactions) carry both driving
    torques: their in-plane part equals the planar inverse dynamics to 1e-9 (the out-of-plane
    problem is statically indeterminate, q = 3 here); the shaking loads follow the drivers'
    path; paper 001's crank-cycle balancing refuses the two drivers, naming them."""
    from linkwork.balancing.mechanism import force_balance, shaking_loads
    from linkwork.redundancy import spatial_reactions

    mech = five_bar()
    phi = _path(mech, (0.8, -0.4), 9)
    w, e = [2.0, -1.0], [3.0, 0.5]
    sr = spatial_reactions(mech, phi, omega1=w, eps1=e, gravity=(0, -9.81))
    dyn = inverse_dynamics(kinematics(mech, phi, w, e), gravity=(0, -9.81))
    scale = float(np.max(np.abs(dyn.fx)))
    assert sr.Q.shape == (2, 9)
    assert np.max(np.abs(sr.Q - dyn.Q)) <= 1e-9 * scale
    assert np.max(np.abs(sr.fx - dyn.fx)) <= 1e-9 * scale
    assert sr.redundant == 3
    assert {"Q_O1", "Q_O2"} <= set(sr.columns())
    sh = shaking_loads(kinematics(mech, phi, w, e))
    assert np.max(np.abs(sh.fx - dyn.shaking_fx)) <= 1e-9 * scale  # gravity has no x part
    with pytest.raises(ParameterError, match=r"driver = \['O1', 'O2'\].*one turn of one crank"):
        force_balance(mech)
