"""The compiled plan (``Mechanism.plan``, :func:`linkwork.planar.structure.compile_plan`): its
groups, body indices and resolved joints against the structure and the name-based look-ups of
the model, and the solvers running on it without looking anything up by name."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from linkwork.planar import (
    Body,
    Crank,
    Mechanism,
    PinInSlot,
    Revolute,
    bar,
    crank_slider_mechanism,
    dead_centres,
    fourbar_mechanism,
    kinematics,
    transmission_angles,
)
from linkwork.planar.structure import Plan, compile_plan


def _slot_mech() -> Mechanism:
    crank = bar("crank", "O", "A", 0.1)
    rocker = Body("rocker", {"C": (0.0, 0.0)})
    return Mechanism(Body("frame", {"O": (0.0, 0.0), "C": (0.0, -0.25)}), (crank, rocker),
                     (Revolute("O", "frame", "crank"), Revolute("C", "frame", "rocker"),
                      PinInSlot("S", "rocker", "crank", angle=0.3, through="C", point="A")),
                     Crank("O", 2.0, 0.0))


MECHS = [fourbar_mechanism(0.1, 0.3, 0.2, 0.3),
         crank_slider_mechanism(0.05, 0.2, 0.01, guide_angle=0.3), _slot_mech()]


@pytest.mark.parametrize("mech", MECHS, ids=["fourbar", "crank_slider", "slot"])
def test_plan_mirrors_the_structure_and_the_model(mech):
    """Each plan group is the structure's group with names resolved: body indices from
    ``mech.index``, joints in the group's order with their bodies' indices, local geometry from
    ``mech.joint_geometry`` and the line direction (cos, sin) of its angle; only the driver's
    joint drives."""
    plan = mech.plan
    assert isinstance(plan, Plan)
    assert plan is mech.plan  # compiled once
    assert plan.body_names == mech.body_names and plan.nb == len(mech.body_names)
    assert [rj.joint for rj in plan.joints] == list(mech.joints)
    assert [g.group for g in plan.groups] == list(mech.structure.groups)
    for g in plan.groups:
        assert (g.kind, g.key) == (g.group.kind, g.group.key)
        assert g.bodies == tuple(mech.index[b] for b in g.group.bodies)
        assert tuple(rj.joint.name for rj in g.joints) == g.group.joints
        assert g.guesses == tuple(mech.body(b).guess for b in g.group.bodies)
    for k, rj in enumerate(plan.joints):
        j = mech.joints[k]
        assert rj.index == k
        assert (rj.ia, rj.ib) == (mech.index[j.a], mech.index[j.b])
        qa, pb, ang = mech.joint_geometry(j)
        assert (rj.qa, rj.pb, rj.ang) == (qa, pb, ang)
        assert all(isinstance(v, float) for v in (*rj.qa, *rj.pb, rj.ang, *rj.u_loc))
        assert rj.u_loc == (np.cos(ang), np.sin(ang))
        assert rj.drive == (j.name == mech.driver.joint)
        assert rj.other(rj.ia) == rj.ib and rj.other(rj.ib) == rj.ia
    assert plan.driver.joint.name == mech.driver.joint
    assert plan.driver_kind == mech.driver.kind
    assert plan.newton is False
    pts = [abs(c) for b in (mech.frame, *mech.bodies) for p in b.points.values() for c in p]
    assert plan.length_scale == max(pts)


def _triad() -> Mechanism:
    """A class III group (ternary link on three binary links) driven by a crank, as in
    tests/test_planar_groups.py::m_triad."""
    A = np.array([0.1 * np.cos(0.3), 0.1 * np.sin(0.3)])
    P1, P2, P3 = np.array([0.25, 0.15]), np.array([0.35, 0.05]), np.array([0.3, 0.25])
    F2, F3 = np.array([0.45, -0.1]), np.array([0.5, 0.35])

    def link(name: str, s: str, e: str, S: np.ndarray, E: np.ndarray) -> Body:
        b = bar(name, s, e, float(np.hypot(*(E - S))), mass=0.5)
        th = float(np.arctan2(*(E - S)[::-1]))
        return Body(b.name, b.points, b.mass, b.com, b.inertia, guess=(S[0], S[1], th))

    frame = Body("frame", {"O": (0, 0), "F2": tuple(F2), "F3": tuple(F3)})
    tern = Body("tern", {"P1": (0, 0), "P2": tuple(P2 - P1), "P3": tuple(P3 - P1)}, mass=2.0,
                guess=(P1[0], P1[1], 0.0))
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "l1"),
              Revolute("P1", "l1", "tern"), Revolute("P2", "l2", "tern"),
              Revolute("P3", "l3", "tern"), Revolute("F2", "frame", "l2"),
              Revolute("F3", "frame", "l3"))
    return Mechanism(frame, (bar("crank", "O", "A", 0.1, mass=1.0), link("l1", "A", "P1", A, P1),
                             link("l2", "F2", "P2", F2, P2), link("l3", "F3", "P3", F3, P3),
                             tern), joints, Crank("O"))


def test_a_newton_group_is_marked_and_keeps_the_guesses():
    """The class-III group is solved by Newton: the plan says so and carries the bodies'
    guess poses in the group's body order."""
    mech = _triad()
    plan = compile_plan(mech)
    assert plan.newton
    newton = [g for g in plan.groups if g.kind == "newton"]
    assert len(newton) == 1
    assert newton[0].guesses == tuple(mech.body(mech.body_names[i]).guess
                                      for i in newton[0].bodies)
    assert None not in newton[0].guesses


class _NoLookups(dict):
    def __getitem__(self, key: Any) -> Any:
        raise AssertionError(f"name look-up of {key!r} during a solve")


def _forbid_name_lookups(mech: Mechanism) -> None:
    """Make every by-name look-up of the mechanism fail (the plan is compiled before)."""
    def fail(*args: Any, **kw: Any) -> Any:
        raise AssertionError(f"name look-up {args!r} during a solve")

    for attr in ("joint", "body", "joint_geometry"):
        object.__setattr__(mech, attr, fail)
    object.__setattr__(mech, "index", _NoLookups())


@pytest.mark.parametrize("make", [lambda: fourbar_mechanism(0.1, 0.3, 0.2, 0.3, omega1=3.0,
                                                            eps1=0.5),
                                  lambda: crank_slider_mechanism(0.05, 0.2, 0.01), _slot_mech,
                                  _triad],
                         ids=["fourbar", "crank_slider", "slot", "newton"])
def test_solvers_never_look_names_up(make):
    """Positions, rates, transmission angles and dead centres run on the compiled plan alone:
    with the mechanism's name look-ups made to fail, the results equal those of an untouched
    copy (bit for bit)."""
    ref_mech, mech = make(), make()
    phi = (np.linspace(0.3, 0.85, 12) if mech.structure.groups[-1].kind == "newton"
           else np.linspace(0.0, 2 * np.pi, 73))
    ref = kinematics(ref_mech, phi)
    _ = mech.structure, mech.plan, mech.body_names
    _forbid_name_lookups(mech)
    kin = kinematics(mech, phi)
    for name in ("x", "y", "theta", "vx", "vy", "omega", "ax", "ay", "eps"):
        np.testing.assert_array_equal(getattr(kin, name), getattr(ref, name))
    ta, ta_ref = transmission_angles(kin), transmission_angles(ref)
    assert ta.keys() == ta_ref.keys()
    for key in ta:
        np.testing.assert_array_equal(ta[key][0], ta_ref[key][0])
    assert dead_centres(kin) == dead_centres(ref)
