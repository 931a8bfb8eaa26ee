"""Spatial reactions fed by the planar engine: in-plane parts equal the engine's inverse
dynamics and the independent four-bar of tests/_fourbar_reference.py."""

from __future__ import annotations

import numpy as np
import pytest
from _fourbar_reference import INERTIA, M_EXT, MASS, OMEGA1
from _fourbar_reference import geometry as ref_geometry
from _fourbar_reference import spatial_model as ref_model
from _fourbar_reference import wrenches as ref_wrenches
from _mechanisms import stephenson_sixbar
from _spatial_cases import DEVS as LOOM_DEVS
from _spatial_cases import HEIGHTS as LOOM_HEIGHTS
from _spatial_cases import JOINTS as LOOM_JOINTS
from _spatial_cases import PHI as LOOM_PHI
from _spatial_cases import TOLS, _problem, loads_ext, loom, spatial
from _spatial_cases import G as LOOM_G

from linkwork import redundancy as rd
from linkwork.errors import LinkworkError, ParameterError, StructureError
from linkwork.planar import (
    BodyTorque,
    PointForce,
    crank_slider_mechanism,
    fourbar_mechanism,
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
    return fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=tuple(MASS), inertias=tuple(INERTIA),
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
    mech = crank_slider_mechanism(0.05, 0.2, 0.01, masses=(1.0, 1.5, 2.0), omega1=20.0)
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


@pytest.mark.parametrize("case", ["slider", "stephenson"])
def test_spatial_inplane_reactions_equal_planar_with_deviations(case):
    """Deviations (tilts, axial offsets), out-of-plane loads, centres of mass and joints at
    different heights, a prismatic joint in space: the in-plane reaction components and Q
    equal the planar engine's inverse dynamics; both formulations agree; each body's z force
    balance holds with the out-of-plane load; the deviations do produce out-of-plane parts."""
    from linkwork.planar import PointForce, inverse_dynamics, kinematics
    from linkwork.planar.model import crank_slider_mechanism
    from linkwork.redundancy import Deviation, OutOfPlaneLoad, spatial_reactions

    if case == "slider":
        mech = crank_slider_mechanism(0.05, 0.2, 0.03, guide_angle=np.radians(35.0),
                            masses=(2.0, 3.0, 4.0), coms=((0.02, 0.01), 0.08), omega1=30.0)
        joints = {"G": {"kind": "prismatic", "e": 0.06, "z": 0.005},
                  "A": {"e": 0.02, "z": 0.01}}
        devs = [Deviation("B", "rod", tx=3e-4), Deviation("G", "frame", dz=1e-5, tz=2e-4)]
        loads = [PointForce("slider", "B", fx=-500.0)]
        op = [OutOfPlaneLoad("slider", fz=20.0, mx=0.5)]
    else:
        mech, _, lfun = stephenson_sixbar()
        joints = {"D": {"e": 0.04, "z": -0.01}, "O6": {"e": 0.05, "z": 0.02}}
        devs = [Deviation("O6", "frame", tx=2e-4, ty=-1e-4),
                Deviation("C", "link5", dz=2e-5)]
        loads = lfun(np.radians(np.arange(0.0, 360.0, 10.0)))
        op = [OutOfPlaneLoad("link5", fz=-7.0, my=0.3)]
    phi = np.radians(np.arange(0.0, 360.0, 10.0))
    w, e = 8.0 + np.sin(phi), 2.0
    g = (3.0, -9.0)
    kw = dict(omega1=w, eps1=e, gravity=g, loads=loads, joints=joints,
              default={"e": 0.03, "k_bearing": 5e7}, heights={mech.bodies[1].name: 0.015},
              out_of_plane=op, deviations=devs)
    res = spatial_reactions(mech, phi, **kw)
    dis = spatial_reactions(mech, phi, method="displacement", **kw)
    dyn = inverse_dynamics(kinematics(mech, phi, w, e), gravity=g, loads=loads)
    scale = np.abs(dyn.fx).max()
    for k, name in enumerate(dyn.joints):
        j = res.joints.index(name)
        assert np.max(np.abs(res.fx[j] - dyn.fx[k])) <= 1e-9 * scale
        assert np.max(np.abs(res.fy[j] - dyn.fy[k])) <= 1e-9 * scale
    assert np.max(np.abs(res.Q - dyn.Q)) <= 1e-9 * np.abs(dyn.Q).max()
    for c in ("fx", "fy", "fz", "mx", "my", "mz"):
        a, b = getattr(res, c), getattr(dis, c)
        assert np.max(np.abs(a - b)) <= 1e-9 * max(np.abs(a).max(), 1e-300) + 1e-9
    # z equilibrium of every moving body: sum of joint fz on it + its out-of-plane load = 0
    fz_ext = {o.body: o.fz for o in op}
    for b in mech.bodies:
        total = np.zeros(phi.size) + fz_ext.get(b.name, 0.0)
        for j in mech.joints:
            i = res.joints.index(j.name)
            total += res.fz[i] * ((j.b == b.name) - (j.a == b.name))
        assert np.max(np.abs(total)) <= 1e-9 * (1.0 + np.abs(res.fz).max())
    assert np.abs(res.bending()).max() > 1e-3  # the deviations and heights do matter


def test_inplane_reactions_and_torque_equal_the_planar_engine_whatever_e_k_deviations():
    mech = loom()
    dyn = inverse_dynamics(kinematics(mech, LOOM_PHI), gravity=LOOM_G, loads=loads_ext(LOOM_PHI))
    rng = np.random.default_rng(6)
    for trial in range(4):
        joints = {j: dict(e=rng.uniform(0.005, 0.08), z=rng.uniform(-0.05, 0.05),
                          k_bearing=10 ** rng.uniform(6, 9)) for j in "OABC"}
        devs = [rd.Deviation(j, b, *(rng.normal(0, 1e-4, 6) * [1, 1, 1, 1, 1, 1]))
                for j, b in (("O", "frame"), ("A", "crank"), ("B", "coupler"), ("C", "rocker"))]
        oop = [rd.OutOfPlaneLoad("coupler", fz=rng.normal(0, 5), mx=rng.normal(), my=1.0)] \
            if trial % 2 else []
        r = spatial(mech, joints, devs, oop=oop)
        for i, name in enumerate(r.joints):
            fx, fy = dyn.reaction(name)
            scale = np.max(np.abs(dyn.fx)) + np.max(np.abs(dyn.fy))
            assert np.max(np.abs(r.fx[i] - fx)) <= 1e-9 * scale
            assert np.max(np.abs(r.fy[i] - fy)) <= 1e-9 * scale
        assert np.max(np.abs(r.Q - dyn.Q)) <= 1e-9 * np.max(np.abs(dyn.Q))


def test_out_of_plane_components_appear_with_deviations_and_out_of_plane_loads():
    flat = {j: dict(e=0.03, z=0.0) for j in "OABC"}
    mech = loom()
    phi = LOOM_PHI
    kw = dict(gravity=LOOM_G, loads=loads_ext(phi), joints=flat)
    r0 = rd.spatial_reactions(mech, phi, **kw)
    oop = np.abs(np.stack([r0.fz, r0.mx, r0.my])).max()
    inplane = np.abs(np.stack([r0.fx, r0.fy])).max()
    assert oop <= 1e-9 * inplane
    r1 = rd.spatial_reactions(mech, phi, deviations=[rd.Deviation("C", "frame", tx=1e-4)], **kw)
    assert np.abs(np.stack([r1.mx, r1.my])).max() > 1e-3
    r2 = rd.spatial_reactions(mech, phi, out_of_plane=[rd.OutOfPlaneLoad("coupler", fz=5.0)],
                              **kw)
    # the frame carries the whole out-of-plane force: fz_O + fz_C = -5 N (frame on links)
    iO, iC = r2.joints.index("O"), r2.joints.index("C")
    assert np.allclose(r2.fz[iO] + r2.fz[iC], -5.0, atol=1e-9)


def _independent_reactions(mech, phi, joints, heights, devs, driver_k=1e9):
    """Spatial stiffness model of the four-bar from scratch.

    Unknowns: per moving body, the small displacement t of its point at the origin and its
    small rotation th (6). Joint j at p = (x_j, y_j, z_j) between a and b: relative motion
    (t_b + th_b x p - t_a - th_a x p, th_b - th_a) plus the misfit delta = R(theta_b) d_b -
    R(theta_a) d_a; springs on (dx, dy, dz, rx, ry): radial k_b, axial k_b, tilt k_b e^2/12;
    the driver is a torsion spring about z at O. Minimum of the potential energy; the reaction
    on b is -K s. Loads: m (g - a_S) at (x_S, y_S, h), -I eps about z, 4 N m on the rocker.
    """
    kin = kinematics(mech, phi)
    bodies = [b.name for b in mech.bodies]
    nb = len(bodies)
    out = np.zeros((len(mech.joints), 6, len(phi)))
    Q = np.zeros(len(phi))

    from _spatial_reference import _rot6 as rot
    from _spatial_reference import _skew as cross_mat

    for n in range(len(phi)):
        Kg = np.zeros((6 * nb, 6 * nb))
        f = np.zeros(6 * nb)
        Bs = []
        for bi, b in enumerate(mech.bodies):
            c = kin.point(b.name, "com")
            p = np.array([c.x[n], c.y[n], heights.get(b.name, 0.0)])
            F = np.array([b.mass * (LOOM_G[0] - c.ax[n]), b.mass * (LOOM_G[1] - c.ay[n]), 0.0])
            M = np.array([0.0, 0.0, -b.inertia * kin.eps[kin.bodies.index(b.name)][n]])
            if b.name == "rocker":
                M[2] += 4.0
            f[6 * bi:6 * bi + 3] += F
            f[6 * bi + 3:6 * bi + 6] += M + np.cross(p, F)
        for j in mech.joints:
            spec = joints[j.name]
            owner = j.b
            pt = j.name if j.name in mech.body(owner).points else None
            pm = kin.point(owner, pt)
            p = np.array([pm.x[n], pm.y[n], spec["z"]])
            B = np.zeros((6, 6 * nb))
            delta = np.zeros(6)
            for body, sign in ((j.a, -1.0), (j.b, 1.0)):
                dv = np.zeros(6)
                for d in devs:
                    if d.joint == j.name and d.body == body:
                        dv += [d.dx, d.dy, d.dz, d.tx, d.ty, d.tz]
                if body == mech.frame.name:
                    delta += sign * dv
                    continue
                bi = bodies.index(body)
                delta += sign * rot(kin.angle(body)[n]) @ dv
                B[:3, 6 * bi:6 * bi + 3] += sign * np.eye(3)
                B[:3, 6 * bi + 3:6 * bi + 6] += -sign * cross_mat(p)
                B[3:, 6 * bi + 3:6 * bi + 6] += sign * np.eye(3)
            kb, e = spec.get("k_bearing", 1e8), spec["e"]
            kt = kb * e * e / 12
            k = np.array([kb, kb, kb, kt, kt, driver_k if j.name == mech.driver.joint else 0.0])
            Kg += B.T @ (k[:, None] * B)
            f -= B.T @ (k * delta)
            Bs.append((B, k, delta))
        u = np.linalg.solve(Kg, f)
        for ji, (B, k, delta) in enumerate(Bs):
            s = B @ u + delta
            out[ji, :, n] = -k * s
            if mech.joints[ji].name == mech.driver.joint:
                Q[n] = out[ji, 5, n]
    return out, Q


def test_against_an_independent_spatial_stiffness_model():
    mech = loom()
    joints = {j: dict(LOOM_JOINTS[j], k_bearing=kb) for j, kb in zip("OABC", (1e8, 2e8, 5e7, 1e8),
                                                                   strict=True)}
    phi = LOOM_PHI[::2]
    ref, Qref = _independent_reactions(mech, phi, joints, LOOM_HEIGHTS, LOOM_DEVS)
    r = spatial(mech, joints, LOOM_DEVS, phi=phi)
    got = r.components()
    for k in range(6):
        scale = np.max(np.abs(ref[:, k])) if k < 5 else np.max(np.abs(Qref))
        assert np.max(np.abs(got[:, k] - ref[:, k])) <= 1e-7 * scale, k
    assert np.max(np.abs(r.Q - Qref)) <= 1e-7 * np.max(np.abs(Qref))


@pytest.mark.parametrize("call, name", [
    (lambda: rd.SpatialJoint("A", "crank", "coupler", e=0.0), "A.e"),
    (lambda: rd.SpatialJoint("A", "crank", "coupler", e=-0.01), "A.e"),
    (lambda: rd.SpatialJoint("A", "crank", "coupler", stiffness=(1e8, 1e8, 0, 1e3, 1e3, 0)),
     "A.stiffness"),
    (lambda: rd.SpatialJoint("A", "crank", "coupler", stiffness=(1e8,) * 5), "A.stiffness"),
    (lambda: rd.SpatialJoint("A", "crank", "coupler", kind="ball"), "kind"),
    (lambda: rd.SpatialJoint("A", "crank", "coupler", k_bearing=-1.0), "A.k_bearing"),
    (lambda: rd.SpatialJoint("A", "crank", "coupler", axial_ratio=0.0), "A.axial_ratio"),
    (lambda: rd.SpatialJoint("A", "crank", "coupler", z=np.nan), "A.z"),
    (lambda: rd.bearing_stiffness("revolute", 0.03, axial_ratio=0.0), "axial_ratio"),
    (lambda: rd.Tolerance("C", "a", "tx", -1e-4), "limit"),
    (lambda: rd.Tolerance("C", "c", "tx", 1e-4), "side"),
    (lambda: rd.Tolerance("C", "a", "zz", 1e-4), "component"),
    (lambda: rd.Tolerance("C", "a", "tx", 1e-4, "cauchy"), "distribution"),
    (lambda: rd.tolerance_study(*_problem(12), TOLS, 0), "n_samples"),
    (lambda: rd.tolerance_study(*_problem(12), TOLS, -3), "n_samples"),
    (lambda: rd.tolerance_study(*_problem(12), TOLS, 2.5), "n_samples"),
    (lambda: rd.tolerance_study(*_problem(12), TOLS, 10, seed=-1), "seed"),
    (lambda: rd.tolerance_study(*_problem(12), [], 10), "tolerances"),
    (lambda: rd.tolerance_study(*_problem(12), [rd.Tolerance("X", "a", "tx", 1e-4)], 10),
     "tolerance.joint"),
    (lambda: rd.tolerance_study(*_problem(12), TOLS, 10, chunk_size=0), "chunk"),
    (lambda: rd.spatial_reactions(loom(), LOOM_PHI, joints={"Z": {"e": 0.03}}), "joints"),
    (lambda: rd.spatial_reactions(loom(), LOOM_PHI, deviations=[rd.Deviation("Z", "frame")]),
     "deviation.joint"),
    (lambda: rd.spatial_reactions(loom(), LOOM_PHI, deviations=[rd.Deviation("A", "frame")]),
     "deviation A.body"),
    (lambda: rd.spatial_reactions(loom(), LOOM_PHI, heights={"nope": 0.1}), "heights"),
    (lambda: rd.spatial_reactions(loom(), LOOM_PHI, method="fem"), "method"),
    (lambda: rd.count_redundancy(*_problem(12)[:2], position=12), "position"),
])
def test_bad_inputs_are_named(call, name):
    with pytest.raises(LinkworkError) as exc:
        call()
    assert name in str(exc.value)


def test_a_mechanism_movable_in_space_cannot_carry_loads():
    mech = loom()
    with pytest.raises(StructureError, match="movable in space"):
        rd.spatial_reactions(mech, LOOM_PHI, gravity=LOOM_G, joints={"A": {"kind": "spherical"},
                                                           "B": {"kind": "spherical"}})


# -- several drivers -----------------------------------------------------------------------------

ROOT_DIR = __import__("pathlib").Path(__file__).resolve().parents[2]


def _several_driver_case(which):
    """(mechanism, path, gravity, point forces, joint spec, heights, deviations) of the
    excavator (three cylinders: linear drivers) or the two-crank five-bar, with joints at
    different heights and axis lengths, bodies lifted and deviations on both sides of joints."""
    from linkwork import io

    if which == "excavator":
        doc = io.load(ROOT_DIR / "examples" / "excavator_boom.toml")
        forces = [("bucket", "K", -12e3, 4e3)]
        heights = {"boom": 0.05, "arm_cyl_rod": -0.04, "bucket": 0.02}
        devs = [("O", "frame", (1e-5, 0, 2e-5, 2e-4, -1e-4, 0)),
                ("E", "bucket", (0, 0, -1e-5, -1e-4, 3e-4, 0)),
                ("arm_cyl", "arm_cyl_barrel", (0, 1e-5, 0, 1e-4, 0, 2e-4)),
                ("A1", "boom_cyl_barrel", (0, 0, 3e-5, 0, 2e-4, 0))]
    else:
        doc = io.load(ROOT_DIR / "tests" / "data" / "drivers" / "five_bar_two_cranks.toml")
        forces = [("l1", "P", 30.0, -20.0)]
        heights = {"l1": 0.01, "c2": -0.005}
        devs = [("O2", "frame", (0, 0, 1e-5, 2e-4, 1e-4, 0)),
                ("P", "l2", (1e-5, 0, 0, -2e-4, 0, 0)),
                ("A", "c1", (0, 0, 2e-5, 0, 1e-4, 0))]
    mech = doc.mechanism()
    spec = {}
    for i, j in enumerate(mech.joints):
        kind = "prismatic" if j.spatial_family == "P" else "revolute"
        spec[j.name] = (kind, 0.02 + 0.004 * (i % 5), 0.01 * ((i % 3) - 1), 1e8 * (1 + i % 2))
    return mech, doc.positions(), tuple(doc.analysis.gravity), forces, spec, heights, devs


@pytest.mark.parametrize("which", ["excavator", "five_bar"])
def test_several_drivers_against_an_independent_spatial_solve(which):
    """Three linear drivers (the excavator's cylinders) and two cranks (a five-bar): the spatial
    reactions and every driver's load equal the independent solve of tests/_spatial_reference.py
    (drivers held rigid by Lagrange multipliers, springs assembled per position from the joint
    definitions) to 1e-8 of the largest component; the in-plane parts and each driver's Q equal
    the planar engine's inverse dynamics to 1e-9; the whole machine (the frame's joints against
    all body loads) is in equilibrium in all six components to 1e-9."""
    from _spatial_reference import reactions as reference

    from linkwork.planar import PointForce

    mech, path, g, forces, spec, heights, devs = _several_driver_case(which)
    phi = path[:, ::8]
    kin = kinematics(mech, phi)
    joints = {name: {"kind": k, "e": e, "z": z, "k_bearing": kb}
              for name, (k, e, z, kb) in spec.items()}
    loads = [PointForce(b, p, fx=fx, fy=fy) for b, p, fx, fy in forces]
    deviations = [Deviation(jn, bn, *v) for jn, bn, v in devs]
    r = spatial_reactions(mech, phi, gravity=g, loads=loads, joints=joints, heights=heights,
                          deviations=deviations)
    assert r.Q.shape == (mech.n_drivers, phi.shape[1]) and r.redundant > 0
    frames, centres = {}, {}
    for j in mech.joints:
        _, pb, ang = mech.joint_geometry(j)
        pm = kin.point(j.b, pb)
        centres[j.name] = (pm.x, pm.y)
        frames[j.name] = (kin.angle(j.a) + ang if j.spatial_family == "P"
                          else np.zeros(phi.shape[1]))
    ref, q_ref = reference(mech, kin, spec=spec, frames=frames, centres=centres,
                           heights=heights, devs=devs, gravity=g, forces=forces)
    got = r.components()
    assert np.abs(ref[:, 2:5]).max() > 1e-3 * np.abs(ref).max()  # out-of-plane parts matter
    assert np.max(np.abs(got - ref)) <= 1e-8 * np.abs(ref).max()
    assert np.max(np.abs(r.Q - q_ref)) <= 1e-8 * np.abs(q_ref).max()
    # in-plane: the planar engine, driver by driver
    dyn = inverse_dynamics(kin, gravity=g, loads=loads)
    scale = max(np.abs(dyn.fx).max(), np.abs(dyn.fy).max())
    for k, name in enumerate(dyn.joints):
        i = r.joints.index(name)
        extra = 0.0
        if name in r.drivers and mech.joint(name).spatial_family == "P":
            extra = dyn.Q[r.drivers.index(name)]  # the driving force along the slide
            c, s = np.cos(frames[name]), np.sin(frames[name])
            assert np.max(np.abs(r.fx[i] - (dyn.fx[k] + extra * c))) <= 1e-9 * scale
            assert np.max(np.abs(r.fy[i] - (dyn.fy[k] + extra * s))) <= 1e-9 * scale
            continue
        assert np.max(np.abs(r.fx[i] - dyn.fx[k])) <= 1e-9 * scale
        assert np.max(np.abs(r.fy[i] - dyn.fy[k])) <= 1e-9 * scale
    assert np.max(np.abs(r.Q - dyn.Q)) <= 1e-9 * np.abs(dyn.Q).max()
    # the whole machine: what the frame's joints exert on the moving bodies balances all loads
    w = rd.body_wrenches(mech, kin, gravity=g, loads=loads, heights=heights)
    total = w.sum(axis=1).T  # (6, n) about the origin
    for j in mech.joints:
        if mech.frame.name not in (j.a, j.b):
            continue
        i = r.joints.index(j.name)
        sign = 1.0 if j.a == mech.frame.name else -1.0  # as a wrench on the moving body
        x, y = centres[j.name]
        p = np.stack([x, y, np.full_like(x, spec[j.name][2])])
        f = sign * np.stack([r.fx[i], r.fy[i], r.fz[i]])
        m = sign * np.stack([r.mx[i], r.my[i], r.mz[i]])
        total += np.concatenate([f, m + np.cross(p, f, axis=0)])
    assert np.max(np.abs(total[:3])) <= 1e-9 * scale
    lever = np.abs(path).max() if which == "five_bar" else 5.0
    assert np.max(np.abs(total[3:])) <= 1e-9 * scale * max(lever, 1.0)


# -- gear pairs ----------------------------------------------------------------------------------


def _frictionless(mech):
    import dataclasses

    from linkwork.planar import GearPair

    return dataclasses.replace(mech, joints=tuple(
        dataclasses.replace(j, efficiency=1.0) if isinstance(j, GearPair) else j
        for j in mech.joints))


def _geared(which):
    """(mechanism without mesh losses, positions, loads): the geared five-bar example over
    one period of the pair (5 turns of the 30-tooth gear) and a planetary train (a planet
    in a fixed ring on a driven arm) with a couple on the planet that reverses."""
    from linkwork import io
    from linkwork.planar import Body, Crank, GearPair, Mechanism, Revolute, bar

    if which == "five_bar":
        doc = io.load(ROOT_DIR / "examples" / "geared_five_bar.toml")
        phi = doc.positions()[::10]
        return _frictionless(doc.mechanism()), phi, doc.loads(phi), tuple(doc.analysis.gravity)
    frame = Body("frame", {"O": (0.0, 0.0)})
    arm = bar("arm", "O", "Q", 0.06, mass=0.8)
    planet = Body("planet", {"Q": (0.0, 0.0), "T": (0.03, 0.0)}, mass=0.4, com=(0.004, 0.0),
                  inertia=2e-4)
    mech = Mechanism(frame, (arm, planet), (
        Revolute("O", "frame", "arm"), Revolute("Q", "arm", "planet"),
        GearPair("M", "planet", "frame", radii=(0.03, 0.09), internal=True, carrier="arm")),
        Crank("O", omega1=6.0))
    phi = np.linspace(0.0, 2 * np.pi, 49)
    return mech, phi, [BodyTorque("planet", 0.4 * np.sin(phi))], (0.0, -9.81)


@pytest.mark.parametrize("which", ["five_bar", "planetary"])
def test_gear_mesh_inplane_parts_are_the_planar_tooth_force(which):
    """A gear pair in space: its reaction acts at the pitch point along the line of action of
    the flank in contact (the tooth force and its separating part), so the in-plane reactions
    of every joint (the pivots carry the separating force) and Q equal the planar engine's
    without mesh losses to 1e-9, through positions where the tooth force reverses (both flanks
    are used); the mesh's force along its line is never a pull."""
    mech, phi, loads, g = _geared(which)
    kin = kinematics(mech, phi)
    dyn = inverse_dynamics(kin, gravity=g, loads=loads)
    r = spatial_reactions(mech, phi, gravity=g, loads=loads)
    scale = max(np.abs(dyn.fx).max(), np.abs(dyn.fy).max())
    for k, name in enumerate(dyn.joints):
        i = r.joints.index(name)
        assert np.max(np.abs(r.fx[i] - dyn.fx[k])) <= 1e-9 * scale, name
        assert np.max(np.abs(r.fy[i] - dyn.fy[k])) <= 1e-9 * scale, name
    assert np.max(np.abs(r.Q - dyn.Q)) <= 1e-9 * np.abs(dyn.Q).max()
    gear = next(j for j in mech.joints if j.spatial_family == "G")
    kg = list(dyn.joints).index(gear.name)
    geom = rd.geometry(mech, kin, rd.body_wrenches(mech, kin, gravity=g, loads=loads))
    jg = r.joints.index(gear.name)
    np.testing.assert_allclose(geom.points[:, jg, 0], dyn.px[kg], atol=1e-12)
    np.testing.assert_allclose(geom.points[:, jg, 1], dyn.py[kg], atol=1e-12)
    line = geom.slide_angles[:, jg]
    fn = r.fx[jg] * np.cos(line) + r.fy[jg] * np.sin(line)
    assert np.all(fn >= -1e-9 * scale)
    ft_sign = np.sign(np.cos(line - np.arctan2(r.fy[jg], r.fx[jg])))
    assert np.all(ft_sign[np.abs(fn) > 1e-6 * scale] > 0)
    # both flanks: the line of action jumps by pi + 2 alpha somewhere in the cycle
    jumps = np.abs(np.angle(np.exp(1j * np.diff(line))))
    assert jumps.max() > np.pi / 2


def test_gear_mesh_against_an_independent_spatial_solve():
    """The geared five-bar in space under gravity: spur mesh (line contact: the tooth force and
    the moment about z x n), pivots and pins at different heights, tilted and offset elements on
    the frame, a gear and a coupler: reactions and Q equal the independent solve of
    tests/_spatial_reference.py to 1e-8, its mesh frame taken from the planar engine's tooth
    force (direction and pitch point)."""
    from _spatial_reference import reactions as reference

    mech, phi, _, g = _geared("five_bar")
    phi = phi[::6]
    kin = kinematics(mech, phi)
    spec = {"O1": ("revolute", 0.04, 0.0, 2e8), "O2": ("revolute", 0.05, 0.01, 1e8),
            "A": ("revolute", 0.02, 0.02, 1e8), "B": ("revolute", 0.025, -0.01, 1e8),
            "P": ("revolute", 0.02, 0.015, 5e7), "G": ("spur", 0.03, 0.005, 6e8)}
    devs = [("O2", "frame", (0, 0, 2e-5, 3e-4, -1e-4, 0)),
            ("G", "gear2", (0, 0, 0, 2e-4, 1e-4, 0)),
            ("P", "coupler1", (1e-5, 0, 1e-5, 0, -2e-4, 0))]
    heights = {"gear1": 0.0, "gear2": 0.01, "coupler1": 0.02}
    joints = {n: {"kind": k, "e": e, "z": z, "k_bearing": kb} for n, (k, e, z, kb) in
              spec.items()}
    r = spatial_reactions(mech, phi, gravity=g, joints=joints, heights=heights,
                          deviations=[Deviation(a, b, *v) for a, b, v in devs])
    dyn = inverse_dynamics(kin, gravity=g)
    frames, centres = {}, {}
    for j in mech.joints:
        if j.spatial_family == "G":
            kg = list(dyn.joints).index(j.name)
            frames[j.name] = np.arctan2(dyn.fy[kg], dyn.fx[kg])
            centres[j.name] = (dyn.px[kg], dyn.py[kg])
            continue
        _, pb, _ = mech.joint_geometry(j)
        pm = kin.point(j.b, pb)
        centres[j.name], frames[j.name] = (pm.x, pm.y), np.zeros(phi.size)
    ref, q_ref = reference(mech, kin, spec=spec, frames=frames, centres=centres,
                           heights=heights, devs=devs, gravity=g)
    got = r.components()
    assert r.redundant == 4
    assert np.abs(ref[:, 3:5]).max() > 1e-2 * np.abs(ref[:, :2]).max()
    assert np.max(np.abs(got - ref)) <= 1e-8 * np.abs(ref).max()
    assert np.max(np.abs(r.Q - q_ref[0])) <= 1e-8 * np.abs(q_ref).max()


@pytest.mark.parametrize("kind", ["spur", "crowned"])
def test_gear_mesh_tilt_misfit_in_series_with_the_bearings(kind):
    """Two gears on frame pivots (r 40 and 80 mm, 20 deg), a 10 N m load on b, the bore of b's
    pivot tilted by 0.3 mrad about x. Spur teeth (class II): the pair has q = 1 redundant
    constraint, a pure couple loop through both bearings and the mesh: the mesh's moment about
    t = z x n is the tilt's component about t times the three tilt stiffnesses in series
    (k e^2/12 each: bearings 1e8 N/m over 40 and 30 mm, mesh 4e8 N/m over 20 mm face), and
    each bearing carries the same bending moment; no axial force. Crowned teeth (class I): q =
    0, the tilt is taken up freely, no moment anywhere. Hand solution to 1e-9."""
    from linkwork.planar import Body, Crank, GearPair, Mechanism, Revolute

    frame = Body("frame", {"Oa": (0.0, 0.0), "Ob": (0.12, 0.0)})
    mech = Mechanism(frame, (Body("ga", {"Oa": (0.0, 0.0)}), Body("gb", {"Ob": (0.0, 0.0)})),
                     (Revolute("Oa", "frame", "ga"), Revolute("Ob", "frame", "gb"),
                      GearPair("G", "ga", "gb", radii=(0.04, 0.08))), Crank("Oa", omega1=3.0))
    phi = np.linspace(0.3, 2.0, 5)
    tilt = 3e-4
    r = spatial_reactions(mech, phi, loads=[BodyTorque("gb", 10.0)],
                          joints={"Oa": {"e": 0.04}, "Ob": {"e": 0.03},
                                  "G": {"kind": kind, "e": 0.02, "k_bearing": 4e8}},
                          deviations=[Deviation("Ob", "frame", tx=tilt)])
    assert r.redundant == (1 if kind == "spur" else 0)
    ig = r.joints.index("G")
    np.testing.assert_allclose(np.hypot(r.fx[ig], r.fy[ig]), 125 / np.cos(np.radians(20)),
                               rtol=1e-12)
    assert np.abs(r.fz).max() <= 1e-9 * 125
    if kind == "crowned":
        assert np.abs(np.stack([r.mx, r.my])).max() <= 1e-9 * 125 * 0.1
        return
    n = np.arctan2(r.fy[ig], r.fx[ig])  # the line of action (the tooth force on b)
    t = np.stack([-np.sin(n), np.cos(n)])
    about_t = tilt * t[0]  # the tilt (about x) resolved on t
    k_series = 1.0 / sum(12.0 / (k * e * e) for k, e in ((1e8, 0.04), (1e8, 0.03),
                                                        (4e8, 0.02)))
    mt = r.mx[ig] * t[0] + r.my[ig] * t[1]
    np.testing.assert_allclose(np.abs(mt), k_series * np.abs(about_t), rtol=1e-9)
    assert np.abs(r.mx[ig] * np.cos(n) + r.my[ig] * np.sin(n)).max() <= 1e-9 * np.abs(mt).max()
    for name in ("Oa", "Ob"):
        i = r.joints.index(name)
        np.testing.assert_allclose(r.bending()[i], np.abs(mt), rtol=1e-9)
