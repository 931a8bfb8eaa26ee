"""Acceptance check of issue 6 (redundant constraints, paper 004), as an external checker would.

Independent references computed here: hand counts (Somov-Malyshev) for a four-bar, a
crank-slider and six-bars; the planar engine's inverse dynamics for the in-plane reactions; a
spatial stiffness model of rigid links on compliant joints assembled from scratch (potential
energy of the joint springs, 6 small displacements per body); brute-force per-sample solves for
the tolerance study; a Dask cluster against the in-process run; the command line on the bundled
example and on broken files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from linkwork import redundancy as rd
from linkwork.cli import main
from linkwork.cli.reactions import load_problem
from linkwork.errors import LinkworkError, ParameterError, StructureError
from linkwork.planar import BodyTorque, kinematics
from linkwork.planar.dynamics import inverse_dynamics
from linkwork.planar.model import crank_slider

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "loom_fourbar_spatial.toml"
SIXBAR = ROOT / "examples" / "loom_sixbar.toml"
G = (0.0, -9.81)


def loom():
    mech, _, _ = load_problem(EXAMPLE)
    return mech


# ---------------------------------------------------------------------------------------------
# 1. counting against hand counts


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
    mech = crank_slider(0.05, 0.2, 0.01, masses=(1, 1, 1))
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


# ---------------------------------------------------------------------------------------------
# 2./3. spatial kinetostatics: planar invariance, two formulations, independent model


def loads_ext(phi):
    return [BodyTorque("rocker", 4.0 + 0 * phi)]


JOINTS = {"O": dict(e=0.03, z=0.0), "A": dict(e=0.02, z=0.03), "B": dict(e=0.04, z=0.03),
          "C": dict(e=0.025, z=-0.03)}
HEIGHTS = {"crank": 0.0, "coupler": 0.03, "rocker": 0.01}
DEVS = [rd.Deviation("C", "frame", tx=2e-4, ty=-1e-4), rd.Deviation("A", "crank", ty=-1e-4,
                                                                     dz=1e-5),
        rd.Deviation("B", "rocker", dz=2e-5, tx=5e-5), rd.Deviation("O", "crank", dx=1e-5)]
PHI = np.radians(np.arange(0.0, 360.0, 15.0))


def spatial(mech=None, joints=JOINTS, devs=DEVS, method="force", oop=(), phi=PHI, **kw):
    mech = mech or loom()
    return rd.spatial_reactions(mech, phi, gravity=G, loads=loads_ext(phi), joints=joints,
                                heights=HEIGHTS, deviations=devs, method=method,
                                out_of_plane=oop, **kw)


def test_inplane_reactions_and_torque_equal_the_planar_engine_whatever_e_k_deviations():
    mech = loom()
    dyn = inverse_dynamics(kinematics(mech, PHI), gravity=G, loads=loads_ext(PHI))
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
    phi = PHI
    kw = dict(gravity=G, loads=loads_ext(phi), joints=flat)
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


def test_force_and_displacement_methods_agree_to_1e_9():
    oop = [rd.OutOfPlaneLoad("coupler", fz=3.0, mx=0.5, my=-0.2)]
    a = spatial(method="force", oop=oop).components()
    b = spatial(method="displacement", oop=oop).components()
    for k in range(6):
        scale = np.max(np.abs(a[:, k]))
        assert np.max(np.abs(a[:, k] - b[:, k])) <= 1e-9 * max(scale, 1e-300)


def test_stiffness_scaling_invariances():
    base = {j: dict(JOINTS[j], k_bearing=1e8) for j in JOINTS}
    scaled = {j: dict(JOINTS[j], k_bearing=7e8) for j in JOINTS}
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

    def cross_mat(p):
        x, y, z = p
        return np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])

    def rot(a):
        c, s = np.cos(a), np.sin(a)
        R = np.zeros((6, 6))
        for o in (0, 3):
            R[o:o + 3, o:o + 3] = [[c, -s, 0], [s, c, 0], [0, 0, 1]]
        return R

    for n in range(len(phi)):
        Kg = np.zeros((6 * nb, 6 * nb))
        f = np.zeros(6 * nb)
        Bs = []
        for bi, b in enumerate(mech.bodies):
            c = kin.point(b.name, "com")
            p = np.array([c.x[n], c.y[n], heights.get(b.name, 0.0)])
            F = np.array([b.mass * (G[0] - c.ax[n]), b.mass * (G[1] - c.ay[n]), 0.0])
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
    joints = {j: dict(JOINTS[j], k_bearing=kb) for j, kb in zip("OABC", (1e8, 2e8, 5e7, 1e8),
                                                                   strict=True)}
    phi = PHI[::2]
    ref, Qref = _independent_reactions(mech, phi, joints, HEIGHTS, DEVS)
    r = spatial(mech, joints, DEVS, phi=phi)
    got = r.components()
    for k in range(6):
        scale = np.max(np.abs(ref[:, k])) if k < 5 else np.max(np.abs(Qref))
        assert np.max(np.abs(got[:, k] - ref[:, k])) <= 1e-7 * scale, k
    assert np.max(np.abs(r.Q - Qref)) <= 1e-7 * np.max(np.abs(Qref))


# ---------------------------------------------------------------------------------------------
# 4. tolerance study


def _problem(nphi=36):
    mech = loom()
    phi = np.linspace(0, 2 * np.pi, nphi, endpoint=False)
    kin = kinematics(mech, phi)
    model = rd.spatial_model(mech, JOINTS)
    geom = rd.geometry(mech, kin)
    w = rd.body_wrenches(mech, kin, gravity=G, loads=loads_ext(phi), heights=HEIGHTS)
    return model, geom, w


TOLS = [rd.Tolerance("C", "a", "tx", 3e-4), rd.Tolerance("O", "a", "ty", 3e-4),
        rd.Tolerance("B", "b", "dz", 3e-5, "uniform"), rd.Tolerance("A", "a", "tx", 2e-4,
                                                                    mean=1e-4)]


def test_tolerance_study_percentiles_against_brute_force_per_sample_solves():
    model, geom, w = _problem()
    st = rd.tolerance_study(model, geom, w, TOLS, 120, seed=11, chunk_size=50)
    # the draws follow the distributions
    assert np.all(np.abs(st.draws[:, 2]) <= 3e-5)
    # brute force: one full solve per sample (displacement method: another formulation)
    slot = {"a": 0, "b": 1}
    names = [j.name for j in model.joints]
    comps = ("dx", "dy", "dz", "tx", "ty", "tz")
    peaks = np.zeros_like(st.peaks)
    for i in range(st.n_samples):
        dev = np.zeros((len(names), 2, 6))
        for t, v in zip(TOLS, st.draws[i], strict=True):
            dev[names.index(t.joint), slot[t.side], comps.index(t.component)] += v
        r = rd.solve_reactions(model, geom, w, dev, method="displacement")
        c = r.components()
        peaks[i, :, :6] = np.max(np.abs(c), axis=-1)
        peaks[i, :, 6] = np.max(np.hypot(c[:, 3], c[:, 4]), axis=-1)
    assert np.max(np.abs(peaks - st.peaks)) <= 1e-9 * np.max(np.abs(peaks))
    pct = st.percentiles((50, 95))
    for j, name in enumerate(st.joints):
        for k, q in enumerate(st.quantities):
            assert pct[name][q]["p95"] == pytest.approx(np.percentile(peaks[:, j, k], 95),
                                                        rel=1e-9, abs=1e-12)
    nom = rd.solve_reactions(model, geom, w).components()
    assert np.allclose(st.nominal[:, :6], np.max(np.abs(nom), axis=-1), rtol=1e-9, atol=1e-12)


def test_tolerance_study_on_dask_equals_in_process():
    distributed = pytest.importorskip("distributed")
    model, geom, w = _problem(24)
    local = rd.tolerance_study(model, geom, w, TOLS, 60, seed=5, chunk_size=25)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        remote = rd.tolerance_study(model, geom, w, TOLS, 60, seed=5, chunk_size=25,
                                    client=client)
    assert np.array_equal(local.peaks, remote.peaks)
    assert np.array_equal(local.draws, remote.draws)


# ---------------------------------------------------------------------------------------------
# failure policy: functions


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
    (lambda: rd.spatial_reactions(loom(), PHI, joints={"Z": {"e": 0.03}}), "joints"),
    (lambda: rd.spatial_reactions(loom(), PHI, deviations=[rd.Deviation("Z", "frame")]),
     "deviation.joint"),
    (lambda: rd.spatial_reactions(loom(), PHI, deviations=[rd.Deviation("A", "frame")]),
     "deviation A.body"),
    (lambda: rd.spatial_reactions(loom(), PHI, heights={"nope": 0.1}), "heights"),
    (lambda: rd.spatial_reactions(loom(), PHI, method="fem"), "method"),
    (lambda: rd.count_redundancy(*_problem(12)[:2], position=12), "position"),
])
def test_bad_inputs_are_named(call, name):
    with pytest.raises(LinkworkError) as exc:
        call()
    assert name in str(exc.value)


def test_a_mechanism_movable_in_space_cannot_carry_loads():
    mech = loom()
    with pytest.raises(StructureError, match="movable in space"):
        rd.spatial_reactions(mech, PHI, gravity=G, joints={"A": {"kind": "spherical"},
                                                           "B": {"kind": "spherical"}})


# ---------------------------------------------------------------------------------------------
# 6. command line


def test_cli_reactions_bundled_example_with_tolerance_study(tmp_path, capsys):
    out = tmp_path / "o"
    rc = main(["reactions", str(EXAMPLE), "--out", str(out), "--tolerance-study", "200",
               "--no-plots"])
    text = capsys.readouterr().out
    assert rc == 0
    assert "q = W - W0 = 3" in text
    for f in ("reactions.csv", "reactions.json", "reactions_peaks.json", "tolerance.json",
              "tolerance_samples.csv"):
        assert (out / f).stat().st_size > 0
    # the CSV equals a direct solve of the file's problem
    import csv

    with (out / "reactions.csv").open() as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    data = np.array(rows[1:], float)
    mech, kw, spec = load_problem(EXAMPLE)
    from linkwork.cli.reactions import _model_inputs

    r = rd.spatial_reactions(mech, kw["cycle"], gravity=kw["gravity"],
                             loads=kw["loads"](kw["cycle"]), **_model_inputs(mech, spec))
    assert np.allclose(data[:, head.index("mx_B [N*m]")], r.mx[2], rtol=1e-12, atol=1e-15)
    assert np.allclose(data[:, head.index("Q [N*m]")], r.Q, rtol=1e-12, atol=1e-15)


def _write(tmp_path, text):
    p = tmp_path / "m.toml"
    p.write_text(text)
    return p


BROKEN = {
    "unknown_spatial_key": ("[spatial]\nstiff = 1\n", "spatial.stiff"),
    "unknown_joint": ("[spatial.joints.Z]\ne = '30 mm'\n", "spatial.joints.Z"),
    "e_units": ("[spatial.joints.A]\ne = '30 kg'\n", "spatial.joints.A.e"),
    "e_negative": ("[spatial.joints.A]\ne = '-30 mm'\n", "spatial.joints.A.e"),
    "kind": ("[spatial.joints.A]\nkind = 'ball'\n", "spatial.joints.A.kind"),
    "kind_family": ("[spatial.joints.A]\nkind = 'prismatic'\n", "A.kind"),
    "stiffness_zero": ("[spatial.joints.A]\nstiffness = [1e8, 1e8, 0, 7e3, 7e3, 0]\n",
                       "A.stiffness"),
    "stiffness_len": ("[spatial.joints.A]\nstiffness = [1e8, 1e8]\n",
                      "spatial.joints.A.stiffness"),
    "stiffness_units": ("[spatial.joints.A]\nstiffness = ['1 kg', 1e8, 1e8, 7e3, 7e3, 0]\n",
                        "spatial.joints.A.stiffness"),
    "k_units": ("[spatial]\nk_bearing = '100 mm'\n", "spatial.k_bearing"),
    "k_zero": ("[spatial]\nk_bearing = 0\n", "spatial.k_bearing"),
    "positions": ("[spatial]\npositions = 3\n", "spatial.positions"),
    "dev_missing_joint": ("[[spatial.deviation]]\nbody = 'frame'\ntx = '1 mrad'\n",
                          "spatial.deviation.0.joint"),
    "dev_unknown_joint": ("[[spatial.deviation]]\njoint = 'Z'\nbody = 'frame'\n",
                          "spatial.deviation.0.joint"),
    "dev_wrong_body": ("[[spatial.deviation]]\njoint = 'A'\nbody = 'frame'\n",
                       "spatial.deviation.0.body"),
    "dev_units": ("[[spatial.deviation]]\njoint = 'C'\nbody = 'frame'\ntx = '1 mm'\n",
                  "spatial.deviation.0.tx"),
    "heights_body": ("[spatial]\nheights = { nope = '1 mm' }\n", "spatial.heights.nope"),
    "oop_body": ("[[spatial.out_of_plane]]\nbody = 'nope'\nfz = '1 N'\n",
                 "spatial.out_of_plane.0.body"),
    "tol_limit": ("[[spatial.tolerance]]\njoint = 'C'\nbody = 'frame'\ncomponent = 'tx'\n"
                  "limit = '-1 mrad'\n", "spatial.tolerance.0.limit"),
    "tol_component": ("[[spatial.tolerance]]\njoint = 'C'\nbody = 'frame'\n"
                      "component = 'zz'\nlimit = '1 mrad'\n", "spatial.tolerance.0.component"),
    "tol_units": ("[[spatial.tolerance]]\njoint = 'C'\nbody = 'frame'\ncomponent = 'tx'\n"
                  "limit = '1 mm'\n", "spatial.tolerance.0.limit"),
    "tol_joint": ("[[spatial.tolerance]]\njoint = 'Z'\nbody = 'frame'\ncomponent = 'tx'\n"
                  "limit = '1 mrad'\n", "spatial.tolerance.0.joint"),
    "tol_body": ("[[spatial.tolerance]]\njoint = 'A'\nbody = 'frame'\ncomponent = 'tx'\n"
                 "limit = '1 mrad'\n", "spatial.tolerance.0.body"),
    "spatial_not_table": ("spatial = 3\n", "spatial"),
}


@pytest.mark.parametrize("case", sorted(BROKEN))
def test_cli_reactions_broken_files_one_line_exit_2(tmp_path, capsys, case):
    """The mechanism of the example with only the broken [spatial] data."""
    extra, word = BROKEN[case]
    text = EXAMPLE.read_text()
    text = text[:text.index("\n[spatial]\n") + 1] + extra
    if case == "spatial_not_table":  # a top-level key must come before the first table
        text = extra + text[:-len(extra)]
    rc = main(["reactions", str(_write(tmp_path, text)), "--out", str(tmp_path / "o"),
               "--no-plots", "--tolerance-study", "5"])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert word in err, err


@pytest.mark.parametrize("args, word", [
    (["--tolerance-study", "0"], "--tolerance-study"),
    (["--tolerance-study", "-5"], "--tolerance-study"),
    (["--tolerance-study", "x"], "tolerance-study"),
    (["--method", "fem"], "--method"),
    (["--chunk-size", "0"], "chunk"),
    (["--seed", "-1"], "seed"),
    (["--seed", "-1", "--tolerance-study", "5"], "seed"),
    (["--angles", "a,b"], "angle"),
])
def test_cli_reactions_bad_options_one_line_exit_2(tmp_path, capsys, args, word):
    rc = main(["reactions", str(EXAMPLE), "--out", str(tmp_path / "o"), "--no-plots", *args])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert word in err, err


def test_cli_tolerance_study_without_tolerances(tmp_path, capsys):
    text = EXAMPLE.read_text()
    text = text[:text.index("[[spatial.tolerance]]")]
    rc = main(["reactions", str(_write(tmp_path, text)), "--out", str(tmp_path / "o"),
               "--no-plots", "--tolerance-study", "10"])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "tolerance" in err


def test_tolerance_histogram_and_table_tell_the_lines_apart(tmp_path, capsys):
    """p50/p95/p99 were three lines of one colour; the samples are drawn around the file's
    systematic deviations but only the 'no deviation' peak was shown, so the whole histogram
    looked shifted by the tolerances alone."""
    from linkwork.plot import pyplot
    from linkwork.plot.redundancy import plot_peak_histogram

    model, geom, w = _problem(24)
    st = rd.tolerance_study(model, geom, w, TOLS, 40, seed=1)
    out = plot_peak_histogram(st, "B", reference={"file's deviations": 1.0})
    styles = {(out[k].get_color(), out[k].get_linestyle()) for k in ("p50", "p95", "p99")}
    assert len(styles) == 3
    assert out["file's deviations"].get_xdata()[0] == 1.0
    pyplot().close("all")
    rc = main(["reactions", str(EXAMPLE), "--out", str(tmp_path / "o"), "--no-plots",
               "--tolerance-study", "20"])
    text = capsys.readouterr().out
    assert rc == 0 and "file's deviations" in text


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
