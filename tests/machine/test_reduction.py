"""Reduction of a mechanism to its crank (linkwork.machine.reduction).

J(phi) and dJ/dphi are checked against (a) the engine's kinetic energy at an arbitrary speed
(T = J omega^2 / 2, to 1e-12 relative), (b) a fourth-order central difference of J itself
(Richardson of steps 1e-3 and 5e-4 rad: error ~1e-11 of max|dJ|, tolerance 1e-8), and (c) the
engine's inverse dynamics, an independent path (d'Alembert's inertia forces and the joint
equilibrium): the driving torque of any motion omega(phi), eps(phi) equals
J eps + dJ/2 omega^2 - M_loads - M_gravity to 1e-10 of the torque scale; with friction,
M_f = Q0 - Q equals minus the joints' friction power over omega to 1e-10 of its scale.
"""

from __future__ import annotations

import numpy as np
import pytest

from linkwork import io
from linkwork.errors import ParameterError
from linkwork.machine import friction_moment, reduce
from linkwork.planar import (
    BodyTorque,
    Damper,
    Drag,
    Linear,
    Mechanism,
    PointForce,
    Revolute,
    Spring,
    inverse_dynamics,
    kinematics,
)

EXAMPLES = ["examples/fourbar_paper001.toml", "examples/loom_sixbar.toml",
            "examples/sine_press_planar.toml"]


def _doc(path):
    return io.load(path)


@pytest.mark.parametrize("path", EXAMPLES)
def test_J_is_twice_the_engines_kinetic_energy_over_omega_squared(path):
    doc = _doc(path)
    mech = doc.mechanism()
    phi = np.linspace(0, 2 * np.pi, 181, endpoint=False)
    red = reduce(mech, phi)
    w = 7.3
    dyn = inverse_dynamics(kinematics(mech, phi, w, 0.0))
    np.testing.assert_allclose(red.J, 2 * dyn.T / w**2, rtol=1e-12)


@pytest.mark.parametrize("path", EXAMPLES)
def test_dJ_is_the_derivative_of_J(path):
    mech = _doc(path).mechanism()
    phi = np.linspace(0.01, 2 * np.pi, 97, endpoint=False)
    red = reduce(mech, phi)

    def central(h):
        return (reduce(mech, phi + h).J - reduce(mech, phi - h).J) / (2 * h)

    fd = (4 * central(5e-4) - central(1e-3)) / 3  # Richardson: O(h^4)
    scale = np.max(np.abs(red.dJ))
    assert np.max(np.abs(red.dJ - fd)) <= 1e-8 * scale


@pytest.mark.parametrize("path", EXAMPLES)
def test_engine_driving_torque_is_the_reduced_equation(path):
    """Q(phi, omega, eps) of the engine = J eps + dJ omega^2 / 2 - M_loads - M_gravity, for a
    motion with varying speed and acceleration, gravity and the file's loads."""
    doc = _doc(path)
    mech = doc.mechanism()
    phi = np.linspace(0, 2 * np.pi, 241, endpoint=False)
    g = (0.3, -9.81)
    red = reduce(mech, phi, loads=doc.loads, gravity=g)
    omega = 6.0 + 1.5 * np.sin(phi) + 0.4 * np.cos(3 * phi)
    eps = 17.0 * np.cos(2 * phi) - 3.0
    dyn = inverse_dynamics(kinematics(mech, phi, omega, eps), gravity=g, loads=doc.loads(phi))
    expected = red.J * eps + 0.5 * red.dJ * omega**2 - red.M
    scale = np.max(np.abs(dyn.Q))
    assert np.max(np.abs(dyn.Q_frictionless - expected)) <= 1e-10 * scale


