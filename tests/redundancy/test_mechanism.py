"""Spatial reactions fed by the planar engine: in-plane parts equal the engine's inverse
dynamics and the independent four-bar of tests/_fourbar_reference.py."""

from __future__ import annotations

import numpy as np
import pytest
from _fourbar_reference import INERTIA, M_EXT, MASS, OMEGA1
from _fourbar_reference import geometry as ref_geometry
from _fourbar_reference import spatial_model as ref_model
from _fourbar_reference import wrenches as ref_wrenches

from linkwork.errors import ParameterError
from linkwork.planar import (
    BodyTorque,
    PointForce,
    crank_slider,
    fourbar,
    inverse_dynamics,
    kinematics,
)
from linkwork.redundancy import (
    Deviation,
    OutOfPlaneLoad,
    count_redundancy,
    geometry,
    solve_reactions,
    spatial_model,
    spatial_reactions,
)

PHI = np.linspace(0.0, 2 * np.pi, 36, endpoint=False)


def _fourbar():
    return fourbar(0.1, 0.3, 0.2, 0.3, masses=tuple(MASS), inertias=tuple(INERTIA),
                   omega1=OMEGA1)


JOINTS = {"O2": {"e": 0.04, "z": 0.0}, "A": {"e": 0.02, "z": 0.03}, "B": {"e": 0.03, "z": 0.03},
          "O4": {"e": 0.05, "z": -0.01}}
DEVS = [Deviation("O2", "frame", dx=1e-5, dy=-2e-5, dz=3e-5, tx=2e-4, ty=-1e-4),
        Deviation("B", "rocker", dz=-4e-5, tx=-3e-4, ty=5e-4),
        Deviation("O4", "frame", dx=2e-5, dz=1e-5, tx=1e-4, ty=2e-4),
        Deviation("A", "crank", dy=1e-5, ty=-2e-4)]


def test_engine_fourbar_inplane_equals_engine_inverse_dynamics():
    mech = _fourbar()
    loads = [BodyTorque("rocker", M_EXT), PointForce("coupler", "B", fx=3.0, fy=-7.0)]
    r = spatial_reactions(mech, PHI, gravity=(0, -9.81), loads=loads, joints=JOINTS,
                          heights={"crank": 0.01, "coupler": 0.03},
                          out_of_plane=[OutOfPlaneLoad("coupler", fz=5.0, mx=1.0)],
                          deviations=DEVS)
    dyn = inverse_dynamics(kinematics(mech, PHI), gravity=(0, -9.81), loads=loads)
    scale = np.max(np.abs(dyn.fx))
    assert np.max(np.abs(r.fx - dyn.fx)) < 1e-9 * scale
    assert np.max(np.abs(r.fy - dyn.fy)) < 1e-9 * scale
    assert np.max(np.abs(r.Q - dyn.Q)) < 1e-9 * np.max(np.abs(dyn.Q))
    rd = spatial_reactions(mech, PHI, gravity=(0, -9.81), loads=loads, joints=JOINTS,
                           heights={"crank": 0.01, "coupler": 0.03},
                           out_of_plane=[OutOfPlaneLoad("coupler", fz=5.0, mx=1.0)],
                           deviations=DEVS, method="displacement")
    assert np.max(np.abs(rd.components() - r.components())) < 1e-9 * np.max(
        np.abs(r.components()))


def test_engine_fourbar_equals_independent_reference_with_deviations():
    """Same four-bar, same joints and deviations: the engine-fed result equals the one fed by
    the independent kinematics of tests/_fourbar_reference.py (body frames coincide: link x-axes
    O2->A, A->B, O4->B)."""
    mech = _fourbar()
    z = tuple(JOINTS[k]["z"] for k in ("O2", "A", "B", "O4"))
    e = tuple(JOINTS[k]["e"] for k in ("O2", "A", "B", "O4"))
    r = spatial_reactions(mech, PHI, gravity=(0, -9.81), loads=[BodyTorque("rocker", M_EXT)],
                          joints=JOINTS, deviations=DEVS)
    dev = np.zeros((4, 2, 6))
    dev[0, 0] = (1e-5, -2e-5, 3e-5, 2e-4, -1e-4, 0)
    dev[2, 1] = (0, 0, -4e-5, -3e-4, 5e-4, 0)
    dev[3, 0] = (2e-5, 0, 1e-5, 1e-4, 2e-4, 0)
    dev[1, 0] = (0, 1e-5, 0, 0, -2e-4, 0)
    ref = solve_reactions(ref_model(e=e, z=z), ref_geometry(PHI), ref_wrenches(PHI), dev)
    assert np.max(np.abs(r.components() - ref.components())) < 1e-8 * np.max(
        np.abs(ref.components()))


