"""Exact kinematics of the swash-plate drive against an independent 3-D construction, finite
differences and invariants; characteristics, schemes, kinetostatics (paper 003)."""

import math

import numpy as np
import pytest
from _strategies import reals
from _swashplate_reference import (
    disk_point,
    ref_delta,
    ref_s,
    ref_stroke,
    ref_z,
    slide_point,
)
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from linkwork.errors import AssemblyError, ParameterError
from linkwork.models import swashplate as sw

DEG = math.pi / 180
DESIGNS = {
    "1": (0.10, 0.09, 0.20, 20 * DEG, 0.02, -0.01),
    "1b": (0.12, 0.14, 0.25, 30 * DEG, -0.03, 0.02),
    "4a": (0.10, 0.10 / math.cos(15 * DEG), 0.20, 15 * DEG, 0.0, 0.0),
    "4b": (0.10, 0.11, 0.22, 25 * DEG, 0.0, 0.015),
    "2": (0.10, 0.03, 0.25, 90 * DEG, 0.0, 0.02),
    "3": (0.10, 0.07, 0.20, 0.0, 0.03, 0.02),
}
PHI = np.radians([0.0, 17.0, 45.0, 90.0, 133.0, 180.0, 222.0, 270.0, 301.0, 359.0])


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_position_and_pressure_angle_match_3d_construction(name):
    """Reference: the 3-D construction of tests/_swashplate_reference.py (rotation matrices +
    brentq). Tolerance: atol=1e-12, atol=1e-7."""
    p = DESIGNS[name]
    s = sw.position(PHI, *p)
    d = sw.pressure_angle(PHI, *p)
    s_ref = np.array([ref_s(x, *p) for x in PHI])
    d_ref = np.array([ref_delta(x, *p) for x in PHI])
    np.testing.assert_allclose(s, s_ref, atol=1e-12)
    np.testing.assert_allclose(d, d_ref, atol=1e-7)  # acos near 0 loses digits in the ref
    assert s[0] == 0.0


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_transfer_functions_match_finite_differences_of_3d_construction(name):
    """Reference: the 3-D construction of tests/_swashplate_reference.py (rotation matrices +
    brentq); central finite differences. Tolerance: atol=1e-9, atol=2e-6."""
    p = DESIGNS[name]
    h = 1e-4
    fd1 = np.array([(ref_s(x + h, *p) - ref_s(x - h, *p)) / (2 * h) for x in PHI])
    fd2 = np.array([(ref_s(x + h, *p) - 2 * ref_s(x, *p) + ref_s(x - h, *p)) / h**2
                    for x in PHI])
    np.testing.assert_allclose(sw.first_transfer(PHI, *p), fd1, atol=1e-9)
    np.testing.assert_allclose(sw.second_transfer(PHI, *p), fd2, atol=2e-6)


def test_points_satisfy_rod_length_and_match_reference():
    """Reference: the 3-D construction of tests/_swashplate_reference.py (rotation matrices +
    brentq). Tolerance: rtol=1e-13, atol=1e-12."""
    p = DESIGNS["1"]
    A, B = sw.points(PHI, *p)
    np.testing.assert_allclose(np.linalg.norm(A - B, axis=-1), p[2], rtol=1e-13)
    for i, x in enumerate(PHI):
        Bref = disk_point(x, *p)
        Aref = slide_point(x, p[0], ref_z(x, *p))
        # same points up to the common axial shift of the datum
        np.testing.assert_allclose(A[i] - B[i], Aref - Bref, atol=1e-12)


@given(R=st.floats(0.05, 0.3), rr=st.floats(0.3, 1.6), ll=st.floats(2.0, 4.0),
       alpha=reals(0.0, math.pi / 2), aa=reals(-0.3, 0.3), bb=reals(-0.3, 0.3),
       phi=reals(0.0, 2 * math.pi))
