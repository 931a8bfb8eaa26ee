"""The swash-plate model (``linkwork.models.swashplate``) against the independent 3-D construction
of ``tests/_swashplate_construction.py`` and finite differences: positions, pressure angle,
transfer functions, strokes, harmonic form, characteristics, schemes, kinetostatics and its
failures.  Tolerances are stated per test (construction solved to ~1e-12, finite differences to
~1e-7 relative)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from _strategies import reals
from _swashplate_construction import fd1, ref_delta, ref_extremes, ref_max_on, ref_points, ref_s
from hypothesis import assume, given, settings

from linkwork.errors import AssemblyError, ParameterError
from linkwork.models import swashplate as sw

DEG = math.pi / 180


def eq5_printed(phi, R, r, l, alpha, a=0.0, b=0.0):
    """The paper's Eq. (5) as printed, solved for delta_z."""
    s2 = (((R - r) * math.sin(phi) - a) / l) ** 2 + \
        (((r * math.cos(alpha) - R) * math.cos(phi) - b) / l) ** 2
    return math.asin(math.sqrt(s2))


def fd2(f, x, h=1e-2):
    """Fourth-order central second difference of f at x."""
    return (-f(x + 2 * h) + 16 * f(x + h) - 30 * f(x) + 16 * f(x - h) - f(x - 2 * h)) / (12 * h * h)


# designs (R, r, l, alpha, a, b) [m, rad]
S1_A = (0.1, 0.11, 0.15, 20 * DEG, 0.01, 0.02)


S1_B = (0.1, 0.09, 0.15, 20 * DEG, -0.03, -0.015)


S1_C = (0.1, 0.12, 0.18, 35 * DEG, 0.025, 0.005)


S4A_A = sw.scheme_4a(0.1, 0.15, 20 * DEG).params


S4A_B = sw.scheme_4a(0.1, 0.2, 30 * DEG).params


S4B_A = sw.scheme_4b(0.1, 0.11, 0.15, 20 * DEG, 0.02).params


S4B_B = sw.scheme_4b(0.1, 0.095, 0.15, 20 * DEG, -0.025).params


S2 = sw.scheme_2(0.1, 0.03, 0.25, 0.02).params


S3 = sw.scheme_3(0.1, 0.09, 0.2, 0.02, 0.03).params


#: a = 0 but two maxima per revolution: s(pi) - s(0) is wrong here too
NONUNI = (0.1, 0.05, 0.15, 20 * DEG, 0.0, -0.045)


DESIGNS = {"1a": S1_A, "1b": S1_B, "1c": S1_C, "4a_a": S4A_A, "4a_b": S4A_B, "4b_a": S4B_A,
           "4b_b": S4B_B, "2": S2, "3": S3}


PHIS = [0.0, 0.3, 1.0, math.pi / 2, 2.0, 3.0, math.pi, 3.5, 4.5, 5.5, 6.2, -0.7, 7.5]


