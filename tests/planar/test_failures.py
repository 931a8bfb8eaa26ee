"""Mechanisms that cannot move, cannot be assembled, or are described wrongly."""

from __future__ import annotations

import numpy as np
import pytest

from linkwork.errors import AssemblyError, ParameterError, StructureError, angle_ranges
from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    Linear,
    Mechanism,
    PointForce,
    Revolute,
    bar,
    fourbar,
    inverse_dynamics,
    kinematics,
)


def test_locked_triangle_names_bodies_and_joints():
    frame = Body("frame", {"O": (0, 0), "C": (0.3, 0)})
    crank = bar("crank", "O", "A", 0.1)
    rod = bar("rod", "A", "C", 0.3)
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "rod"),
              Revolute("C", "rod", "frame"))
    with pytest.raises(StructureError, match=r"locked.*W = 3\*2 - 2\*3 - 0 = 0.*crank"):
        Mechanism(frame, (crank, rod), joints, Crank("O")).validate()


def test_under_driven_five_bar():
    frame = Body("frame", {"O": (0, 0), "E": (0.4, 0)})
    bodies = (bar("crank", "O", "A", 0.1), bar("l2", "A", "B", 0.3), bar("l3", "B", "C", 0.3),
              bar("l4", "E", "C", 0.2))
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "l2"),
              Revolute("B", "l2", "l3"), Revolute("C", "l3", "l4"), Revolute("E", "frame", "l4"))
    with pytest.raises(StructureError, match="under-driven: mobility W = 3\\*4 - 2\\*5 - 0 = 2"):
        kinematics(Mechanism(frame, bodies, joints, Crank("O")), [0.0])


def test_locked_subchain_with_free_body_elsewhere():
    """W = 1 by count, but the driven crank sits in a rigid triangle, and a four-bar elsewhere
    has no driver: the error names the locked sub-chain."""
    frame = Body("frame", {"O": (0, 0), "C": (0.3, 0), "E": (0.6, 0.0), "F": (0.9, 0.0)})
    bodies = (bar("crank", "O", "A", 0.1), bar("rod", "A", "C", 0.3),
              bar("p", "E", "G", 0.1), bar("q", "G", "H", 0.3), bar("r", "F", "H", 0.2))
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "rod"),
              Revolute("C", "rod", "frame"), Revolute("E", "frame", "p"),
              Revolute("G", "p", "q"), Revolute("H", "q", "r"), Revolute("F", "frame", "r"))
    with pytest.raises(StructureError, match=r"sub-chain is locked: 4 constraints on 3 .*'rod'"):
        Mechanism(frame, bodies, joints, Crank("O")).validate()


def test_redundant_link_is_a_locked_subchain():
    """A parallelogram with a third parallel bar: counted W = 0 -> locked."""
    frame = Body("frame", {"O": (0, 0), "C": (0.3, 0), "E": (0.15, 0.0)})
    bodies = (bar("crank", "O", "A", 0.1, points={"M": (0.05, 0.0)}),
              bar("coupler", "A", "B", 0.3, points={"N": (0.15, 0.0)}),
              bar("rocker", "C", "B", 0.1), bar("extra", "E", "N", 0.1))
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "coupler"),
              Revolute("B", "coupler", "rocker"), Revolute("C", "frame", "rocker"),
              Revolute("E", "frame", "extra"), Revolute("N", "coupler", "extra"))
    with pytest.raises(StructureError, match=r"locked: mobility W = 3\*4 - 2\*6 - 0 = 0"):
        Mechanism(frame, bodies, joints, Crank("O")).validate()


def test_cannot_assemble_lists_ranges():
    # non-Grashof: crank 0.25 cannot turn fully with coupler 0.3, rocker 0.2, frame 0.3
    mech = fourbar(0.25, 0.3, 0.2, 0.3)
    phi = np.radians(np.arange(0, 360, 1.0))
    with pytest.raises(AssemblyError) as exc:
        kinematics(mech, phi)
    # independent: |b - c| <= |A - O4| <= b + c
    reach = np.hypot(0.3 - 0.25 * np.cos(phi), 0.25 * np.sin(phi))
    bad = (reach > 0.5) | (reach < 0.1)
    assert exc.value.ranges == angle_ranges(phi, bad)
    assert len(exc.value.ranges) == 3
    assert "cannot assemble at phi1 in [" in str(exc.value)