@settings(max_examples=60, deadline=None)
def test_property_derivatives_consistent(R, rr, ll, alpha, aa, bb, phi):
    p = (R, rr * R, ll * R, alpha, aa * R, bb * R)
    h = 1e-5
    s = lambda x: float(sw.position(x, *p))  # noqa: E731
    s1 = lambda x: float(sw.first_transfer(x, *p))  # noqa: E731
    assert abs(sw.first_transfer(phi, *p) - (s(phi + h) - s(phi - h)) / (2 * h)) < 1e-7 * R
    assert abs(sw.second_transfer(phi, *p) - (s1(phi + h) - s1(phi - h)) / (2 * h)) < 1e-6 * R
    assert abs(sw.position(phi, *p) - ref_s(phi, *p)) < 1e-11


def test_broadcasting_designs_against_angles():
    Rs = np.array([0.1, 0.12, 0.15])[:, None]
    s = sw.position(PHI, Rs, 0.1, 0.25, 20 * DEG, 0.01, 0.0)
    assert s.shape == (3, PHI.size)
    for i in range(3):
        np.testing.assert_allclose(s[i], sw.position(PHI, float(Rs[i, 0]), 0.1, 0.25,
                                                     20 * DEG, 0.01, 0.0))


def test_finite_and_exact_where_pressure_angle_is_zero():
    # scheme 4a: delta_z = 0 at phi = 0 and pi, where the paper's Eq. (10) is 0/0
    R, al, l = 0.1, 20 * DEG, 0.2
    r = R / math.cos(al)
    phi = np.array([0.0, math.pi])
    assert np.all(np.abs(sw.pressure_angle(phi, R, r, l, al)) < 1e-15)
    v = sw.first_transfer(phi, R, r, l, al)
    acc = sw.second_transfer(phi, R, r, l, al)
    assert np.all(np.isfinite(v)) and np.all(np.abs(v) < 1e-15)
    # d2s/dphi2 at phi=0 from the reference by finite differences
    h = 1e-4
    p = (R, r, l, al, 0.0, 0.0)
    fd = (ref_s(h, *p) - 2 * ref_s(0.0, *p) + ref_s(-h, *p)) / h**2
    assert abs(acc[0] - fd) < 1e-6


def test_rod_cannot_reach_raises_with_angle_ranges():
    with pytest.raises(AssemblyError, match=r"sin\(delta_z\)") as ei:
        sw.position(np.linspace(0, 2 * math.pi, 73), 0.1, 0.05, 0.04, 20 * DEG, 0.0, 0.0)
    assert ei.value.ranges
    out = sw.position(np.linspace(0, 2 * math.pi, 73), 0.1, 0.05, 0.06, 20 * DEG, 0.0, 0.06,
                      on_failure="nan")
    assert np.isnan(out).all()


@pytest.mark.parametrize("kw, name", [({"l": -1.0}, "l"), ({"alpha": 2.0}, "alpha"),
                                      ({"R": 0.0}, "R"), ({"a": math.nan}, "a")])
def test_bad_parameters_name_themselves(kw, name):
    p = {"R": 0.1, "r": 0.1, "l": 0.2, "alpha": 0.3, "a": 0.0, "b": 0.0} | kw
    with pytest.raises(ParameterError, match=f"^{name} = "):
        sw.position(0.3, **p)


@pytest.mark.parametrize("name", ["1", "1b", "3"])
def test_stroke_from_true_extremes_where_s_pi_minus_s_0_is_wrong(name):
    p = DESIGNS[name]
    H_ref, (smax, smin) = ref_stroke(*p)
    H = sw.stroke(*p)
    naive = ref_s(math.pi, *p) - ref_s(0.0, *p)
    assert abs(H - H_ref) < 1e-10
    assert abs(naive - H_ref) > 1e-5  # the naive stroke is wrong here
    e = sw.extremes(*p)
    assert abs(e["s_max"] - smax) < 1e-10 and abs(e["s_min"] - smin) < 1e-10
    assert abs(ref_s(float(e["phi_max"]), *p) - smax) < 1e-10


