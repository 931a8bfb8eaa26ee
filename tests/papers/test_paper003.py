"""Paper 003 (Kryukov & Preis 2012), formula by formula, against the independent 3-D reference
(rotation matrices + brentq, tests/_swashplate_reference.py) and finite differences. Each
test names the equation; docs/errata.md cites these tests."""

import math

import numpy as np
import pytest
from _swashplate_reference import disk_point, ref_delta, ref_s, ref_z, slide_point

from linkwork.models import swashplate as sw

DEG = math.pi / 180
P1 = (0.10, 0.09, 0.20, 20 * DEG, 0.02, -0.01)  # scheme 1
P4A = (0.10, 0.10 / math.cos(15 * DEG), 0.20, 15 * DEG, 0.0, 0.0)
P4B = (0.10, 0.11, 0.22, 25 * DEG, 0.0, 0.015)
PHI = np.radians([0.0, 20.0, 75.0, 110.0, 180.0, 200.0, 260.0, 333.0])


def printed_sin2_delta(phi, R, r, l, alpha, a, b):
    """Eq. (5) as printed."""
    return (((R - r) * np.sin(phi) - a) / l) ** 2 + \
        (((r * np.cos(alpha) - R) * np.cos(phi) - b) / l) ** 2


def printed_s(phi, R, r, l, alpha, a, b):
    """Eq. (4) as printed, with delta_z from Eq. (5)."""
    cd = np.sqrt(1 - printed_sin2_delta(phi, R, r, l, alpha, a, b))
    cd0 = np.sqrt(1 - printed_sin2_delta(0.0, R, r, l, alpha, a, b))
    return r * np.sin(alpha) * (1 - np.cos(phi)) + l * (cd - cd0)


def fd(f, x, h=1e-5):
    return (f(x + h) - f(x - h)) / (2 * h)


@pytest.mark.parametrize("p", [P1, P4A, P4B])
def test_paper003_eq5_pressure_angle_as_printed(p):
    """Reference: paper 003, Eq. (5); the 3-D construction of tests/_swashplate_reference.py
    (rotation matrices + brentq). Tolerance: atol=1e-12."""
    ref = np.array([math.sin(ref_delta(x, *p)) ** 2 for x in PHI])
    np.testing.assert_allclose(printed_sin2_delta(PHI, *p), ref, atol=1e-12)
    np.testing.assert_allclose(np.sin(sw.pressure_angle(PHI, *p)) ** 2, ref, atol=1e-12)


@pytest.mark.parametrize("p", [P1, P4A, P4B])
def test_paper003_eq4_position_as_printed(p):
    """Reference: paper 003, Eq. (4); the 3-D construction of tests/_swashplate_reference.py
    (rotation matrices + brentq). Tolerance: atol=1e-12."""
    ref = np.array([ref_s(x, *p) for x in PHI])
    np.testing.assert_allclose(printed_s(PHI, *p), ref, atol=1e-12)
    np.testing.assert_allclose(sw.position(PHI, *p), ref, atol=1e-12)


def test_paper003_datum_offset_c_depends_on_alpha():
    # c = z_O - z_O1 (paper: c = c(R, r, l, a, b)); from the 3-D reference: O1 is at z = 0
    """Reference: paper 003; the 3-D construction of tests/_swashplate_reference.py (rotation
    matrices + brentq). Tolerance: < 1e-12."""
    # there, and z_A(0) is the height of O
    for al in (10 * DEG, 30 * DEG):
        p = (0.1, 0.09, 0.2, al, 0.02, -0.01)
        assert abs(sw.datum_offset(*p) - ref_z(0.0, *p)) < 1e-12
    assert abs(sw.datum_offset(0.1, 0.09, 0.2, 10 * DEG, 0.02, -0.01)
               - sw.datum_offset(0.1, 0.09, 0.2, 30 * DEG, 0.02, -0.01)) > 1e-3


