"""Spatial reactions with redundant constraints: counting, two formulations, invariances,
an independent finite-element-like assembly of the joint springs, analytic two-bearing shaft."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _fourbar_reference import geometry, planar_reactions, spatial_model, wrenches
from _spatial_cases import JOINTS as LOOM_JOINTS
from _spatial_cases import spatial
from _strategies import reals
from hypothesis import given, settings
from hypothesis import strategies as st

from linkwork import redundancy as rd
from linkwork.cli.reactions import load_problem
from linkwork.errors import ParameterError, StructureError
from linkwork.planar import crank_slider_mechanism, kinematics
from linkwork.planar.model import fourbar_mechanism
from linkwork.redundancy import (
    SpatialGeometry,
    SpatialJoint,
    SpatialModel,
    bearing_stiffness,
    count_redundancy,
    solve_reactions,
)

PHI = np.linspace(0.0, 2 * np.pi, 24, endpoint=False)


def _dev(n_joints=4, **items):
    """deviations array; items like O_a=(dx, dy, dz, tx, ty, tz)."""
    d = np.zeros((n_joints, 2, 6))
    names = "OABC"
    for key, val in items.items():
        j, side = key.split("_")
        d[names.index(j), 0 if side == "a" else 1] = val
    return d


DEV = _dev(O_a=(1e-5, -2e-5, 3e-5, 2e-4, -1e-4, 0), B_b=(0, 0, -4e-5, -3e-4, 5e-4, 0),
           C_a=(2e-5, 0, 1e-5, 1e-4, 2e-4, 0), A_a=(0, 1e-5, 0, 0, -2e-4, 0))


# ------------------------------------------------------------------------------------------------
# counting


def test_count_fourbar_four_revolutes_q3_hand_count():
    """n = 3, p5 = 4: W0 = 18 - 20 = -2, W = 1 -> q = 3; in-plane forces and Q determinate,
    axial forces and bending moments not."""
    c = count_redundancy(spatial_model(), geometry(PHI[:3]), position=1)
    assert (c.n_bodies, c.p, c.mobility_formula, c.mobility, c.redundant) == (3, {5: 4}, -2, 1, 3)
    for (joint, comp), det in zip(c.labels, c.determinate, strict=True):
        assert det == (comp in ("fx", "fy", "Q")), (joint, comp)
    assert c.selfstress.shape == (21, 3)
    assert "q = W - W0 = 3" in c.summary()


def test_count_fourbar_self_aligning_joints_q0():
    """R-R-S-C four-bar (classes 5, 5, 3, 4): W0 = 18 - 17 = 1 = W, q = 0: all determinate."""
    m = spatial_model(kinds=("revolute", "revolute", "spherical", "cylindrical"))
    c = count_redundancy(m, geometry(PHI[:2]), position=1)
    assert (c.mobility_formula, c.mobility, c.redundant) == (1, 1, 0)
    assert c.determinate.all()


def test_count_fourbar_two_spherical_local_mobility():
    """R-S-S-R: W0 = 18 - 16 = 2 = W (the coupler spins about AB), q = 0."""
    m = spatial_model(kinds=("revolute", "spherical", "spherical", "revolute"))
    c = count_redundancy(m, geometry(PHI[:2]), position=1)
    assert (c.mobility_formula, c.mobility, c.redundant) == (2, 2, 0)
    with pytest.raises(StructureError, match="movable in space"):
        solve_reactions(m, geometry(PHI[:2]), wrenches(PHI[:2]))


def _crank_slider():
    joints = (SpatialJoint("O", "ground", "crank"), SpatialJoint("A", "crank", "rod"),
              SpatialJoint("B", "rod", "slider"),
              SpatialJoint("P", "ground", "slider", kind="prismatic", e=0.05))
    model = SpatialModel(("crank", "rod", "slider"), joints, "O")
    phi = 0.7
    a = 0.05 * np.array([np.cos(phi), np.sin(phi)])
    bx = a[0] + np.sqrt(0.2**2 - a[1] ** 2)
    pts = np.array([[[0, 0], a, [bx, 0], [bx, 0]]])
    ang = np.array([[phi, np.arctan2(-a[1], bx - a[0]), 0.0]])
    return model, SpatialGeometry(pts, ang, np.zeros((1, 4)))


def test_count_crank_slider_q3_hand_count():
    """3 R + 1 P, all class V: W0 = 18 - 20 = -2, W = 1, q = 3; in-plane f_n, m_z of the slider
    and all in-plane forces determinate."""
    model, geom = _crank_slider()
    c = count_redundancy(model, geom)
    assert (c.mobility_formula, c.mobility, c.redundant) == (-2, 1, 3)
    for (joint, comp), det in zip(c.labels, c.determinate, strict=True):
        inplane = comp in ("fx", "fy", "Q") or (joint == "P" and comp in ("fn", "mz"))
        assert det == inplane, (joint, comp)


def _six_bar_watt():
    """Watt six-bar: four-bar O-A-B-C plus dyad D-E-F on the rocker (ternary) and ground."""
    bodies = ("crank", "coupler", "rocker", "link4", "link5")
    conn = [("O", "ground", "crank"), ("A", "crank", "coupler"), ("B", "coupler", "rocker"),
            ("C", "ground", "rocker"), ("D", "rocker", "link4"), ("E", "link4", "link5"),
            ("F", "ground", "link5")]
    joints = tuple(SpatialJoint(n, a, b, z=0.01 * i) for i, (n, a, b) in enumerate(conn))
    pts = np.array([[[0, 0], [0.05, 0.08], [0.3, 0.2], [0.3, 0], [0.4, 0.15], [0.6, 0.3],
                     [0.7, 0.0]]])
    ang = np.array([[1.0, 0.4, 1.6, 0.3, 1.9]])
    return SpatialModel(bodies, joints, "O"), SpatialGeometry(pts, ang)


def test_count_watt_six_bar_q6_hand_count():
    """n = 5, p5 = 7: W0 = 30 - 35 = -5, W = 1, q = 6 (two independent loops, 3 each)."""
    model, geom = _six_bar_watt()
    c = count_redundancy(model, geom)
    assert (c.n_bodies, c.p, c.mobility_formula, c.mobility, c.redundant) == (5, {5: 7}, -5, 1, 6)
    for (_, comp), det in zip(c.labels, c.determinate, strict=True):
        assert det == (comp in ("fx", "fy", "Q"))


def test_six_bar_two_formulations_agree():
    model, geom = _six_bar_watt()
    rng = np.random.default_rng(3)
    w = rng.normal(size=(1, 5, 6)) * np.array([100, 100, 10, 5, 5, 5])
    dev = rng.normal(size=(7, 2, 6)) * np.array([1e-5, 1e-5, 1e-5, 1e-4, 1e-4, 0])
    rf = solve_reactions(model, geom, w, dev)
    rd = solve_reactions(model, geom, w, dev, method="displacement")
    scale = np.max(np.abs(rf.components()))
    assert np.max(np.abs(rf.components() - rd.components())) < 1e-9 * scale
    assert rf.redundant == 6


# ------------------------------------------------------------------------------------------------
# two formulations, planar solution


def _max_rel(a, b):
    return np.max(np.abs(a - b)) / np.max(np.abs(b))


def test_force_and_displacement_methods_agree_1e9():
    m = spatial_model(e=(0.04, 0.02, 0.03, 0.05), z=(0.0, 0.03, 0.03, -0.01))
    g = geometry(PHI)
    w = wrenches(PHI, z_g=(0.01, 0.03, 0.0), out_of_plane=[[5, 1, -2], [0, 0, 0], [-3, 0, 1]])
    rf = solve_reactions(m, g, w, DEV, phi1=PHI)
    rd = solve_reactions(m, g, w, DEV, phi1=PHI, method="displacement")
    assert _max_rel(rd.components(), rf.components()) < 1e-9
    assert np.max(np.abs(rd.Q - rf.Q)) < 1e-9 * np.max(np.abs(rf.Q))
    assert np.max(np.abs(rf.fz)) > 1.0 and np.max(rf.bending()) > 0.1


@settings(max_examples=40, deadline=None)
@given(e=st.lists(st.floats(0.005, 0.1), min_size=4, max_size=4),
       z=st.lists(reals(-0.05, 0.05), min_size=4, max_size=4),
       logk=st.lists(st.floats(6.0, 10.0), min_size=4, max_size=4),
       dev_scale=reals(0.0, 1e-3), seed=st.integers(0, 10_000))
def test_inplane_reactions_and_Q_equal_planar_solution(e, z, logk, dev_scale, seed):
    """In-plane reactions and driving torque do not depend on e, compliances, deviations or
    out-of-plane loads: they equal an independent planar kinetostatic solution."""
    rng = np.random.default_rng(seed)
    phi = PHI[::3]
    stiff = [bearing_stiffness("revolute", ei, 10**lk) * rng.uniform(0.5, 2, 6)
             for ei, lk in zip(e, logk, strict=True)]
    m = spatial_model(e=e, z=z, stiffness=stiff)
    dev = rng.normal(size=(4, 2, 6)) * dev_scale
    w = wrenches(phi, z_g=rng.normal(size=3) * 0.02, out_of_plane=rng.normal(size=(3, 3)) * 5)
    r = solve_reactions(m, geometry(phi), w, dev)
    ref, q = planar_reactions(phi)
    got = np.stack([r.fx, r.fy], -1).transpose(1, 0, 2)
    assert np.max(np.abs(got - ref)) < 1e-8 * np.max(np.abs(ref))
    assert np.max(np.abs(r.Q - q)) < 1e-8 * np.max(np.abs(q))
    # revolute joints carry no moment about their axis; the driver's is Q, reported at O
    assert np.max(np.abs(r.mz[1:])) < 1e-8 * np.max(np.abs(q))
    assert np.array_equal(r.mz[0], r.Q)


def test_no_deviation_planar_loads_no_out_of_plane_reactions():
    """All joints and centres of mass in one plane, no deviations: fz = mx = my = 0."""
    m = spatial_model(z=(0, 0, 0, 0))
    r = solve_reactions(m, geometry(PHI), wrenches(PHI))
    scale = np.max(np.abs(r.fx))
    for comp in (r.fz, r.mx, r.my):
        assert np.max(np.abs(comp)) < 1e-10 * scale


def test_deviation_and_out_of_plane_load_create_out_of_plane_reactions():
    m = spatial_model(z=(0, 0, 0, 0))
    g = geometry(PHI)
    with_dev = solve_reactions(m, g, wrenches(PHI), _dev(C_a=(0, 0, 1e-5, 0, 0, 0)))
    # 10 µm axial misfit: mostly taken up by the (soft) tilt of the joints -> ~0.8 N
    assert 0.3 < np.max(np.abs(with_dev.fz)) < 5.0
    tilt = solve_reactions(m, g, wrenches(PHI), _dev(C_a=(0, 0, 0, 1e-4, 0, 0)))
    # 0.1 mrad tilt misfit against four tilt springs k_t = k_b e^2/12 = 7500 N m/rad in series:
    # a circulating bending moment of the order 1e-4 * 7500 / 4 = 0.19 N m
    assert 0.1 < np.max(tilt.bending()) < 0.4
    oop = solve_reactions(m, g, wrenches(PHI, out_of_plane=[[0, 0, 0], [10, 0, 0], [0, 0, 0]]))
    assert np.max(np.abs(oop.fz)) > 1.0


@pytest.mark.parametrize("factor", [1e-3, 7.0, 1e4])
def test_stiffness_scaling(factor):
    """No deviation: scaling every stiffness leaves the reactions unchanged. With a deviation
    the deviation-induced part scales in proportion to the stiffness."""
    g = geometry(PHI)
    w = wrenches(PHI, z_g=(0.01, 0.03, 0.0), out_of_plane=[[5, 1, -2], [0, 0, 0], [-3, 0, 1]])
    m1 = spatial_model(e=(0.04, 0.02, 0.03, 0.05), z=(0.0, 0.03, 0.03, -0.01))
    m2 = spatial_model(e=(0.04, 0.02, 0.03, 0.05), z=(0.0, 0.03, 0.03, -0.01),
                       k_bearing=1e8 * factor)
    r1, r2 = solve_reactions(m1, g, w), solve_reactions(m2, g, w)
    assert _max_rel(r2.components(), r1.components()) < 1e-9
    d1 = solve_reactions(m1, g, w, DEV).components() - r1.components()
    d2 = solve_reactions(m2, g, w, DEV).components() - r2.components()
    assert np.max(np.abs(d1)) > 1.0
    assert _max_rel(d2, factor * d1) < 1e-8


def test_deviation_part_is_linear_and_does_not_depend_on_loads():
    g = geometry(PHI)
    m = spatial_model()
    w0 = np.zeros((len(PHI), 3, 6))
    pure = solve_reactions(m, g, w0, DEV).components()
    both = solve_reactions(m, g, wrenches(PHI), DEV).components()
    load = solve_reactions(m, g, wrenches(PHI)).components()
    assert _max_rel(both - load, pure) < 1e-9
    twice = solve_reactions(m, g, w0, 2 * DEV).components()
    assert _max_rel(twice, 2 * pure) < 1e-9


def test_inplane_deviation_offsets_cause_no_stress():
    """Offsets dx, dy only shift the planar configuration (first order): no reactions."""
    g = geometry(PHI)
    d = _dev(A_b=(3e-5, -2e-5, 0, 0, 0, 0), C_a=(1e-5, 4e-5, 0, 0, 0, 0))
    r = solve_reactions(spatial_model(), g, np.zeros((len(PHI), 3, 6)), d)
    assert np.max(np.abs(r.components())) < 1e-6


# ------------------------------------------------------------------------------------------------
# independent model: finite-element-like assembly of the joint springs, one position at a time


def _skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def _fe_solve(e, z, kvec_local, points, angles, w_origin, dev, k_drive=1e9):
    """Nodes: the three moving bodies, 6 DOFs each at their own reference point (first joint's
    centre projected in the plane, different from linkwork's origin reduction); joint springs
    assembled as 12x12 elements; the driver is a torsion spring crank-ground."""
    conn = [(-1, 0), (0, 1), (1, 2), (-1, 2)]
    refs = np.array([[0.0, 0.0, 0.0], [*points[1], 0.0], [*points[3], 0.01]])
    n_dof = 18
    kk = np.zeros((n_dof, n_dof))
    ff = np.zeros(n_dof)
    # loads: the wrench about the origin moved to each body's reference point
    for b in range(3):
        f, mo = w_origin[b, :3], w_origin[b, 3:]
        ff[6 * b:6 * b + 3] += f
        ff[6 * b + 3:6 * b + 6] += mo - np.cross(refs[b], f)
    elems = []
    for j, (ba, bb) in enumerate(conn):
        p = np.array([*points[j], z[j]])
        k_loc = np.diag(kvec_local[j])
        # rows: relative (translation at p, rotation); body DOFs -> motion at p
        def motion(b, p=p):
            e6 = np.zeros((6, n_dof))
            if b < 0:
                return e6
            e6[:3, 6 * b:6 * b + 3] = np.eye(3)
            e6[:3, 6 * b + 3:6 * b + 6] = -_skew(p - refs[b])
            e6[3:, 6 * b + 3:6 * b + 6] = np.eye(3)
            return e6
        d_rel = motion(bb) - motion(ba)
        def rot(angle):
            c, s = np.cos(angle), np.sin(angle)
            r = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
            return np.block([[r, np.zeros((3, 3))], [np.zeros((3, 3)), r]])
        ang_a = 0.0 if ba < 0 else angles[ba]
        ang_b = angles[bb]
        mis = rot(ang_b) @ dev[j, 1] - rot(ang_a) @ dev[j, 0]
        kk += d_rel.T @ k_loc @ d_rel
        ff -= d_rel.T @ k_loc @ mis
        elems.append((d_rel, k_loc, mis))
    # driver: torsion spring about z between crank and ground
    kk[5, 5] += k_drive
    u = np.linalg.solve(kk, ff)
    out = np.zeros((4, 6))
    for j, (d_rel, k_loc, mis) in enumerate(elems):
        out[j] = -k_loc @ (d_rel @ u + mis)
    return out, -k_drive * u[5]


def test_independent_fe_assembly_agrees():
    e = (0.04, 0.02, 0.03, 0.05)
    z = (0.0, 0.03, 0.03, -0.01)
    m = spatial_model(e=e, z=z)
    phi = PHI[::4]
    g = geometry(phi)
    w = wrenches(phi, z_g=(0.01, 0.03, 0.0), out_of_plane=[[5, 1, -2], [0, 0, 0], [-3, 0, 1]])
    r = solve_reactions(m, g, w, DEV)
    kloc = [bearing_stiffness("revolute", ei) for ei in e]
    comp = r.components()
    for i in range(len(phi)):
        ref, q = _fe_solve(e, z, kloc, g.points[i], g.body_angles[i], w[i], DEV)
        got = comp[:, :, i]
        got = got.copy()
        got[0, 5] = 0.0  # the driving torque is reported in mz of O by linkwork
        assert np.max(np.abs(got - ref)) < 1e-6 * np.max(np.abs(ref))
        assert abs(r.Q[i] - q) < 1e-6 * abs(q) + 1e-9


# ------------------------------------------------------------------------------------------------
# analytic: a shaft in two bearings


def _shaft(e, length, kb=1e8, axial_ratio=1.0):
    joints = (SpatialJoint("O1", "ground", "shaft", e=e, z=0.0, k_bearing=kb,
                           axial_ratio=axial_ratio),
              SpatialJoint("O2", "ground", "shaft", e=e, z=length, k_bearing=kb,
                           axial_ratio=axial_ratio))
    model = SpatialModel(("shaft",), joints, "O1")
    geom = SpatialGeometry(np.zeros((3, 2, 2)), np.array([[0.0], [1.0], [2.0]]))
    return model, geom


def test_shaft_in_two_bearings_count():
    model, geom = _shaft(0.02, 0.2)
    c = count_redundancy(model, geom)
    assert (c.mobility_formula, c.mobility, c.redundant) == (-4, 1, 5)


@pytest.mark.parametrize("e", [0.01, 0.03, 0.08])
def test_shaft_axial_and_radial_misfit_analytic(e):
    """Axial misfit dz: the axial springs in series, F = dz k/2. Radial offset d of the second
    bearing, radial k and tilt k_t = k e^2/12 in each: the second bearing carries
    F = 2 k k_t d / (k L^2 + 4 k_t) = k d e^2 / (6 L^2 + 2 e^2) (minimum of the spring energy,
    derived by hand)."""
    length, kb, d = 0.2, 1e8, 1e-5
    model, geom = _shaft(e, length, kb)
    w = np.zeros((3, 1, 6))
    dev = np.zeros((2, 2, 6))
    dev[1, 0, 2] = d
    r = solve_reactions(model, geom, w, dev)
    # bearing 2's ground element is shifted +d: the shaft pulls it, i.e. it pushes the shaft +z
    assert np.allclose(r.fz[1], kb * d / 2, rtol=1e-9)
    assert np.allclose(r.fz[0], -kb * d / 2, rtol=1e-9)
    dev = np.zeros((2, 2, 6))
    dev[1, 0, 0] = d
    r = solve_reactions(model, geom, w, dev)
    expected = kb * d * e**2 / (6 * length**2 + 2 * e**2)
    assert np.allclose(r.fx[1], expected, rtol=1e-9)
    assert np.allclose(r.fx[0], -expected, rtol=1e-9)


# ------------------------------------------------------------------------------------------------
# input checks


def test_bad_inputs_raise_parameter_errors():
    with pytest.raises(ParameterError, match="kind"):
        SpatialJoint("X", "ground", "crank", kind="hinge")
    with pytest.raises(ParameterError, match=r"e = -0\.01"):
        SpatialJoint("X", "ground", "crank", e=-0.01)
    with pytest.raises(ParameterError, match="constrained"):
        SpatialJoint("X", "ground", "crank", stiffness=(1, 1, 0, 1, 1, 0))
    with pytest.raises(ParameterError, match="driver"):
        SpatialModel(("crank",), (SpatialJoint("X", "ground", "crank"),), "Y")
    m = spatial_model()
    with pytest.raises(ParameterError, match="deviations"):
        solve_reactions(m, geometry(PHI), wrenches(PHI), np.zeros((3, 2, 6)))
    with pytest.raises(ParameterError, match="method"):
        solve_reactions(m, geometry(PHI), wrenches(PHI), method="magic")
    with pytest.raises(ParameterError, match="wrenches"):
        solve_reactions(m, geometry(PHI), np.zeros((2, 3, 6)))


def test_count_crank_slider_round_guide_q2():
    """A round guide (prismatic_round, class IV: free roll about the slide): W0 = 18 - 19 = -1,
    W = 1, q = 2."""
    model, geom = _crank_slider()
    joints = (*model.joints[:3], SpatialJoint("P", "ground", "slider", kind="prismatic_round",
                                              e=0.05))
    c = count_redundancy(SpatialModel(model.bodies, joints, "O"), geom)
    assert (c.p, c.mobility_formula, c.mobility, c.redundant) == ({5: 3, 4: 1}, -1, 1, 2)


def test_tilt_deviations_beyond_first_order_theory_are_named_in_the_api():
    from linkwork.redundancy import Deviation, Tolerance, spatial_reactions

    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0), omega1=10.0)
    with pytest.raises(ParameterError, match="tx"):
        spatial_reactions(mech, [0.0, 1.0], deviations=[Deviation("O4", "frame", tx=0.5)])
    with pytest.raises(ParameterError, match="ty"):
        Tolerance("O4", "a", "ty", 0.05, "uniform", mean=0.08)
    # small ones are fine
    spatial_reactions(mech, [0.0, 1.0], deviations=[Deviation("O4", "frame", tx=0.01)])


ROOT = Path(__file__).resolve().parents[2]


SIXBAR = ROOT / "examples" / "loom_sixbar.toml"


def _model(joints, bodies, driver, kinds=None):
    kinds = kinds or {}
    return rd.SpatialModel(tuple(bodies), tuple(
        rd.SpatialJoint(n, a, b, kind=kinds.get(n, "revolute")) for n, a, b in joints), driver)


def _geom(points, nb):
    return rd.SpatialGeometry(np.asarray(points, float)[None], np.zeros((1, nb)))


FOURBAR = [("O", "ground", "crank"), ("A", "crank", "coupler"), ("B", "coupler", "rocker"),
           ("C", "ground", "rocker")]


FOURBAR_PTS = [(0, 0), (0.03, 0.09), (0.28, 0.2), (0.3, 0)]


@pytest.mark.parametrize("kinds, w0, w, q", [
    ({}, 6 * 3 - 5 * 4, 1, 3),                                   # 4 R (class V)
    ({"B": "spherical", "C": "cylindrical"}, 18 - (5 + 5 + 3 + 4), 1, 0),   # R-R-S-C
    ({"A": "spherical", "B": "spherical"}, 18 - (5 + 3 + 3 + 5), 2, 0),     # R-S-S-R, spin
])
def test_count_fourbar_by_hand(kinds, w0, w, q):
    c = rd.count_redundancy(_model(FOURBAR, ["crank", "coupler", "rocker"], "O", kinds),
                            _geom(FOURBAR_PTS, 3))
    assert (c.mobility_formula, c.mobility, c.redundant) == (w0, w, q)
    if not kinds:
        # in-plane components unique, out-of-plane ones not
        ind = set(c.indeterminate_labels())
        assert ind == {(j, k) for j in "OABC" for k in ("fz", "mx", "my")}


def test_count_crank_slider_by_hand():
    """3 moving bodies, 3 R + 1 P, all class V: W0 = 18 - 20 = -2, W = 1, q = 3."""
    mech = crank_slider_mechanism(0.05, 0.2, 0.01, masses=(1, 1, 1))
    kin = kinematics(mech, np.radians([37.0]))
    c = rd.count_redundancy(rd.spatial_model(mech), rd.geometry(mech, kin))
    assert (c.n_bodies, c.mobility_formula, c.mobility, c.redundant) == (3, -2, 1, 3)
    assert c.p == {5: 4}


def test_count_watt_sixbar_by_hand():
    """Watt six-bar, 5 moving bodies, 7 R: W0 = 30 - 35 = -5, W = 1, q = 6 (two loops x 3)."""
    joints = [("O2", "ground", "crank"), ("A", "crank", "c1"), ("B", "c1", "tern"),
              ("O4", "ground", "tern"), ("C", "tern", "c2"), ("D", "c2", "rock"),
              ("O6", "ground", "rock")]
    pts = [(0, 0), (0.05, 0.08), (0.3, 0.25), (0.35, 0), (0.45, 0.15), (0.7, 0.3), (0.8, 0.0)]
    c = rd.count_redundancy(_model(joints, ["crank", "c1", "tern", "c2", "rock"], "O2"),
                            _geom(pts, 5))
    assert (c.mobility_formula, c.mobility, c.redundant) == (-5, 1, 6)


def test_count_loom_sixbar_example_by_hand():
    """The bundled loom six-bar: 5 moving bodies, 6 R + 1 P (class V): q = 6."""
    mech, kw, _ = load_problem(SIXBAR)
    kin = kinematics(mech, kw["cycle"][[17]])
    c = rd.count_redundancy(rd.spatial_model(mech), rd.geometry(mech, kin))
    assert (c.n_bodies, c.mobility_formula, c.mobility, c.redundant) == (5, -5, 1, 6)


def test_force_and_displacement_methods_agree_to_1e_9():
    oop = [rd.OutOfPlaneLoad("coupler", fz=3.0, mx=0.5, my=-0.2)]
    a = spatial(method="force", oop=oop).components()
    b = spatial(method="displacement", oop=oop).components()
    for k in range(6):
        scale = np.max(np.abs(a[:, k]))
        assert np.max(np.abs(a[:, k] - b[:, k])) <= 1e-9 * max(scale, 1e-300)


def test_stiffness_scaling_invariances():
    base = {j: dict(LOOM_JOINTS[j], k_bearing=1e8) for j in LOOM_JOINTS}
    scaled = {j: dict(LOOM_JOINTS[j], k_bearing=7e8) for j in LOOM_JOINTS}
    a = spatial(joints=base, devs=[]).components()
    b = spatial(joints=scaled, devs=[]).components()
    assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(a))
    da = spatial(joints=base).components() - a
    db = spatial(joints=scaled).components() - b
    assert np.max(np.abs(da)) > 1e-3
    assert np.max(np.abs(db - 7 * da)) <= 1e-8 * np.max(np.abs(db))


def test_reactions_vary_with_e_as_the_shaft_model_predicts():
    """A shaft (one body) in two coaxial bearings a distance L apart, bearing length e, an
    offset d of the second bearing: bending by hand. Each bearing: radial k, tilt k e^2/12.
    Shaft rotation theta and translation u: the springs give
    F = k d e^2 / (6 L^2 + 2 e^2) at each bearing (derived below by energy minimisation)."""
    k, L, d = 1e8, 0.2, 1e-5
    for e in (0.01, 0.03, 0.06):
        # the shaft's axis is z: bearings at z = 0 and z = L, same plane point
        model = rd.SpatialModel(("shaft",), (
            rd.SpatialJoint("J1", "ground", "shaft", e=e, z=0.0, k_bearing=k),
            rd.SpatialJoint("J2", "ground", "shaft", e=e, z=L, k_bearing=k)), "J1")
        geom = rd.SpatialGeometry(np.zeros((1, 2, 2)), np.zeros((1, 1)))
        dev = np.zeros((2, 2, 6))
        dev[1, 0, 0] = d  # ground's bore of J2 offset by d along x
        r = rd.solve_reactions(model, geom, np.zeros((1, 1, 6)), dev)
        # by hand: minimise 1/2 k (u + 0)^2 + 1/2 k (u + L th - d)^2 + 2 * 1/2 kt th^2 with
        # u the x translation at z = 0 and th the rotation about y (x = u + z th)
        kt = k * e * e / 12
        Kmat = np.array([[2 * k, k * L], [k * L, k * L * L + 2 * kt]])
        u, th = np.linalg.solve(Kmat, [k * d, k * L * d])
        F1 = -k * u
        assert r.fx[0, 0] == pytest.approx(F1, rel=1e-9)
        assert F1 == pytest.approx(-k * d * e * e / (6 * L * L + 2 * e * e), rel=1e-12)
        assert r.my[0, 0] == pytest.approx(-kt * th, rel=1e-9)


@pytest.mark.parametrize("joints, name", [
    ({"A": dict(e=0.03, z=0.03, stiffness=(1e20, 1e20, 1e20, 1e-20, 1e-20, 0))}, "stiffness"),
    ({j: dict(e=1e-300) for j in "OABC"}, ".e"),
])
def test_ill_conditioned_or_underflowing_compliance_is_named(joints, name):
    """Stiffnesses 1e20 and 1e-20 in one joint gave numpy's 'LinAlgError: Singular matrix'
    (a traceback through the CLI); e = 1e-300 m made k_b e^2/12 underflow to 0 and divided by
    zero (RuntimeWarning, inf/NaN reactions)."""
    for method in ("force", "displacement"):
        with pytest.raises(ParameterError) as exc:
            spatial(joints=joints, method=method)
        assert name in exc.value.parameter