def test_stroke_non_unimodal_large_offset():
    # large offsets make two maxima per revolution (found by a scan; checked on the reference)
    p = (0.1, 0.07715, 0.1602, math.radians(61.36), -0.01566, -0.0766)
    assert not sw.unimodal(*p)
    ph = np.linspace(0, 2 * math.pi, 2001)[:-1]
    s = np.array([ref_s(x, *p) for x in ph])
    assert np.sum((s > np.roll(s, 1)) & (s > np.roll(s, -1))) == 2
    H_ref, _ = ref_stroke(*p, n=2001)
    assert abs(sw.stroke(*p) - H_ref) < 1e-10
    assert abs(ref_s(math.pi, *p) - H_ref) > 1e-4


def test_stroke_vectorised_matches_scalar():
    al = np.radians([5.0, 10.0, 20.0, 30.0])
    H = sw.stroke(0.1, 0.1 / np.cos(al), 0.2, al)
    np.testing.assert_allclose(H, 2 * 0.1 * np.tan(al), rtol=1e-12)  # 4a: H = 2 R tan(alpha)
    H2 = sw.stroke(0.1, 0.09, 0.2, al[:, None], np.array([0.0, 0.02]), 0.01)
    assert H2.shape == (4, 2)
    assert abs(H2[2, 1] - ref_stroke(0.1, 0.09, 0.2, al[2], 0.02, 0.01)[0]) < 1e-10


def test_characteristics_against_reference_scan():
    """Reference: the 3-D construction of tests/_swashplate_reference.py (rotation matrices +
    brentq). Tolerance: < 1e-12, < 1e-5, < 1e-15, < 1e-7, < 2e-3, < 1e-6."""
    p = DESIGNS["1b"]
    c = sw.characteristics(*p)
    ph = np.linspace(0, 2 * math.pi, 3601)
    s = np.array([ref_s(x, *p) for x in ph])
    kmin, kmax = int(np.argmin(s)), int(np.argmax(s))
    assert abs(c.phi_min - ph[kmin]) < 2e-3 and abs(c.phi_max - ph[kmax]) < 2e-3
    assert abs(c.phi_f + c.phi_r - 2 * math.pi) < 1e-12
    # pressure angle on the forward stroke (from the exact phi_min to phi_max) and the return
    t = np.linspace(0.0, 1.0, 2001)
    pf = float(c.phi_min) + float(c.phi_f) * t
    pr = float(c.phi_max) + float(c.phi_r) * t
    d_f = max(ref_delta(x, *p) for x in pf)
    d_r = max(ref_delta(x, *p) for x in pr)
    assert abs(c.delta_f - d_f) < 1e-6 and abs(c.delta_r - d_r) < 1e-6
    assert c.delta_f >= d_f - 1e-9 and c.delta_r >= d_r - 1e-9
    fd = np.gradient(s, ph)
    assert abs(c.Pi_v_max - np.abs(fd).max()) < 1e-5
    assert abs(c.L - (2 * p[1] * math.sin(p[3]) + p[2])) < 1e-15
    # exact axial extent from the 3-D points: highest A minus lowest disk point
    zA = np.array([ref_z(x, *p) for x in ph])
    zB = np.array([disk_point(x, *p)[2] for x in ph])
    assert abs(c.L_exact - (zA.max() - zB.min())) < 1e-7
    assert c.L_exact <= c.L
    assert bool(c.unimodal)


def test_schemes_with_a_zero_are_symmetric_about_pi():
    for name in ("4a", "4b", "2"):
        p = DESIGNS[name]
        np.testing.assert_allclose(sw.position(PHI, *p), sw.position(2 * math.pi - PHI, *p),
                                   atol=1e-15)
        c = sw.characteristics(*p)
        assert abs(c.phi_f - math.pi) < 1e-9 and abs(c.delta_f - c.delta_r) < 1e-12