@pytest.mark.parametrize("p", [P1, P4B])
def test_paper003_eq6_harmonic_form_is_the_small_angle_expansion(p):
    # independent: r sin(alpha)(1 - cos phi) - (q(phi) - q(0)) / (2 l), q = squared horizontal
    """Reference: paper 003, Eq. (6); the 3-D construction of tests/_swashplate_reference.py
    (rotation matrices + brentq). Tolerance: atol=1e-15, rtol=1e-15."""
    # rod projection from the 3-D points (cos d ~ 1 - sin^2 d / 2)
    R, r, l, al, a, b = p

    def q(x):
        d = slide_point(x, R, 0.0) - disk_point(x, *p)
        return d[0] ** 2 + d[1] ** 2

    expansion = np.array([r * math.sin(al) * (1 - math.cos(x)) - (q(x) - q(0.0)) / (2 * l)
                          for x in PHI])
    A1 = r * math.sin(al) + b * (R - r * math.cos(al)) / l  # as printed
    A2 = a * (R - r) / l
    A3 = ((R - r * math.cos(al)) ** 2 - (R - r) ** 2) / l
    printed_quarter = A1 * (1 - np.cos(PHI)) + A2 * np.sin(PHI) + A3 / 4 * (1 - np.cos(2 * PHI))
    np.testing.assert_allclose(printed_quarter, expansion, atol=1e-15)
    np.testing.assert_allclose(sw.position_harmonic(PHI, *p), expansion, atol=1e-15)
    np.testing.assert_allclose(np.array(sw.harmonic_coefficients(*p)), [A1, A2, A3], rtol=1e-15)
    # the OCR's "4 A3" instead of 1/4 A3 does not match
    wrong = A1 * (1 - np.cos(PHI)) + A2 * np.sin(PHI) + 4 * A3 * (1 - np.cos(2 * PHI))
    assert np.max(np.abs(wrong - expansion)) > 1e-4


def test_paper003_eq6_accuracy_against_exact():
    # the expansion drops O(l sin^4 delta): its error against the exact 3-D position is small
    """Reference: paper 003, Eq. (6); the 3-D construction of tests/_swashplate_reference.py
    (rotation matrices + brentq). Tolerance: < 0.2 * errs[-1] + 1e-9, < 5e-5."""
    # and shrinks as l grows
    errs = []
    for l in (0.2, 0.4):
        p = (0.1, 0.09, l, 20 * DEG, 0.02, -0.01)
        exact = np.array([ref_s(x, *p) for x in PHI])
        errs.append(np.max(np.abs(sw.position_harmonic(PHI, *p) - exact)))
        assert abs(sw.harmonic_error(*p)["max"] - errs[-1]) < 0.2 * errs[-1] + 1e-9
    assert errs[0] < 5e-5 and errs[1] < errs[0] / 5


def test_paper003_eq7_eq8_eq9_relative_units():
    """Reference: paper 003, Eq. (7), (8), (9); the 3-D construction of
    tests/_swashplate_reference.py (rotation matrices + brentq). Tolerance: atol=1e-15,
    atol=1e-12."""
    R = P1[0]
    rel = sw.relative(R, r=P1[1], l=P1[2], a=P1[4], b=P1[5])
    prel = (1.0, float(rel["r"]), float(rel["l"]), P1[3], float(rel["a"]), float(rel["b"]))
    # Eq. (8): the relative pressure angle equals the absolute one
    np.testing.assert_allclose(printed_sin2_delta(PHI, *prel), printed_sin2_delta(PHI, *P1),
                               atol=1e-15)
    # Eq. (9): s~ = s / R
    ref = np.array([ref_s(x, *P1) for x in PHI]) / R
    np.testing.assert_allclose(sw.position(PHI, *prel), ref, atol=1e-12)


def printed_eq10(phi, R, r, l, alpha, a, b, first_term_sin=False):
    """Eq. (10) as printed (relative units when R = 1): r sin(a) cos(phi) - l sin d d'."""
    s2 = printed_sin2_delta(phi, R, r, l, alpha, a, b)
    d = np.arcsin(np.sqrt(s2))
    X = (R - r) * np.sin(phi) - a
    Y = (r * np.cos(alpha) - R) * np.cos(phi) - b
    with np.errstate(invalid="ignore", divide="ignore"):
        dd = 2 / (l * l * np.sin(2 * d)) * (X * (R - r) * np.cos(phi)
                                            - Y * (r * np.cos(alpha) - R) * np.sin(phi))
    trig = np.sin(phi) if first_term_sin else np.cos(phi)
    return r * np.sin(alpha) * trig - l * np.sin(d) * dd