@pytest.mark.parametrize("name", list(DESIGNS))
def test_position_and_pressure_angle_against_3d_construction(name):
    """Reference: the 3-D construction of tests/_swashplate_construction.py. Tolerance:
    rtol=1e-9, atol=1e-9 * scale, atol=1e-12."""
    p = DESIGNS[name]
    ph = np.array(PHIS)
    s = sw.position(ph, *p)
    d = sw.pressure_angle(ph, *p)
    s_ref = np.array([ref_s(x, *p) for x in ph])
    d_ref = np.array([ref_delta(x, *p) for x in ph])
    d_eq5 = np.array([eq5_printed(x, *p) for x in ph])
    scale = np.max(np.abs(s_ref))
    np.testing.assert_allclose(s, s_ref, rtol=1e-9, atol=1e-9 * scale)
    np.testing.assert_allclose(d, d_ref, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(d, d_eq5, rtol=1e-9, atol=1e-12)
    assert sw.position(0.0, *p) == 0.0
    assert np.all(d >= 0)


@pytest.mark.parametrize("name", list(DESIGNS))
def test_transfer_functions_against_finite_differences(name):
    """Reference: the 3-D construction of tests/_swashplate_construction.py; central finite
    differences. Tolerance: rtol=1e-7, atol=1e-9 * np.max(np.abs(pv_ref)), rtol=1e-6,
    atol=1e-8 * np.max(np.abs(pa_ref))."""
    p = DESIGNS[name]
    ph = np.array(PHIS)
    pv = sw.first_transfer(ph, *p)
    pa = sw.second_transfer(ph, *p)
    pv_ref = np.array([fd1(lambda x: ref_s(x, *p), t) for t in ph])
    pa_ref = np.array([fd2(lambda x: ref_s(x, *p), t) for t in ph])
    np.testing.assert_allclose(pv, pv_ref, rtol=1e-7, atol=1e-9 * np.max(np.abs(pv_ref)))
    np.testing.assert_allclose(pa, pa_ref, rtol=1e-6, atol=1e-8 * np.max(np.abs(pa_ref)))


@settings(max_examples=20, deadline=None)
@given(r=reals(0.04, 0.16), l=reals(0.08, 0.5), alpha=reals(0.0, math.pi / 2),
       a=reals(-0.05, 0.05), b=reals(-0.05, 0.05), phi=reals(-7.0, 7.0))
def test_property_random_designs_against_3d_construction(r, l, alpha, a, b, phi):
    """Reference: the 3-D construction of tests/_swashplate_construction.py; central finite
    differences. Tolerance: abs=1e-12 * p[0], abs=1e-12, abs=1e-9 * l, rel=1e-9."""
    p = (0.1, r, l, alpha, a, b)
    # keep the rod clear of 90 deg to the axis everywhere (horizontal reach < 0.95 l)
    reach = max(math.hypot((0.1 - r) * math.sin(t) - a, (r * math.cos(alpha) - 0.1)
                           * math.cos(t) - b) for t in np.linspace(0, 2 * math.pi, 361))
    assume(reach < 0.95 * l)
    assert float(sw.position(phi, *p)) == pytest.approx(ref_s(phi, *p), abs=1e-12 * p[0])
    assert float(sw.pressure_angle(phi, *p)) == pytest.approx(ref_delta(phi, *p), abs=1e-12)
    pv_ref = fd1(lambda x: ref_s(x, *p), phi)
    assert float(sw.first_transfer(phi, *p)) == pytest.approx(pv_ref, abs=1e-9 * l)
    _, smin, _, smax = ref_extremes(p, n=240)
    assert float(sw.stroke(*p)) == pytest.approx(smax - smin, rel=1e-9, abs=1e-12 * p[0])


def test_broadcasting_designs_by_angles():
    ph = np.array(PHIS)
    P = np.array([S1_A, S4A_A, S4B_A])  # (3, 6)
    cols = [P[:, j:j + 1] for j in range(6)]
    s = sw.position(ph, *cols)
    assert s.shape == (3, len(PHIS))
    for i, p in enumerate((S1_A, S4A_A, S4B_A)):
        np.testing.assert_allclose(s[i], [ref_s(x, *p) for x in ph], atol=1e-12)
    H = sw.stroke(*cols)
    assert H.shape == (3, 1)


def test_finite_and_exact_where_the_pressure_angle_is_zero():
    # scheme 4a: delta_z = 0 at phi = 0 and pi (the paper's Eq. (10) is 0/0 there)
    p = S4A_A
    for t in (0.0, math.pi):
        assert ref_delta(t, *p) < 1e-7
        assert sw.pressure_angle(t, *p) == pytest.approx(0.0, abs=1e-15)
        pv = float(sw.first_transfer(t, *p))
        pa = float(sw.second_transfer(t, *p))
        assert math.isfinite(pv) and math.isfinite(pa)
        assert pv == pytest.approx(fd1(lambda x: ref_s(x, *p), t), abs=1e-10)
        assert pa == pytest.approx(fd2(lambda x: ref_s(x, *p), t), rel=1e-6)


@pytest.mark.parametrize("name", ["1a", "1b", "1c", "4a_a", "4b_a", "3", "nonuni"])
def test_stroke_from_true_extremes(name):
    p = NONUNI if name == "nonuni" else DESIGNS[name]
    _xmin, smin, _xmax, smax = ref_extremes(p)
    H_ref = smax - smin
    H = float(sw.stroke(*p))
    assert H == pytest.approx(H_ref, rel=1e-9)
    e = sw.extremes(*p)
    assert float(e["s_max"]) == pytest.approx(smax, rel=1e-9, abs=1e-12)
    assert float(e["s_min"]) == pytest.approx(smin, rel=1e-9, abs=1e-12)
    # angles of the extremes: flat there, so compare through the positions they give
    assert ref_s(float(e["phi_max"]), *p) == pytest.approx(smax, abs=1e-12)
    assert ref_s(float(e["phi_min"]), *p) == pytest.approx(smin, abs=1e-12)
    naive = ref_s(math.pi, *p) - ref_s(0.0, *p)
    if name in ("1a", "1b", "1c", "3", "nonuni"):
        assert abs(naive - H_ref) > 1e-6  # here s(pi) - s(0) is wrong; the stroke is right
    if name == "nonuni":
        assert not bool(sw.unimodal(*p))


def ref_harmonic(phi, R, r, l, alpha, a=0.0, b=0.0):
    """cos(delta) ~ 1 - sin^2(delta)/2 applied to the 3-D construction (horizontal rod part)."""
    def q(t):
        A, B = ref_points(t, R, r, l, alpha, a, b)
        return (A[0] - B[0]) ** 2 + (A[1] - B[1]) ** 2
    return r * math.sin(alpha) * (1 - math.cos(phi)) + (q(0.0) - q(phi)) / (2 * l)


@pytest.mark.parametrize("name", ["1a", "4a_a", "4b_a", "2"])
def test_harmonic_form_and_its_error(name):
    p = DESIGNS[name]
    ph = np.linspace(0, 2 * math.pi, sw.GRID, endpoint=False)
    approx = sw.position_harmonic(ph, *p)
    ref_h = np.array([ref_harmonic(t, *p) for t in ph])
    np.testing.assert_allclose(approx, ref_h, atol=1e-14)
    # Pi_v of the harmonic form = derivative of the harmonic position
    pv_h = sw.first_transfer_harmonic(ph[:20], *p)
    np.testing.assert_allclose(pv_h, [fd1(lambda x: ref_harmonic(x, *p), t) for t in ph[:20]],
                               atol=1e-11)
    err = approx - np.array([ref_s(t, *p) for t in ph])
    e = sw.harmonic_error(*p)
    assert float(e["max"]) == pytest.approx(np.max(np.abs(err)), rel=1e-6)
    assert float(e["rms"]) == pytest.approx(np.sqrt(np.mean(err ** 2)), rel=1e-6)
    assert float(e["relative_max"]) == pytest.approx(np.max(np.abs(err)) / float(sw.stroke(*p)),
                                                     rel=1e-6)


def test_relative_units_helper():
    R, r, l, al, a, b = S1_A
    rel = sw.relative(R, r=r, l=l, a=a, b=b, H=0.06)
    assert float(rel["r"]) == pytest.approx(r / R) and float(rel["H"]) == pytest.approx(0.6)
    ph = np.array(PHIS)
    s_rel = sw.position(ph, 1.0, rel["r"], rel["l"], al, rel["a"], rel["b"])
    np.testing.assert_allclose(s_rel, [ref_s(t, *S1_A) / R for t in ph], atol=1e-11)
    d = sw.Design(*S1_A).relative()
    assert d["l"] == pytest.approx(l / R)


@pytest.mark.parametrize("name", ["1a", "1b", "1c", "4b_a"])
def test_characteristics_against_reference(name):
    """Reference: the 3-D construction of tests/_swashplate_construction.py; central finite
    differences. Tolerance: rel=1e-9, abs=1e-6, rel=1e-7, rel=1e-14."""
    p = DESIGNS[name]
    _R, r, l, al, _a, _b = p
    c = sw.characteristics(*p)
    xmin, smin, xmax, smax = ref_extremes(p)
    assert float(c.H) == pytest.approx(smax - smin, rel=1e-9)
    phi_f = (xmax - xmin) % (2 * math.pi)
    # the extremes are flat: their angles are known to ~sqrt(eps) only
    assert float(c.phi_f) == pytest.approx(phi_f, abs=1e-6)
    assert float(c.phi_r) == pytest.approx(2 * math.pi - phi_f, abs=1e-6)
    df = ref_max_on(lambda t: ref_delta(t, *p), xmin, xmin + phi_f)
    dr = ref_max_on(lambda t: ref_delta(t, *p), xmax, xmax + 2 * math.pi - phi_f)
    assert float(c.delta_f) == pytest.approx(df, rel=1e-7)
    assert float(c.delta_r) == pytest.approx(dr, rel=1e-7)
    vmax = ref_max_on(lambda t: abs(fd1(lambda x: ref_s(x, *p), t)), 0.0, 2 * math.pi, n=720)
    assert float(c.Pi_v_max) == pytest.approx(vmax, rel=1e-7)
    assert float(c.L) == pytest.approx(2 * r * math.sin(al) + l, rel=1e-14)  # Eq. (13)
    # exact axial extent: lowest disk point (phi = 0) to the highest slide point
    zA0 = ref_points(0.0, *p)[0][2]
    zB_low = min(ref_points(t, *p)[1][2] for t in np.linspace(0, 2 * math.pi, 721))
    assert float(c.L_exact) == pytest.approx(zA0 + smax - zB_low, rel=1e-9)
    assert bool(c.unimodal)
    omega = 50 * math.pi / 30
    assert float(sw.max_slide_speed(*p, omega=omega)) == pytest.approx(omega * vmax, rel=1e-7)


def test_velocity_limit_from_productivity_eq3_eq14():
    # Eq. (3): [Pi_v] <= 30 u [v] / (pi Pi_T), Pi_T in pieces/min; u = 12, [v] = 0.35 m/s,
    # Pi_T = 600/min
    expected = 30 * 12 * 0.35 / (math.pi * 600)
    assert float(sw.allowed_first_transfer(0.35, 600 / 60, 12)) == pytest.approx(expected,
                                                                                 rel=1e-14)


def test_unimodality_against_dense_reference():
    for p, want in ((S1_A, True), (S4A_A, True), (NONUNI, False)):
        ph = np.linspace(0, 2 * math.pi, 720, endpoint=False)
        s = np.array([ref_s(t, *p) for t in ph])
        n_max = int(np.sum((s > np.roll(s, 1)) & (s >= np.roll(s, -1))))
        assert (n_max == 1) is want
        assert bool(sw.unimodal(*p)) is want
        assert bool(sw.characteristics(*p).unimodal) is want


def test_scheme_constructors_fix_what_the_scheme_fixes():
    R = 0.1
    d1 = sw.scheme_1(R, 0.11, 0.15, 20 * DEG, 0.01, 0.02)
    assert d1.scheme == "1" and set(d1.free) == {"r", "l", "alpha", "a", "b"}
    d2 = sw.scheme_2(R, 0.03, 0.25, 0.02)
    assert (d2.alpha, d2.a) == (math.pi / 2, 0.0) and set(d2.free) == {"r", "l", "b"}
    d3 = sw.scheme_3(R, 0.09, 0.2, 0.02, 0.03)
    assert d3.alpha == 0.0 and set(d3.free) == {"r", "l", "a", "b"}
    d4a = sw.scheme_4a(R, 0.15, 20 * DEG)
    assert (d4a.a, d4a.b) == (0.0, 0.0) and set(d4a.free) == {"l", "alpha"}
    assert d4a.r * math.cos(d4a.alpha) == pytest.approx(R, rel=1e-15)
    d4b = sw.scheme_4b(R, 0.11, 0.15, 20 * DEG, 0.02)
    assert d4b.a == 0.0 and d4b.b == 0.02 and set(d4b.free) == {"r", "l", "alpha", "b"}
    # each constructor's design moves as the 3-D construction says, e.g. scheme 4a H = 2 R tan a
    _xmin, smin, _xmax, smax = ref_extremes(d4a.params, n=360)
    assert d4a.stroke() == pytest.approx(smax - smin, rel=1e-9)
    assert d4a.stroke() == pytest.approx(2 * R * math.tan(20 * DEG), rel=1e-12)
    for d in (d2, d3, d4b):
        assert float(d.position(2.0)) == pytest.approx(ref_s(2.0, *d.params), abs=1e-12)


@pytest.mark.parametrize("call, needle", [
    (lambda: sw.scheme_4a(0.1, 0.15, 0.0), "alpha"),
    (lambda: sw.scheme_4a(0.1, 0.15, math.pi / 2), "alpha"),
    (lambda: sw.scheme_4b(0.1, 0.11, 0.15, 20 * DEG, 0.0), "b"),
    (lambda: sw.scheme_3(0.1, 0.09, 0.2, 0.0, 0.0), "a, b"),
    (lambda: sw.scheme_1(0.1, -0.11, 0.15, 20 * DEG), "r"),
])
def test_scheme_constructors_reject_what_the_scheme_excludes(call, needle):
    with pytest.raises(ParameterError) as ei:
        call()
    assert str(ei.value).startswith(needle)


def ref_slide_statics(phi, p, F, mu_eff):
    """Rod force S (compression +), lateral force N, and the virtual powers (at omega = 1) of
    the rod force on the disk point and of the guide reaction on the slide point.

    Axial equilibrium of the slide: S cos(delta) = F + friction, friction = mu_eff |N| opposing
    the slide's velocity ds/dphi (from a finite difference of the construction).
    """
    A, B = ref_points(phi, *p)
    e = (A - B) / p[2]
    cd, sd = e[2], math.hypot(e[0], e[1])
    v = fd1(lambda x: ref_s(x, *p), phi)
    # S cd = F + mu sd |S| sgn(v)  -> solve for both signs of S and keep the consistent one
    S = None
    for sgn_S in (1.0, -1.0):
        cand = F / (cd - mu_eff * sd * sgn_S * math.copysign(1.0, v))
        if cand * sgn_S >= 0:
            S = cand
            break
    assert S is not None

    def B_of(t):
        return ref_points(t, *p)[1]

    def Ah_of(t):
        A_ = ref_points(t, *p)[0]
        return np.array([A_[0], A_[1], 0.0])

    vB = np.array([fd1(lambda t, k=k: B_of(t)[k], phi) for k in range(3)])
    vAh = np.array([fd1(lambda t, k=k: Ah_of(t)[k], phi) for k in range(3)])
    P_disk = S * float(e @ vB)  # the disk pushes the rod at B with S e
    eh = np.array([e[0], e[1], 0.0])
    P_rotor = -S * float(eh @ vAh)  # the guide holds the slide against the rod's S e_h
    return S, S * sd, P_disk, P_rotor, v


LOAD_ANG = np.radians([0.0, 60.0, 120.0, 170.0, 180.0, 360.0])


LOAD_F = np.array([0.0, 0.0, 20e3, 20e3, 0.0, 0.0])


@pytest.mark.parametrize("name", ["1a", "4a_a", "4b_b"])
def test_kinetostatics_frictionless_power_balance(name):
    d = sw.Design(*DESIGNS[name])
    u = 6
    ph = np.linspace(0.0, 2 * math.pi, 73)
    f = sw.drive_forces(d, (LOAD_ANG, LOAD_F), u=u, phi=ph)
    sel = [3, 20, 27, 33, 40, 55]
    for i in sel:
        t = ph[i]
        F = float(np.interp(t % (2 * math.pi), LOAD_ANG, LOAD_F))
        S, _N, P_disk, P_rotor, v = ref_slide_statics(t, d.params, F, 0.0)
        assert float(f.F[i]) == pytest.approx(F, abs=1e-9)
        assert float(f.S[i]) == pytest.approx(S, rel=1e-9, abs=1e-9)
        assert float(f.M_disk[i]) == pytest.approx(P_disk, rel=1e-7, abs=1e-6)
        assert float(f.M_rotor[i]) == pytest.approx(P_rotor, rel=1e-7, abs=1e-6)
        assert float(f.M[i]) == pytest.approx(F * v, rel=1e-7, abs=1e-6)  # torque x omega = F v
        # all u slides, phase-shifted by 2 pi / u: M_total omega = sum F_k v_k
        tot = 0.0
        for k in range(u):
            tk = t + 2 * math.pi * k / u
            Fk = float(np.interp(tk % (2 * math.pi), LOAD_ANG, LOAD_F))
            tot += Fk * fd1(lambda x: ref_s(x, *d.params), tk)
        assert float(f.M_total[i]) == pytest.approx(tot, rel=1e-7, abs=1e-6)
    assert f.efficiency == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("guide", [None, (0.12, 0.04)])
def test_kinetostatics_with_friction_losses_and_efficiency(guide):
    d = sw.Design(*S1_A)
    rho = 6 * DEG
    mu = math.tan(rho)
    kw = {}
    if guide is not None:
        bg, e = guide
        kw = {"guide_length": bg, "overhang": e}
        # two bearing places bg apart, the joint e outside: moments about the far one give
        # N1 = N (bg + e) / bg at the near one, N2 = N1 - N = N e / bg at the far one
        mu_eff = mu * ((bg + e) / bg + e / bg)
    else:
        mu_eff = mu
    ph = np.linspace(0.0, 2 * math.pi, 145)
    # a load that resists part of the forward stroke and aids part of the return stroke
    ang = np.radians([0.0, 60.0, 120.0, 200.0, 260.0, 300.0, 360.0])
    Fs = np.array([0.0, 5e3, 10e3, 0.0, -4e3, 0.0, 0.0])
    f = sw.drive_forces(d, (ang, Fs), u=3, rho_guide=rho, phi=ph, **kw)
    f0 = sw.drive_forces(d, (ang, Fs), u=3, phi=ph)
    for i in (10, 30, 45, 74, 76, 90, 110, 120):  # 74, 76: the load aids the return stroke
        t = ph[i]
        F = float(np.interp(t, ang, Fs))
        S, N, _P_disk, _P_rotor, v = ref_slide_statics(t, d.params, F, mu_eff)
        assert float(f.S[i]) == pytest.approx(S, rel=1e-9, abs=1e-9)
        # power in = useful power + friction power (losses >= 0, whichever way power flows)
        loss = mu_eff * abs(N) * abs(v)
        assert float(f.M[i]) == pytest.approx(F * v + loss, rel=1e-7, abs=1e-6)
        assert float(f.M[i]) - float(f0.M[i]) >= -1e-9
    assert 0.0 < f.efficiency < 1.0
    assert f.work_input > f0.work_input > 0
    # instantaneous efficiency of one slide: one value per angle (was (u, n), garbage rows)
    assert f.eta_inst.shape == ph.shape
    i = 30
    F = float(np.interp(ph[i], ang, Fs))
    assert float(f.eta_inst[i]) == pytest.approx(F * fd1(lambda x: ref_s(x, *d.params), ph[i])
                                                 / float(f.M[i]), rel=1e-7)
    assert f0.efficiency == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("kwargs, exc, needles", [
    ({"l": 0.01}, AssemblyError, ("rod cannot reach", "|sin(delta_z)| = 2.86799")),
    ({"alpha": 100 * DEG}, ParameterError, ("alpha", "100", "90")),
    ({"alpha": -1 * DEG}, ParameterError, ("alpha", "-1", "0")),
    ({"R": -0.1}, ParameterError, ("R", "-0.1", "> 0")),
    ({"l": 0.0}, ParameterError, ("l", "0")),
    ({"r": float("nan")}, ParameterError, ("r", "nan")),
    ({"a": float("inf")}, ParameterError, ("a", "inf")),
])
def test_bad_input_fails_clearly(kwargs, exc, needles):
    p = dict(zip(("R", "r", "l", "alpha", "a", "b"), S1_A, strict=True))
    p.update(kwargs)
    for fn in (sw.position, sw.pressure_angle, sw.first_transfer, sw.second_transfer):
        with pytest.raises(exc) as ei:
            fn(np.array([0.0, 1.0, 2.0]), **p)
        msg = str(ei.value)
        for n in needles:
            assert n in msg, msg
    with pytest.raises(exc):
        sw.stroke(**p)


def test_nan_angle_fails_clearly():
    with pytest.raises(ParameterError, match="phi"):
        sw.position(np.array([0.0, np.nan]), *S1_A)


def test_rod_that_cannot_reach_lists_the_angles():
    with pytest.raises(AssemblyError) as ei:
        sw.position(np.linspace(0, 2 * math.pi, 73), 0.1, 0.05, 0.06, 20 * DEG, 0.0, -0.045)
    assert ei.value.ranges  # the rotor-angle ranges where it fails


def test_drive_forces_rejects_fractional_slide_count():
    with pytest.raises(ParameterError, match=re.escape("u = 2.5")):  # was silently truncated to 2
        sw.drive_forces(sw.scheme_4a(0.1, 0.2, 0.2), 1000.0, u=2.5)


def test_harmonic_error_of_a_slide_that_does_not_move():
    # alpha = 0, a = b = 0: H = 0 and the harmonic form is exact; no 0/0 (a RuntimeWarning,
    # an error under pytest) and no NaN
    e = sw.harmonic_error(0.1, 0.09, 0.2, 0.0)
    assert float(e["max"]) == 0.0 and float(e["relative_max"]) == 0.0