def test_scheme_constructors_fix_what_the_scheme_fixes():
    d1 = sw.scheme_1(0.1, 0.09, 0.2, 0.3, 0.01, 0.02)
    assert d1.free == {"r": 0.09, "l": 0.2, "alpha": 0.3, "a": 0.01, "b": 0.02}
    d2 = sw.scheme_2(0.1, 0.03, 0.25, b=0.02)
    assert d2.alpha == math.pi / 2 and d2.a == 0.0 and set(d2.free) == {"r", "l", "b"}
    d3 = sw.scheme_3(0.1, 0.07, 0.2, a=0.03, b=0.02)
    assert d3.alpha == 0.0 and set(d3.free) == {"r", "l", "a", "b"}
    with pytest.raises(ParameterError, match="scheme 3"):
        sw.scheme_3(0.1, 0.07, 0.2)
    d4a = sw.scheme_4a(0.1, 0.2, 15 * DEG)
    assert d4a.a == d4a.b == 0.0 and abs(d4a.r * math.cos(d4a.alpha) - d4a.R) < 1e-15
    assert set(d4a.free) == {"l", "alpha"}
    with pytest.raises(ParameterError, match="alpha"):
        sw.scheme_4a(0.1, 0.2, 0.0)
    d4b = sw.scheme_4b(0.1, 0.11, 0.22, 25 * DEG, 0.015)
    assert d4b.a == 0.0 and set(d4b.free) == {"r", "l", "alpha", "b"}
    with pytest.raises(ParameterError, match="b = 0"):
        sw.scheme_4b(0.1, 0.11, 0.22, 25 * DEG, 0.0)
    with pytest.raises(ParameterError, match="scheme"):
        sw.Design(0.1, 0.1, 0.2, 0.3, scheme="5")
    # each scheme evaluates like the general functions with its fixed values
    for d in (d2, d3, d4a, d4b):
        assert d.stroke() == pytest.approx(ref_stroke(*d.params)[0], abs=1e-10)


def test_scheme_4a_closed_forms():
    # scheme 4a: delta_z max = asin(R (1/cos a - 1) / l) at phi = 90 deg, H = 2 R tan(alpha)
    R, l, al = 0.1, 0.2, 25 * DEG
    c = sw.scheme_4a(R, l, al).characteristics()
    assert abs(c.delta_f - math.asin(R * (1 / math.cos(al) - 1) / l)) < 1e-12
    assert abs(c.H - 2 * R * math.tan(al)) < 1e-12


def test_relative_units_homogeneous():
    p = DESIGNS["1"]
    rel = sw.relative(p[0], r=p[1], l=p[2], a=p[4], b=p[5])
    s_rel = sw.position(PHI, 1.0, rel["r"], rel["l"], p[3], rel["a"], rel["b"])
    np.testing.assert_allclose(s_rel * p[0], sw.position(PHI, *p), atol=1e-15)


def test_harmonic_error_small_for_long_rods_and_shrinks_like_l_cubed():
    p = list(DESIGNS["1"])
    e1 = sw.harmonic_error(*p)
    p[2] *= 2
    e2 = sw.harmonic_error(*p)
    assert e1["max"] < 1e-3 * p[0]
    assert 5.0 < e1["max"] / e2["max"] < 11.0  # O(l^-3)
    assert e1["rms"] < e1["max"]


def test_slide_speed_and_velocity_limit():
    p = DESIGNS["1"]
    c = sw.characteristics(*p)
    n_rpm = 30.0
    v = sw.max_slide_speed(*p, omega=n_rpm * math.pi / 30)
    assert abs(v - c.Pi_v_max * math.pi) < 1e-15
    # Eq. (3): u = 10 slides, 300 pieces/min -> n = 30 rpm; the limit equals v / omega
    lim = sw.allowed_first_transfer(v, 300 / 60, 10)
    assert abs(lim - c.Pi_v_max) < 1e-12


def test_analyze_result_exports(tmp_path):
    d = sw.scheme_4b(*[DESIGNS["4b"][i] for i in (0, 1, 2, 3, 5)])
    res = sw.analyze(d, omega=2.0, n=73)
    assert res.s.shape == (73,) and res.v[10] == 2.0 * res.Pi_v[10]
    data = res.to_dict()
    assert data["design.scheme"] == "4b" and "characteristics.H" in data
    res.to_csv(tmp_path / "x.csv")
    assert (tmp_path / "x.csv").read_text().startswith("phi [rad]")