def test_nan_and_mask_on_request():
    mech = fourbar(0.25, 0.3, 0.2, 0.3)
    phi = np.radians(np.arange(0, 360, 1.0))
    k = kinematics(mech, phi, on_fail="nan")
    Ax = 0.25 * np.cos(phi)
    reach = np.hypot(0.3 - Ax, 0.25 * np.sin(phi))
    expected = (reach <= 0.5) & (reach >= 0.1)
    np.testing.assert_array_equal(k.assembled, expected)
    assert np.isnan(k.theta[2][~expected]).all()
    assert np.isfinite(k.theta[2][expected]).all()
    d = inverse_dynamics(k)
    assert np.isnan(d.Q[~expected]).all() and np.isfinite(d.Q[expected]).all()


def test_bad_inputs_name_parameter():
    m = fourbar(0.1, 0.3, 0.2, 0.3)
    with pytest.raises(ParameterError, match="phi1"):
        kinematics(m, [0.0, np.nan])
    with pytest.raises(ParameterError, match="on_fail"):
        kinematics(m, [0.0], on_fail="ignore")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"branches\.B"):
        kinematics(m, [0.0], branches={"B": 2})
    with pytest.raises(ParameterError, match="omega1"):
        kinematics(m, [0.0, 1.0], omega1=[1.0, 2.0, 3.0])
    with pytest.raises(ParameterError, match="mass"):
        bar("x", "A", "B", 0.1, mass=-1.0)
    with pytest.raises(ParameterError, match="length"):
        bar("x", "A", "B", 0.0)
    with pytest.raises(ParameterError, match="no such point"):
        Mechanism(Body("frame", {"O": (0, 0)}), (bar("c", "O", "A", 0.1),),
                  (Revolute("Q", "frame", "c"),), Crank("Q"))
    with pytest.raises(ParameterError, match="unknown body"):
        Mechanism(Body("frame", {"O": (0, 0)}), (bar("c", "O", "A", 0.1),),
                  (Revolute("O", "frame", "k"),), Crank("O"))
    with pytest.raises(ParameterError, match="Linear driver needs a prismatic"):
        Mechanism(Body("frame", {"O": (0, 0)}), (bar("c", "O", "A", 0.1),),
                  (Revolute("O", "frame", "c"),), Linear("O"))
    with pytest.raises(ParameterError, match="unique"):
        Mechanism(Body("frame", {"O": (0, 0)}), (bar("c", "O", "A", 0.1),
                                                  bar("c", "O", "A", 0.1)),
                  (Revolute("O", "frame", "c"),), Crank("O"))
    k = kinematics(m, [0.0, 1.0])
    with pytest.raises(ParameterError, match=r"loads\.body"):
        inverse_dynamics(k, loads=[PointForce("frame", "O2", 1.0, 0.0)])
    with pytest.raises(ParameterError, match="fx"):
        inverse_dynamics(k, loads=[PointForce("crank", "A", [1.0, 2.0, 3.0], 0.0)])
    with pytest.raises(ParameterError, match=r"loads\[1\]\.fy = \(3,\)"):  # which load
        inverse_dynamics(k, loads=[PointForce("crank", "A", 1.0, 0.0),
                                   PointForce("crank", "A", 0.0, [1.0, 2.0, 3.0])])
    with pytest.raises(ParameterError, match=r"loads\[0\]\.mz"):
        inverse_dynamics(k, loads=[BodyTorque("crank", [np.nan, 1.0])])
    with pytest.raises(ParameterError, match="gravity"):
        inverse_dynamics(k, gravity=(0.0, -9.81, 0.0))


def test_change_point_toggle_is_reported():
    """a + b = c + d: at phi1 = 0 coupler and rocker are collinear, velocities undefined."""
    mech = fourbar(0.1, 0.3, 0.2, 0.2)
    phi = np.linspace(0, 2 * np.pi, 13)
    with pytest.raises(AssemblyError, match=r"singular \(toggle\).*at phi1 in 0 deg$"):
        kinematics(mech, phi)
    k = kinematics(mech, phi, on_fail="nan")
    np.testing.assert_array_equal(k.assembled, [False] + [True] * 11 + [False])
    assert np.isnan(k.omega[3][0]) and np.isfinite(k.omega[3][1:-1]).all()


def test_a_body_without_joints_is_named_as_such():
    """A body left unconnected was reported as 'under-driven: mobility W = 4' (its three free
    coordinates), which sends the user looking for a missing driver."""
    m = fourbar(0.1, 0.3, 0.2, 0.3)
    extra = (bar("lonely", "P", "Q", 0.1), bar("stray", "P", "Q", 0.1))
    with pytest.raises(StructureError, match=r"body 'lonely' has no joints"):
        Mechanism(m.frame, (*m.bodies, extra[0]), m.joints, m.driver).validate()
    with pytest.raises(StructureError, match=r"bodies 'lonely', 'stray' have no joints"):
        Mechanism(m.frame, (*m.bodies, *extra), m.joints, m.driver).validate()