def test_engine_crank_slider_prismatic():
    mech = crank_slider(0.05, 0.2, 0.01, masses=(1.0, 1.5, 2.0), omega1=20.0)
    loads = [PointForce("slider", "B", fx=-50.0)]
    kin = kinematics(mech, PHI)
    model = spatial_model(mech, {"G": {"e": 0.06, "z": 0.0}}, default={"e": 0.02, "z": 0.01})
    c = count_redundancy(model, geometry(mech, kin), position=3)
    assert (c.mobility_formula, c.mobility, c.redundant) == (-2, 1, 3)
    devs = [Deviation("G", "frame", dz=1e-5, tx=1e-4, tz=2e-4), Deviation("A", "rod", ty=3e-4)]
    r = spatial_reactions(mech, PHI, gravity=(0, -9.81), loads=loads,
                          joints={"G": {"e": 0.06, "z": 0.0}}, default={"e": 0.02, "z": 0.01},
                          heights={"slider": 0.02}, deviations=devs)
    rd = spatial_reactions(mech, PHI, gravity=(0, -9.81), loads=loads,
                           joints={"G": {"e": 0.06, "z": 0.0}}, default={"e": 0.02, "z": 0.01},
                           heights={"slider": 0.02}, deviations=devs, method="displacement")
    dyn = inverse_dynamics(kin, gravity=(0, -9.81), loads=loads)
    scale = np.max(np.abs(dyn.fx))
    assert np.max(np.abs(r.fx - dyn.fx)) < 1e-9 * scale
    assert np.max(np.abs(r.fy - dyn.fy)) < 1e-9 * scale
    assert np.max(np.abs(r.mz[3] - dyn.mz[3])) < 1e-9 * scale * 0.2
    assert np.max(np.abs(r.Q - dyn.Q)) < 1e-9 * np.max(np.abs(dyn.Q))
    assert np.max(np.abs(rd.components() - r.components())) < 1e-9 * np.max(
        np.abs(r.components()))
    assert np.max(np.abs(r.fz)) > 0.1


def test_engine_adapter_bad_names():
    mech = _fourbar()
    with pytest.raises(ParameterError, match="no such joint"):
        spatial_model(mech, {"Z": {"e": 0.01}})
    with pytest.raises(ParameterError, match="family"):
        spatial_model(mech, {"A": {"kind": "prismatic"}})
    with pytest.raises(ParameterError, match="joint's bodies"):
        spatial_reactions(mech, PHI[:3], deviations=[Deviation("A", "rocker", dz=1e-5)])