# ----------------------------------------------------------------------------- kinetostatics

def test_drive_forces_power_balance_without_friction():
    d = sw.Design(*DESIGNS["1b"])
    load = (np.radians([0, 90, 180, 270, 360]), np.array([100.0, 800.0, 300.0, -50.0, 100.0]))
    f = sw.drive_forces(d, load, u=1)
    Pi_v = d.first_transfer(f.phi)
    np.testing.assert_allclose(f.M, f.F * Pi_v, atol=1e-9)  # M omega = F v
    np.testing.assert_allclose(f.S * np.cos(d.pressure_angle(f.phi)), f.F, rtol=1e-12)


def test_drive_forces_torque_by_virtual_work_on_3d_reference():
    # independent: the torque on the disk alone = - dW/dphi of the rod force moving B, and
    """Reference: the 3-D construction of tests/_swashplate_reference.py (rotation matrices +
    brentq); central finite differences. Tolerance: < 1e-8."""
    # the rotor torque likewise, from the 3-D reference points by finite differences
    p = DESIGNS["1"]
    d = sw.Design(*p)
    F = 500.0
    f = sw.drive_forces(d, F, phi=np.array([0.7, 2.5, 4.4]))
    h = 1e-6
    for i, x in enumerate(f.phi):
        B = disk_point(x, *p)
        A = slide_point(x, p[0], ref_z(x, *p))
        e = (A - B) / np.linalg.norm(A - B)
        S = F / e[2]
        dB = (disk_point(x + h, *p) - disk_point(x - h, *p)) / (2 * h)
        # power the disk delivers to the rod: force on the disk is -S e, disk needs M = S e.dB
        assert abs(f.M_disk[i] - S * e @ dB) < 1e-8
        # the rotor carries the guide: the slide is pushed by S e; the rotor moves the slide
        # tangentially (dA at fixed z), the guide reaction does work -S e_h . dA_h
        dA = (slide_point(x + h, p[0], 0.0) - slide_point(x - h, p[0], 0.0)) / (2 * h)
        assert abs(f.M_rotor[i] - (-S * (e[0] * dA[0] + e[1] * dA[1]))) < 1e-8


def test_drive_forces_friction_efficiency_and_u_slides():
    d = sw.scheme_4a(0.1, 0.2, 20 * DEG)

    def load(phi):  # working force on the forward stroke only
        return np.where(np.mod(phi, 2 * math.pi) < math.pi, 1000.0, 0.0)

    f0 = sw.drive_forces(d, load, u=6)
    f1 = sw.drive_forces(d, load, u=6, rho_guide=6 * DEG)
    assert abs(f0.efficiency - 1.0) < 1e-3
    assert 0.8 < f1.efficiency < 1.0
    assert f1.work_input > f0.work_input
    # 6 slides, phase-shifted: total torque is the sum of the shifted single-slide torques
    single = sw.drive_forces(d, load, u=1, phi=f0.phi + 2 * math.pi / 6)
    one = sw.drive_forces(d, load, u=1)
    assert np.all(f0.M_total >= one.M - 1e-9)
    assert abs(f0.work_useful - 6 * one.work_useful) < 1e-6 * abs(f0.work_useful)
    assert np.isfinite(single.M).all()


def test_drive_forces_jams():
    d = sw.Design(0.1, 0.2, 0.12, 30 * DEG)
    with pytest.raises(AssemblyError, match="jams"):
        sw.drive_forces(d, 100.0, rho_guide=60 * DEG)


def test_characteristics_batch_equals_one_by_one():
    # regression: a root hit exactly in one design must not disturb the others' refinement
    rng = np.random.default_rng(3)
    n = 40
    p = (0.1, rng.uniform(0.06, 0.15, n), rng.uniform(0.25, 0.4, n), rng.uniform(0.05, 0.7, n),
         rng.uniform(-0.03, 0.03, n), rng.uniform(-0.03, 0.03, n))
    c = sw.characteristics(*p)
    for i in range(n):
        ci = sw.characteristics(0.1, *(x[i] for x in p[1:]))
        for key in ("H", "phi_min", "phi_max", "delta_f", "delta_r", "Pi_v_max"):
            assert abs(getattr(c, key)[i] - getattr(ci, key)) < 1e-11, (key, i)