@pytest.mark.parametrize("p", [P1, P4B])
def test_paper003_eq10_first_term_should_be_sin_phi(p):
    """Reference: paper 003, Eq. (10); the 3-D construction of tests/_swashplate_reference.py
    (rotation matrices + brentq); central finite differences. Tolerance: atol=1e-8."""
    R = p[0]
    prel = (1.0, p[1] / R, p[2] / R, p[3], p[4] / R, p[5] / R)
    ph = PHI[1:]  # avoid phi = 0 where the printed form is 0/0 for some designs
    ref = np.array([fd(lambda x: ref_s(x, *p), x) for x in ph]) / R
    corrected = printed_eq10(ph, *prel, first_term_sin=True)
    np.testing.assert_allclose(corrected, ref, atol=1e-8)
    np.testing.assert_allclose(sw.first_transfer(ph, *prel), ref, atol=1e-8)
    assert np.max(np.abs(printed_eq10(ph, *prel) - ref)) > 0.05


def test_paper003_eq10_zero_over_zero_where_pressure_angle_vanishes():
    # a design with the rod parallel to the axis at phi = 0 (X = Y = 0 exactly): the printed
    """Reference: paper 003, Eq. (10); the 3-D construction of tests/_swashplate_reference.py
    (rotation matrices + brentq); central finite differences. Tolerance: atol=1e-9."""
    # d(delta)/d(phi) is 0/0 there; the corrected form is finite and matches the reference
    r, al = 1.1, 25 * DEG
    prel = (1.0, r, 2.2, al, 0.0, r * np.cos(al) - 1.0)
    ph = np.array([0.0, 0.5])
    printed = printed_eq10(ph, *prel, first_term_sin=True)
    assert np.isnan(printed[0]) and np.isfinite(printed[1])
    ours = sw.first_transfer(ph, *prel)
    ref = np.array([fd(lambda x: ref_s(x, *prel), x) for x in ph])
    np.testing.assert_allclose(ours, ref, atol=1e-9)
    assert np.isfinite(sw.second_transfer(ph, *prel)).all()


def test_paper003_eq11_harmonic_transfer_function_factor_one_half():
    """Reference: paper 003, Eq. (11); central finite differences. Tolerance: atol=1e-9."""
    p = P1
    h = 1e-6
    deriv = (sw.position_harmonic(PHI + h, *p) - sw.position_harmonic(PHI - h, *p)) / (2 * h)
    A1, A2, A3 = sw.harmonic_coefficients(*p)
    half = A1 * np.sin(PHI) + A2 * np.cos(PHI) + 0.5 * A3 * np.sin(2 * PHI)
    np.testing.assert_allclose(half, deriv, atol=1e-9)
    np.testing.assert_allclose(sw.first_transfer_harmonic(PHI, *p), deriv, atol=1e-9)
    printed_two = A1 * np.sin(PHI) + A2 * np.cos(PHI) + 2 * A3 * np.sin(2 * PHI)
    assert np.max(np.abs(printed_two - deriv)) > 1e-4


