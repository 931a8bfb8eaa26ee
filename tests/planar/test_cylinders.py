"""Driven cylinders (linear actuators between two moving bodies) in closed form.

References: (1) the same mechanism with its cylinder groups handed to the engine's Newton solver
(the plan's cylinder groups relabelled ``newton``: Newton from the drawn poses, continued from
the drawing), to 1e-9 of the size; (2) the independent loop equations, complex-step rates and
Newton-Euler equations with Lagrange multipliers of ``tests/_planar_newton_euler.py``
(tolerance 1e-6 relative with a floor of 1e-9 of the scale); (3) the power of the three
cylinders equal to the rate of the kinetic energy minus the power of gravity, the digging load
and a gas spring, to 1e-9 of the largest term. Example: ``examples/excavator_boom.toml``.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from _planar_newton_euler import _check_engine, energy_rate

from linkwork import io
from linkwork.errors import ParameterError
from linkwork.planar import Cylinder, PointForce, Spring, inverse_dynamics, kinematics, sketch

ROOT = Path(__file__).resolve().parents[2]


def excavator():
    doc = io.load(ROOT / "examples" / "excavator_boom.toml")
    return doc, doc.mechanism()


def lifting_table():
    """A cylinder from a frame pivot A to a pin C on a link that slides on a horizontal frame
    guide and carries a platform point P: a cyl-RRP group."""
    pts = {"A": (0.0, 0.0), "C": (0.6, 0.25), "P": (0.7, 0.6)}
    return sketch(pts, {"table": ["C", "P"]}, ground=["A"], drivers="cyl",
                  cylinders={"cyl": Cylinder("A", "C")},
                  sliders={"G": {"point": "C", "guide": "frame", "angle": 0.0,
                                 "body": "table"}},
                  masses={"table": {"mass": 40.0, "inertia": 0.8}, "cyl_barrel": 5.0,
                          "cyl_rod": 2.0})


def as_newton(mech):
    """The mechanism with every cylinder group solved by the engine's Newton iteration."""
    plan = mech.plan
    groups = tuple(dataclasses.replace(g, kind="newton") if g.kind.startswith("cyl-") else g
                   for g in plan.groups)
    other = dataclasses.replace(mech)
    other.__dict__["plan"] = dataclasses.replace(plan, groups=groups, newton=True)
    return other


def test_excavator_is_three_closed_form_cylinder_triangles():
    _, mech = excavator()
    kinds = [g.kind for g in mech.structure.groups]
    assert kinds == ["cyl-RRR"] * 3 and mech.structure.mobility == 3
    assert [d.joint for d in mech.drivers] == ["boom_cyl", "arm_cyl", "bucket_cyl"]
    # the drawn lengths are the drawn pin-to-pin distances
    pts = mech.drawing.points
    for d, (a, c) in zip(mech.drawing.positions, (("A1", "C1"), ("A2", "C2"), ("A3", "C3")),
                         strict=True):
        assert d == pytest.approx(np.hypot(*np.subtract(pts[c], pts[a])), abs=1e-15)
    assert not mech.plan.newton


@pytest.mark.parametrize("build", [lambda: excavator()[1], lifting_table])
def test_cylinder_groups_equal_the_newton_solution(build):
    """Closed form against Newton on the same constraints, every body's pose and rates."""
    mech = build()
    ref = np.array(mech.drawing.positions)
    nd = len(ref)
    span = np.linspace(-0.08, 0.1, nd)[:, None] if nd > 1 else -0.15
    phi = ref[:, None] + span * np.linspace(0.0, 1.0, 31)[None, :]
    phi = phi if nd > 1 else phi[0]
    w = np.linspace(0.05, -0.04, nd) if nd > 1 else 0.05
    k1 = kinematics(mech, phi, w, 0.02)
    k2 = kinematics(as_newton(mech), phi, w, 0.02)
    for f, scale in (("x", 5.0), ("y", 5.0), ("theta", 1.0), ("vx", 1.0), ("omega", 1.0),
                     ("ax", 1.0), ("eps", 1.0)):
        assert np.max(np.abs(getattr(k1, f) - getattr(k2, f))) <= 1e-9 * scale, f


def test_excavator_against_newton_euler():
    """Three cylinders with gravity and the digging load at the tooth: poses, rates, every
    reaction, the three cylinder forces, shaking and kinetic energy at 5 positions of the
    file's path against the independent reference (speeds and accelerations of each
    cylinder different and non-zero)."""
    doc, mech = excavator()
    phi = doc.positions()[:, ::20]
    loads = [PointForce("bucket", "K", fx=-12e3, fy=4e3)]
    _check_engine(mech, phi, np.array([0.045, -0.0625, 0.05]), np.array([0.01, 0.02, -0.015]),
                  (0.0, -9.81), loads, label="excavator ")