@given(R=st.floats(0.05, 0.3), rr=st.floats(0.5, 1.5), ll=st.floats(2.5, 4.0),
       alpha=st.floats(0.02, 1.2), aa=reals(-0.2, 0.2), bb=reals(-0.2, 0.2),
       u=st.integers(1, 8), F0=reals(-5e3, 5e3))
@settings(max_examples=40, deadline=None)
def test_property_drive_power_balance(R, rr, ll, alpha, aa, bb, u, F0):
    d = sw.Design(R, rr * R, ll * R, alpha, aa * R, bb * R)
    f = sw.drive_forces(d, lambda ph: F0 * (1.0 + 0.5 * np.sin(ph)), u=u, n=91)
    ph = f.phi
    total = sum((F0 * (1 + 0.5 * np.sin(ph + 2 * math.pi * k / u)))
                * d.first_transfer(ph + 2 * math.pi * k / u) for k in range(u))
    np.testing.assert_allclose(f.M_total, total, atol=1e-9 * max(1.0, abs(F0)) * R)


def test_drive_forces_two_point_guide_by_slide_equilibrium():
    # independent: the slide's planar equilibrium (rod plane) with two guide contacts at the
    # ends of the guided length b, rod joint A at overhang e below the nearer one; unknowns
    # S, N1, N2 (normal reactions, signs from the lateral push), friction mu*|N| against the
    # motion; solved as a linear system per position and compared with drive_forces
    d = sw.Design(0.1, 0.09, 0.2, 20 * DEG, 0.02, -0.01)
    b_g, e, rho = 0.08, 0.03, 8 * DEG
    mu = math.tan(rho)
    phi = np.radians([30.0, 100.0, 150.0, 250.0])
    F = 1000.0
    f = sw.drive_forces(d, F, rho_guide=rho, guide_length=b_g, overhang=e, phi=phi)
    delta = d.pressure_angle(phi)
    v = d.first_transfer(phi)
    for i in range(phi.size):
        sd, cd = math.sin(delta[i]), math.cos(delta[i])
        sv = math.copysign(1.0, F * v[i])
        # lateral push S sd at A (x = 0 along the axis); contacts at z = e and z = e + b;
        # near contact pushes back N1, far contact pulls the other way N2 (tilting couple)
        # lateral:  S sd - N1 + N2 = 0 ; moment about A: -N1 e + N2 (e + b) = 0
        # axial:    S cd - F - sv mu (N1 + N2) = 0
        A = np.array([[sd, -1.0, 1.0], [0.0, -e, e + b_g], [cd, -sv * mu, -sv * mu]])
        S, N1, N2 = np.linalg.solve(A, [0.0, 0.0, F])
        assert N1 > 0 and N2 > 0
        assert abs(f.S[i] - S) < 1e-9 * abs(S)
    with pytest.raises(ParameterError, match="overhang"):
        sw.drive_forces(d, F, overhang=0.01)


def test_reference_rod_length_and_datum():
    """Reference: the 3-D construction of tests/_swashplate_reference.py (rotation matrices +
    brentq). Tolerance: < 1e-12."""
    p = (0.1, 0.09, 0.2, math.radians(20), 0.02, -0.01)
    for phi in (0.3, 2.0, 4.0):
        B = disk_point(phi, *p)
        A = slide_point(phi, p[0], ref_z(phi, *p))
        assert abs(np.linalg.norm(A - B) - p[2]) < 1e-12
        assert A[2] > B[2]
    assert ref_s(0.0, *p) == 0.0