def test_loads_as_sequence_or_function_and_body_torques():
    doc = _doc("examples/fourbar_paper001.toml")
    mech = doc.mechanism()
    phi = np.linspace(0, 2 * np.pi, 73, endpoint=False)
    loads = [PointForce("coupler", "P", 3.0, -20.0), BodyTorque("rocker", 1.5 * np.sin(phi))]
    a = reduce(mech, phi, loads=loads)
    b = reduce(mech, phi, loads=lambda p: [PointForce("coupler", "P", 3.0, -20.0),
                                           BodyTorque("rocker", 1.5 * np.sin(p))])
    np.testing.assert_array_equal(a.M_loads, b.M_loads)
    kin = kinematics(mech, phi, 1.0, 0.0)
    p = kin.point("coupler", "P")
    expected = 3.0 * p.vx - 20.0 * p.vy + 1.5 * np.sin(phi) * kin.omega[mech.index["rocker"]]
    np.testing.assert_allclose(a.M_loads, expected, rtol=1e-13, atol=1e-13)


def test_friction_moment_is_minus_the_friction_power_over_omega():
    doc = _doc("examples/fourbar_paper001.toml")
    mech = doc.mechanism()
    joints = tuple(Revolute(j.name, j.a, j.b, friction=0.1, radius=0.01) for j in mech.joints)
    mf = Mechanism(mech.frame, mech.bodies, joints, mech.driver, mech.branches)
    phi = np.linspace(0, 2 * np.pi, 121, endpoint=False)
    omega = 10 + np.sin(phi)
    eps = 5 * np.cos(phi)
    M_f = friction_moment(mf, phi, omega, eps, gravity=(0, -9.81))
    dyn = inverse_dynamics(kinematics(mf, phi, omega, eps), gravity=(0, -9.81))
    expected = -np.sum(dyn.friction_power, axis=0) / omega
    assert np.all(M_f <= 1e-12)
    assert np.max(np.abs(M_f - expected)) <= 1e-10 * np.max(np.abs(expected))
    assert np.all(friction_moment(mech, phi, omega, eps) == 0.0)


def test_only_a_crank_on_a_frame_joint_is_reduced():
    doc = io.load("tests/data/slider_driven_crank.toml")
    mech = doc.mechanism()
    assert isinstance(mech.driver, Linear)
    with pytest.raises(ParameterError, match=r"driver.*must be a Crank"):
        reduce(mech, [0.0])
    four = _doc("examples/fourbar_paper001.toml").mechanism()
    with pytest.raises(ParameterError, match="loads"):
        reduce(four, [0.0, 1.0], loads=PointForce("coupler", "P", 1.0, 0.0))
    with pytest.raises(ParameterError, match=r"loads\[0\].body"):
        reduce(four, [0.0, 1.0], loads=[BodyTorque("frame", 1.0)])


def test_dampers_and_drags_reduce_to_a_moment_linear_in_the_speed():
    """A damper between frame and rocker and a drag on the coupler point: the engine's driving
    torque at any omega, eps is J eps + dJ omega^2 / 2 - M_loads + damping omega (1e-10)."""
    doc = _doc("examples/fourbar_paper001.toml")
    mech = doc.mechanism()
    loads = [Damper("frame", (0.45, 0.2), "rocker", "B", damping=40.0),
             Drag("coupler", "P", force=3.0, damping=2.0),
             Spring("frame", (0.0, 0.3), "coupler", "P", stiffness=500.0, free_length=0.1)]
    phi = np.linspace(0, 2 * np.pi, 181, endpoint=False)
    red = reduce(mech, phi, loads=loads)
    assert np.all(red.damping >= 0) and np.max(red.damping) > 0
    omega = 6.0 + 2.0 * np.sin(phi)
    eps = 9.0 * np.cos(phi)
    dyn = inverse_dynamics(kinematics(mech, phi, omega, eps), loads=loads)
    expected = red.J * eps + 0.5 * red.dJ * omega**2 - red.M_loads + red.damping * omega
    assert np.max(np.abs(dyn.Q - expected)) <= 1e-10 * np.max(np.abs(dyn.Q))