def test_cylinder_table_against_newton_euler():
    mech = lifting_table()
    phi = mech.drawing.positions[0] + np.linspace(-0.1, 0.05, 6)
    _check_engine(mech, phi, 0.08, -0.3, (0.0, -9.81), [PointForce("table", "P", fy=-900.0)],
                  label="lifting table ")


def test_power_of_three_cylinders_with_a_gas_spring():
    """The three cylinders' power = dT/dt - P_gravity - P_load - P_spring at every position of
    the file's path with a gas spring (push 6 kN, rate 20 kN/m) from the frame point A1 to the
    boom's point A2 added: the spring's power -F dL/dt from its tension F and the rate of its
    length, both from the kinematics (to 1e-9 of the largest term)."""
    doc, mech = excavator()
    phi = doc.positions()
    w = np.array([0.045, -0.0625, 0.05])
    e = np.array([0.004, 0.003, -0.002])
    kin = kinematics(mech, phi, w, e)
    spring = Spring("frame", "A1", "boom", "A2", stiffness=2e4, free_length=2.0, preload=-6e3,
                    name="gas")
    loads = [*doc.loads(phi), spring]
    dyn = inverse_dynamics(kin, gravity=(0.0, -9.81), loads=loads)
    dT, p = energy_rate(mech, kin, (0.0, -9.81))
    tooth = kin.point("bucket", "K")
    p += -12e3 * tooth.vx + 4e3 * tooth.vy
    A1 = np.array(mech.frame.points["A1"])
    A2 = kin.point("boom", "A2")
    dx, dy = A2.x - A1[0], A2.y - A1[1]
    L = np.hypot(dx, dy)
    tension = -6e3 + 2e4 * (L - 2.0)
    p += -tension * (dx * A2.vx + dy * A2.vy) / L
    scale = float(np.max(np.abs(dyn.power)))
    assert np.max(np.abs(dyn.total_power - (dT - p))) <= 1e-9 * scale


def test_cylinder_branch_from_the_drawing_and_flipped():
    """The boom drawn above the line from the cylinder's pivot to the boom's pivot takes that
    assembly; the other branch mirrors the pin C about that line at the same length."""
    _, mech = excavator()
    key = mech.structure.groups[0].key
    assert key == "C1"
    b = mech.branches[key]
    q = np.array(mech.drawing.positions)[:, None]
    k1 = kinematics(mech, q, 0.0)
    k2 = kinematics(mech.with_branches(C1=-b), q, 0.0)
    c1, c2 = k1.point("boom", "C1"), k2.point("boom", "C1")
    A1, O = np.array(mech.drawing.points["A1"]), np.array(mech.drawing.points["O"])
    for c in (c1, c2):  # both at the cylinder's length from A1 and the boom's from O
        assert np.hypot(c.x[0] - A1[0], c.y[0] - A1[1]) == pytest.approx(q[0, 0], abs=1e-12)
    assert (c1.x[0], c1.y[0]) == pytest.approx(mech.drawing.points["C1"], abs=1e-12)
    # mirror images about the line A1 -> O
    u = (O - A1) / np.hypot(*(O - A1))
    side = [float(u[0] * (c.y[0] - A1[1]) - u[1] * (c.x[0] - A1[0])) for c in (c1, c2)]
    assert side[0] == pytest.approx(-side[1], rel=1e-12)


def test_cylinder_errors():
    pts = {"O": (0, 0), "A": (0.3, -0.2), "C": (0.8, 0.1), "T": (1.6, 0.4), "Z": (2, 2)}
    with pytest.raises(ParameterError, match=r"cylinders\.cyl = Z .*hinged to nothing"):
        sketch(pts, {"boom": ["O", "C", "T"]}, ground=["O", "A"], drivers="cyl",
               cylinders={"cyl": ("A", "Z")})
    with pytest.raises(ParameterError, match=r"pivots coincide"):
        sketch({**pts, "D": (0.3, -0.2)}, {"boom": ["O", "C", "T", "D"]}, ground=["O", "A"],
               drivers="cyl", cylinders={"cyl": ("A", "D")})
    del pts["Z"]
    with pytest.raises(ParameterError, match=r"must be .start, end."):
        sketch(pts, {"boom": ["O", "C", "T"]}, ground=["O", "A"], drivers="cyl",
               cylinders={"cyl": "AC"})