def _sw_z(phi: float, R: float, r: float, l: float, alpha: float, a: float, b: float) -> float:
    ca, sa = math.cos(alpha), math.sin(alpha)
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    rz = np.array([[math.cos(phi), -math.sin(phi), 0], [math.sin(phi), math.cos(phi), 0],
                   [0, 0, 1]])
    B = np.array([a, b, 0.0]) + rx @ rz @ np.array([0.0, -r, 0.0])
    Axy = np.array([R * math.sin(phi), -R * math.cos(phi)])
    return brentq(lambda z: float(np.sum((np.r_[Axy, z] - B) ** 2) - l * l), B[2], B[2] + l,
                  xtol=1e-15, rtol=1e-15)


SW_REVIEW = [  # R, r, l, alpha, a, b (scheme 1 with both offsets, 4b, 2)
    (0.12, 0.093, 0.31, math.radians(27.0), -0.017, 0.023),
    (0.08, 0.1, 0.17, math.radians(11.0), 0.0, -0.012),
    (0.1, 0.045, 0.4, math.pi / 2, 0.0, 0.03),
]


@pytest.mark.parametrize("p", SW_REVIEW)
def test_swashplate_against_own_construction(p):
    """Reference: central finite differences. Tolerance: rtol=1e-10, atol=1e-13, rtol=1e-7,
    atol=1e-11, rtol=1e-5, atol=1e-9, rel=1e-6."""
    phis = np.array([0.4, 1.9, 2.8, 4.1, 5.95])
    z0 = _sw_z(0.0, *p)
    s_ref = np.array([_sw_z(x, *p) - z0 for x in phis])
    np.testing.assert_allclose(sw.position(phis, *p), s_ref, rtol=1e-10, atol=1e-13)
    h = 1e-4
    d1 = np.array([(_sw_z(x - 2 * h, *p) - 8 * _sw_z(x - h, *p) + 8 * _sw_z(x + h, *p)
                    - _sw_z(x + 2 * h, *p)) / (12 * h) for x in phis])
    np.testing.assert_allclose(sw.first_transfer(phis, *p), d1, rtol=1e-7, atol=1e-11)
    h = 1e-3
    d2 = np.array([(-_sw_z(x - 2 * h, *p) + 16 * _sw_z(x - h, *p) - 30 * _sw_z(x, *p)
                    + 16 * _sw_z(x + h, *p) - _sw_z(x + 2 * h, *p)) / (12 * h * h)
                   for x in phis])
    np.testing.assert_allclose(sw.second_transfer(phis, *p), d2, rtol=1e-5, atol=1e-9)
    grid = np.linspace(0, 2 * math.pi, 4001)
    zs = np.array([_sw_z(x, *p) for x in grid])
    assert float(sw.stroke(*p)) == pytest.approx(np.ptp(zs), rel=1e-6)


def test_drive_forces_jamming_with_several_slides_names_the_angles():
    # the two-point guide with rho = 60 deg jams where tan(delta_z) >= 1 / (k tan rho); with
    # u > 1 slides the error used to crash in angle_ranges (a (u, n) array of angles).
    d = sw.scheme_1(0.1, 0.07, 0.25, math.radians(20.0), 0.02, 0.0)
    with pytest.raises(AssemblyError, match="jams") as exc:
        sw.drive_forces(d, 1000.0, u=12, rho_guide=math.radians(80.0), guide_length=0.12,
                        overhang=0.04, n=361)
    # the jam ranges are angles of a slide over one revolution, in [0, 360] deg
    for lo, hi in exc.value.ranges:
        assert 0.0 <= lo <= hi <= 2 * math.pi + 1e-12