def test_paper003_eq1_eq2_eq3_eq14_velocity_limit():
    """Reference: paper 003, Eq. (1), (2), (3), (14); the 3-D construction of
    tests/_swashplate_reference.py (rotation matrices + brentq). Tolerance: < 1e-4 * v_ref, <
    1e-12, < 1e-15."""
    # Pi_T = 600 pieces/min on u = 12 positions: n = 50 rpm, omega = pi n / 30
    Pi_T, u = 600.0, 12
    n = Pi_T / u
    omega = math.pi * n / 30
    c = sw.characteristics(*P1)
    # Eq. (1): v = omega Pi_v; slide speed from the reference by a time derivative
    t = np.linspace(0, 2 * math.pi / omega, 3001)
    z = np.array([ref_s(omega * x, *P1) for x in t])
    v_ref = np.max(np.abs(np.gradient(z, t)))
    v2 = math.pi * Pi_T / (30 * u) * c.Pi_v_max  # Eq. (2)
    assert abs(v2 - v_ref) < 1e-4 * v_ref
    assert abs(sw.max_slide_speed(*P1, omega=omega) - v2) < 1e-12
    v_allow = 0.2
    lim = 30 * u * v_allow / (math.pi * Pi_T)  # Eq. (3)
    assert abs(sw.allowed_first_transfer(v_allow, Pi_T / 60, u) - lim) < 1e-15
    assert abs(sw.allowed_first_transfer(v_allow, Pi_T / 60, u) / P1[0] - lim / P1[0]) < 1e-15


def test_paper003_eq13_axial_size_is_an_upper_bound():
    """Reference: paper 003, Eq. (13); the 3-D construction of tests/_swashplate_reference.py
    (rotation matrices + brentq). Tolerance: < 1e-15."""
    for p in (P1, P4A, P4B):
        c = sw.characteristics(*p)
        ph = np.linspace(0, 2 * math.pi, 1441)
        zA = max(ref_z(x, *p) for x in ph)
        zB = min(disk_point(x, *p)[2] for x in ph)
        assert c.L >= zA - zB - 1e-12
        assert abs(c.L - (2 * p[1] * math.sin(p[3]) + p[2])) < 1e-15


def test_paper003_symmetry_of_schemes_with_a_zero():
    """Reference: paper 003; the 3-D construction of tests/_swashplate_reference.py (rotation
    matrices + brentq). Tolerance: atol=1e-12, < 1e-9, < 1e-12."""
    # "for schemes 2 and 4 (a = 0) all characteristics are symmetric about phi = pi"
    for p in (P4A, P4B, (0.1, 0.03, 0.25, 90 * DEG, 0.0, 0.02)):
        s = np.array([ref_s(x, *p) for x in PHI])
        s_mirror = np.array([ref_s(2 * math.pi - x, *p) for x in PHI])
        np.testing.assert_allclose(s, s_mirror, atol=1e-12)
        c = sw.characteristics(*p)
        assert abs(c.phi_f - c.phi_r) < 1e-9 and abs(c.delta_f - c.delta_r) < 1e-12


def test_paper003_scheme3_symmetric_after_shifting_the_origin():
    """Reference: paper 003; the 3-D construction of tests/_swashplate_reference.py (rotation
    matrices + brentq). Tolerance: atol=1e-12, < 1e-9."""
    R, r, l, a, b = 0.1, 0.07, 0.2, 0.03, 0.02
    p = (R, r, l, 0.0, a, b)
    centre = math.atan2(b, a) + math.pi / 2  # q = const - 2 (R - r) rho sin(phi - psi)
    t = np.radians([5.0, 40.0, 100.0, 170.0])
    left = np.array([ref_s(centre - x, *p) for x in t])
    right = np.array([ref_s(centre + x, *p) for x in t])
    np.testing.assert_allclose(left, right, atol=1e-12)
    c = sw.characteristics(*p)
    assert abs(c.phi_f - math.pi) < 1e-9


def test_paper003_scheme_4a_pressure_angle_zero_at_extremes_and_stroke():
    """Reference: paper 003; the 3-D construction of tests/_swashplate_reference.py (rotation
    matrices + brentq). Tolerance: < 1e-12, < 1e-7."""
    # 4a: R = r cos(alpha) puts the rod parallel to the axis at phi = 0 and pi; H = 2 r sin a
    assert ref_delta(0.0, *P4A) < 1e-7 and ref_delta(math.pi, *P4A) < 1e-7
    H = sw.stroke(*P4A)
    assert abs(H - (ref_s(math.pi, *P4A) - ref_s(0.0, *P4A))) < 1e-12
    assert abs(H - 2 * P4A[1] * math.sin(P4A[3])) < 1e-12