def test_engine_linear_driver_force_along_the_slide():
    """A crank-slider driven at the slider (Linear driver): Q is the force along the guide,
    in-plane parts equal the engine's, both formulations agree, q = 3."""
    from linkwork.planar import Body, Linear, Mechanism, Prismatic, Revolute, bar

    frame = Body("frame", {"O": (0.0, 0.0), "G": (0.0, 0.0)})
    crank = bar("crank", "O", "A", 0.05, mass=1.0)
    rod = bar("rod", "A", "B", 0.2, mass=1.5)
    slider = Body("slider", {"B": (0.0, 0.0)}, mass=2.0)
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "rod"),
              Revolute("B", "rod", "slider"),
              Prismatic("G", "frame", "slider", angle=0.0, through="G", point="B"))
    mech = Mechanism(frame, (crank, rod, slider), joints, Linear("G", v1=-0.3, a1=0.5),
                     {"A": 1})
    s1 = np.linspace(0.17, 0.23, 9)
    loads = [BodyTorque("crank", -3.0)]
    kw = dict(gravity=(0, -9.81), loads=loads, default={"e": 0.03, "z": 0.01},
              joints={"G": {"e": 0.08, "z": 0.0}}, heights={"rod": 0.02},
              deviations=[Deviation("G", "frame", tx=2e-4, dz=1e-5),
                          Deviation("O", "frame", ty=1e-4)])
    r = spatial_reactions(mech, s1, **kw)
    rd = spatial_reactions(mech, s1, method="displacement", **kw)
    dyn = inverse_dynamics(kinematics(mech, s1), gravity=(0, -9.81), loads=loads)
    scale = np.max(np.abs(dyn.fx)) + np.max(np.abs(dyn.fy))
    assert np.max(np.abs(r.fy[:3] - dyn.fy[:3])) < 1e-9 * scale
    assert np.max(np.abs(r.fx[:3] - dyn.fx[:3])) < 1e-9 * scale
    assert np.max(np.abs(r.Q - dyn.Q)) < 1e-9 * np.max(np.abs(dyn.Q))
    # the slider joint: normal force as the engine's, plus the driving force along x
    assert np.max(np.abs(r.fy[3] - dyn.fy[3])) < 1e-9 * scale
    assert np.max(np.abs(r.fx[3] - (dyn.fx[3] + dyn.Q))) < 1e-9 * scale
    assert np.max(np.abs(rd.components() - r.components())) < 1e-9 * np.max(
        np.abs(r.components()))
    assert r.redundant == 3 and np.max(np.abs(r.fz)) > 0.01


def test_engine_watt_six_bar_q6_and_planar_parts():
    """A Watt six-bar of the engine (four-bar + dyad on the ternary rocker): q = 6, in-plane
    reactions and Q as the engine's, both formulations agree."""
    from linkwork.planar import Body, Crank, Mechanism, Revolute, bar

    frame = Body("frame", {"O": (0.0, 0.0), "C": (0.3, 0.0), "F": (0.55, -0.05)})
    rocker = Body("rocker", {"C": (0.0, 0.0), "B": (0.2, 0.0), "D": (0.12, -0.09)}, mass=2.0,
                  com=(0.1, -0.03), inertia=0.01)
    bodies = (bar("crank", "O", "A", 0.1, mass=1.0), bar("coupler", "A", "B", 0.3, mass=3.0),
              rocker, bar("link4", "D", "E", 0.25, mass=1.2),
              bar("link5", "F", "E", 0.2, mass=1.0))
    pairs = [("O", "frame", "crank"), ("A", "crank", "coupler"), ("B", "coupler", "rocker"),
             ("C", "frame", "rocker"), ("D", "rocker", "link4"), ("E", "link4", "link5"),
             ("F", "frame", "link5")]
    mech = Mechanism(frame, bodies, tuple(Revolute(*p) for p in pairs), Crank("O", 10.0),
                     {"B": 1, "E": 1})
    kw = dict(gravity=(0, -9.81), loads=[BodyTorque("link5", 2.0)],
              joints={n: {"z": 0.01 * i, "e": 0.02 + 0.005 * i} for i, (n, _, _) in
                      enumerate(pairs)},
              heights={"link4": 0.03},
              deviations=[Deviation("F", "frame", tx=2e-4), Deviation("D", "rocker", dz=1e-5)])
    r = spatial_reactions(mech, PHI, **kw)
    rd = spatial_reactions(mech, PHI, method="displacement", **kw)
    dyn = inverse_dynamics(kinematics(mech, PHI), gravity=(0, -9.81),
                           loads=[BodyTorque("link5", 2.0)])
    scale = np.max(np.abs(dyn.fx))
    assert r.redundant == 6
    assert np.max(np.abs(r.fx - dyn.fx)) < 1e-9 * scale
    assert np.max(np.abs(r.fy - dyn.fy)) < 1e-9 * scale
    assert np.max(np.abs(r.Q - dyn.Q)) < 1e-9 * np.max(np.abs(dyn.Q))
    assert np.max(np.abs(rd.components() - r.components())) < 1e-9 * np.max(
        np.abs(r.components()))
    c = count_redundancy(spatial_model(mech), geometry(mech, kinematics(mech, PHI)), 5)
    assert (c.mobility_formula, c.mobility, c.redundant) == (-5, 1, 6)