def test_swashplate_shape_mismatch_and_sample_count_are_named():
    with pytest.raises(ParameterError, match="shapes"):  # was numpy's raw broadcast ValueError
        sw.position(np.zeros(3), 0.1, np.full(4, 0.07), 0.25, 0.3)
    with pytest.raises(ParameterError, match="shapes"):
        sw.stroke(0.1, np.full(4, 0.07), np.full(3, 0.25), 0.3)
    d = sw.scheme_1(0.1, 0.07, 0.25, 0.35, 0.02, 0.0)
    with pytest.raises(ParameterError, match="n = 0"):  # was an IndexError
        sw.drive_forces(d, 1000.0, n=0)
    with pytest.raises(ParameterError, match="phi"):  # one angle: the cycle integrals are 0/0
        sw.drive_forces(d, 1000.0, phi=[0.3])
    # designs (m, 1) against angles (n,) still broadcast
    s = sw.position(np.linspace(0, 6, 5), 0.1, np.array([[0.07], [0.09]]), 0.25, 0.3)
    assert s.shape == (2, 5)


def test_eta_inst_is_undefined_exactly_where_the_slide_carries_no_load():
    """Reference: eta = useful power / input power from its definition on the 3-D construction
    of tests/_swashplate_reference.py: the rod force S from the slide's axial equilibrium with
    guide friction (S (e_z - sgn(F v) mu |e_h|) = F), the input torque from the power the disk
    and the rotor deliver (central differences of the disk point B and the slide's circle), the
    useful power F ds/dphi (central differences of the 3-D position). Tolerance: 1e-6. Where
    the load is zero the efficiency is 0/0: NaN in the result, an empty CSV cell and JSON
    null."""
    p = DESIGNS["1"]
    d = sw.Design(*p)
    rho = 5 * DEG
    mu = math.tan(rho)
    # load diagram: zero over [0, 90] deg and [270, 360] deg, a drawing force between
    load = (np.radians([0.0, 90.0, 120.0, 240.0, 270.0, 360.0]),
            np.array([0.0, 0.0, 800.0, 800.0, 0.0, 0.0]))
    phi = np.radians([10.0, 60.0, 100.0, 150.0, 200.0, 260.0, 300.0, 350.0])
    f = sw.drive_forces(d, load, rho_guide=rho, phi=phi)
    h = 1e-6
    for i, x in enumerate(phi):
        F = float(np.interp(x, *load))
        ds = (ref_s(x + h, *p) - ref_s(x - h, *p)) / (2 * h)
        if F == 0.0:
            assert math.isnan(f.eta_inst[i]), (np.degrees(x), f.eta_inst[i])
            continue
        B = disk_point(x, *p)
        A = slide_point(x, p[0], ref_z(x, *p))
        e = (A - B) / np.linalg.norm(A - B)
        S = F / (e[2] - math.copysign(1.0, F * ds) * mu * math.hypot(e[0], e[1]))
        dB = (disk_point(x + h, *p) - disk_point(x - h, *p)) / (2 * h)
        dA = (slide_point(x + h, p[0], 0.0) - slide_point(x - h, p[0], 0.0)) / (2 * h)
        M_in = S * e @ dB - S * (e[0] * dA[0] + e[1] * dA[1])
        eta = F * ds / M_in
        assert abs(f.eta_inst[i] - eta) < 1e-6, (np.degrees(x), f.eta_inst[i], eta)
        # friction takes a part of the power where the rod drives the slide (F v > 0)
        assert (eta < 1.0) == (F * ds > 0)
    assert np.isnan(f.eta_inst).sum() == 4


def test_zero_load_efficiency_is_undefined_and_written_as_empty_and_null(tmp_path):
    import csv
    import json

    d = sw.scheme_4a(0.1, 0.2, 15 * DEG)
    f = sw.drive_forces(d, 0.0, u=3, rho_guide=5 * DEG, n=37)
    assert np.isnan(f.eta_inst).all() and math.isnan(f.efficiency)
    assert f.work_useful == 0.0 and f.work_input == 0.0
    with f.to_csv(tmp_path / "forces.csv").open(newline="") as fh:
        rows = list(csv.reader(fh))
    k = rows[0].index("eta_inst []")
    assert all(r[k] == "" for r in rows[1:]) and len(rows) == 38

    def refuse(name):
        raise ValueError(name)
    data = json.loads(f.to_json(tmp_path / "forces.json").read_text(), parse_constant=refuse)
    assert data["efficiency"] is None and data["columns"]["eta_inst"] == [None] * 37
