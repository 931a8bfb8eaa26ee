"""Every printed formula (1)-(21) of paper 000 (Toktakunov), checked one by one.

Each test writes the formula *as printed* (OCR read, symbols as in the paper: W1 = omega1,
tg = tan) and compares it with an independent reference: the geometric construction of
``_paper000_geometry`` (root solve of the bare constraints, time differences of positions).
Where the printed form is wrong the test shows that it disagrees with the reference and that
linkwork's corrected form agrees; docs/errata.md cites these tests.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _paper000_geometry import crank_slider_positions, slot_positions, time_derivatives

from linkwork.models.crank_slider import offset_crank_slider
from linkwork.models.sine import inclined_slot

L1, LAM2, LAME = 0.05, 4.0, 0.5  # a press-like crank-slider: L2 = 200 mm, e = 25 mm
PHIS = np.radians([0.0, 17.0, 45.0, 90.0, 133.0, 180.0, 211.0, 270.0, 302.0, 345.0])
W1, EPS1 = 12.566, 37.0  # rad/s, rad/s^2 (eps1 != 0 where the formula allows it)
SLOT = [math.radians(a) for a in (35.0, 60.0, 90.0, 120.0)]


def cs(phi):
    return crank_slider_positions(phi, L1, LAM2, LAME, 1)


def cs_rates(phi, w1=W1, e1=EPS1):
    """(Y_C, V_C, a_C), (phi2, omega2, eps2) from time differences of the construction."""
    y = time_derivatives(lambda q: cs(q)["Y_C"], phi, w1, e1)
    p0 = cs(phi)["phi2"]
    p = time_derivatives(lambda q: p0 + math.remainder(cs(q)["phi2"] - p0, 2 * math.pi),
                         phi, w1, e1)
    return y, p


def x3_con(phi, L, alpha):
    return slot_positions(0.0, L, alpha)["x_P"] - slot_positions(phi, L, alpha)["x_P"]


def rel(a, b, scale):
    return abs(a - b) / scale


# --- idle mode: offset crank-slider, Eqs. (1)-(13) ---------------------------------------------

def test_paper000_eq1_rod_angle_definition():
    """tg phi2 = (X_C - X_B) / (Y_C - Y_B): phi2 from +Y towards +X.  Correct."""
    r = offset_crank_slider(PHIS, L1, LAM2, LAME)
    for i, p in enumerate(PHIS):
        g = cs(p)
        assert math.tan(r.phi2[i]) == pytest.approx((g["X_C"] - g["X_B"]) / (g["Y_C"] - g["Y_B"]),
                                                    rel=1e-10, abs=1e-13)


def test_paper000_eq2_coordinates():
    """X_B = L1 cos, Y_B = L1 sin, X_C = e = lambda_e L1,
    Y_C = L1 [sin phi1 + sqrt(lambda2^2 - (lambda_e - cos phi1)^2)].  Correct (+ root = branch +1).

    The sentence before Eq. (1) prints the guide offset as "y = L1" and "e = lambda2 L1"; Eq. (2)
    and the rest use X_C = e = lambda_e L1 (erratum of the text, not of the formula)."""
    for p in PHIS:
        g = cs(p)
        printed_YC = L1 * (math.sin(p) + math.sqrt(LAM2**2 - (LAME - math.cos(p)) ** 2))
        assert g["X_B"] == pytest.approx(L1 * math.cos(p), abs=1e-16)
        assert g["Y_B"] == pytest.approx(L1 * math.sin(p), abs=1e-16)
        assert g["X_C"] == pytest.approx(LAME * L1)
        assert printed_YC == pytest.approx(g["Y_C"], rel=1e-12)
    # e = lambda2 L1 (the text's typo) would put the guide 200 mm away: not the mechanism of (2)
    assert crank_slider_positions(0.0, L1, LAM2, LAM2, 1)["X_C"] != pytest.approx(LAME * L1)


def test_paper000_eq3_tan_phi2():
    """tg phi2 = (lambda_e - cos phi1) / sqrt(lambda2^2 - (lambda_e - cos phi1)^2).  Correct."""
    for p in PHIS:
        printed = (LAME - math.cos(p)) / math.sqrt(LAM2**2 - (LAME - math.cos(p)) ** 2)
        assert printed == pytest.approx(math.tan(cs(p)["phi2"]), rel=1e-10, abs=1e-14)


def test_paper000_eq4_sin_cos_phi2_and_arcsin():
    """sin phi2 = (lambda_e - cos phi1)/lambda2, cos phi2 = sqrt(...)/lambda2,
    phi2 = arcsin[(lambda_e - cos phi1)/lambda2].  Correct for branch +1."""
    r = offset_crank_slider(PHIS, L1, LAM2, LAME)
    for i, p in enumerate(PHIS):
        g = cs(p)["phi2"]
        s = (LAME - math.cos(p)) / LAM2
        c = math.sqrt(LAM2**2 - (LAME - math.cos(p)) ** 2) / LAM2
        assert s == pytest.approx(math.sin(g), abs=1e-13)
        assert c == pytest.approx(math.cos(g), abs=1e-13)
        assert math.asin(s) == pytest.approx(g, abs=1e-12)
        assert r.phi2[i] == pytest.approx(math.asin(s), abs=1e-14)


def test_paper000_eq5_slider_position_function():
    """Y_C = L1 [sin phi1 + sqrt(lambda2^2 - (lambda_e - cos phi1)^2)].  Correct."""
    r = offset_crank_slider(PHIS, L1, LAM2, LAME)
    for i, p in enumerate(PHIS):
        printed = L1 * (math.sin(p) + math.sqrt(LAM2**2 - (LAME - math.cos(p)) ** 2))
        assert printed == pytest.approx(cs(p)["Y_C"], rel=1e-12)
        assert r.Y_C[i] == pytest.approx(printed, rel=1e-14)


def test_paper000_eq6_rod_angular_velocity_ratio():
    """U21 = sin phi1 / sqrt(lambda2^2 - (lambda_e - cos phi1)^2) = sin phi1/(lambda2 cos phi2),
    and the unsimplified derivative before it.  Correct."""
    r = offset_crank_slider(PHIS, L1, LAM2, LAME, W1, EPS1)
    for i, p in enumerate(PHIS):
        _, (phi2, w2, _) = cs_rates(p)
        ref = w2 / W1
        u = (LAME - math.cos(p)) / LAM2
        printed_a = math.sin(p) / (LAM2 * math.sqrt(1 - u * u))
        printed_b = math.sin(p) / math.sqrt(LAM2**2 - (LAME - math.cos(p)) ** 2)
        printed_c = math.sin(p) / (LAM2 * math.cos(phi2))
        for printed in (printed_a, printed_b, printed_c, r.U21[i]):
            assert rel(printed, ref, 1.0) < 1e-8


def test_paper000_eq7_slider_velocity_analogue():
    """V_qC = L1 [cos phi1 - sin phi1 (lambda_e - cos phi1)/sqrt(...)].  Correct."""
    for p in PHIS:
        (_, v, _), _ = cs_rates(p)
        root = math.sqrt(LAM2**2 - (LAME - math.cos(p)) ** 2)
        printed = L1 * (math.cos(p) - math.sin(p) * (LAME - math.cos(p)) / root)
        assert rel(printed, v / W1, L1) < 1e-8


def test_paper000_eq8_slider_velocity_analogue_trig_form():
    """V_qC = L1 [cos phi1 - sin phi1 sin phi2 / cos phi2] = L1 cos(phi1+phi2)/cos phi2.
    Correct."""
    r = offset_crank_slider(PHIS, L1, LAM2, LAME, W1, EPS1)
    for i, p in enumerate(PHIS):
        (_, v, _), (phi2, _, _) = cs_rates(p)
        f1 = L1 * (math.cos(p) - math.sin(p) * math.sin(phi2) / math.cos(phi2))
        f2 = L1 * math.cos(p + phi2) / math.cos(phi2)
        for printed in (f1, f2, r.V_qC[i]):
            assert rel(printed, v / W1, L1) < 1e-8


def test_paper000_eq9_rod_angular_acceleration_product_rule():
    """eps2 = U21 dW1/dt + W1 dU21/dt, checked with a varying crank speed.  Correct."""
    for p in PHIS:
        _, (_, _, eps2) = cs_rates(p)

        def u21(q):
            c2 = math.sqrt(LAM2**2 - (LAME - math.cos(q)) ** 2) / LAM2
            return math.sin(q) / (LAM2 * c2)

        _, du21_dt, _ = time_derivatives(u21, p, W1, EPS1)
        printed = u21(p) * EPS1 + W1 * du21_dt
        assert rel(printed, eps2, W1**2 + EPS1) < 1e-7


def test_paper000_eq10_rod_angular_acceleration():
    """eps2 = U21 eps1 + W1^2 dU21/dphi1.  Correct."""
    h = 1e-5
    r = offset_crank_slider(PHIS, L1, LAM2, LAME, W1, EPS1)
    rp = offset_crank_slider(PHIS + h, L1, LAM2, LAME)
    rm = offset_crank_slider(PHIS - h, L1, LAM2, LAME)
    du = (rp.U21 - rm.U21) / (2 * h)
    for i, p in enumerate(PHIS):
        _, (_, _, eps2) = cs_rates(p)
        printed = r.U21[i] * EPS1 + W1**2 * du[i]
        assert rel(printed, eps2, W1**2 + EPS1) < 1e-7
        assert rel(r.eps2[i], eps2, W1**2 + EPS1) < 1e-7


def test_paper000_eq11_angular_acceleration_analogue_last_form_wrong():
    """eps2/W1^2 = U21 eps1/W1^2 + eps_q2 and eps_q2 = (cos1 cos2 + sin1 sin2 U21)/(lambda2 cos2^2)
    are correct; the last printed form
    eps_q2 = 1/(lambda2 cos2) (cos1 + sin1^2 sin2/(lambda2 cos2)) lacks a square on cos2 in the
    inner denominator: correct is sin1^2 sin2/(lambda2 cos2^2)."""
    r = offset_crank_slider(PHIS, L1, LAM2, LAME, W1, EPS1)
    worst_printed = 0.0
    for i, p in enumerate(PHIS):
        _, (phi2, _, eps2) = cs_rates(p)
        s1, c1, s2, c2 = math.sin(p), math.cos(p), math.sin(phi2), math.cos(phi2)
        ref_q2 = (eps2 - r.U21[i] * EPS1) / W1**2  # eps_q2 from (11) and the construction
        u21 = s1 / (LAM2 * c2)
        middle = (c1 * c2 + s1 * s2 * u21) / (LAM2 * c2**2)
        printed_last = (c1 + s1**2 * s2 / (LAM2 * c2)) / (LAM2 * c2)
        corrected_last = (c1 + s1**2 * s2 / (LAM2 * c2**2)) / (LAM2 * c2)
        assert rel(middle, ref_q2, 1.0) < 1e-7
        assert rel(corrected_last, ref_q2, 1.0) < 1e-7
        assert rel(r.eps_q2[i], ref_q2, 1.0) < 1e-7
        worst_printed = max(worst_printed, abs(printed_last - ref_q2))
    assert worst_printed > 1e-4  # 1000x the check accuracy: the printed last form is wrong


def test_paper000_eq12_rod_angular_acceleration_ratio():
    """eps2/W1^2 = 1/(lambda2 cos2) [eps1/W1^2 sin1 + cos1 + sin1^2 sin2/(lambda2 cos2^2)].
    Correct."""
    for p in PHIS:
        _, (phi2, _, eps2) = cs_rates(p)
        s1, c1, s2, c2 = math.sin(p), math.cos(p), math.sin(phi2), math.cos(phi2)
        printed = (EPS1 / W1**2 * s1 + c1 + s1**2 * s2 / (LAM2 * c2**2)) / (LAM2 * c2)
        assert rel(printed, eps2 / W1**2, 1.0) < 1e-7


def test_paper000_eq13_slider_acceleration_wrong_signs():
    """Printed: a_C/W1^2 = L1/cos2 [eps1/W1^2 cos(phi2-phi1) + sin(phi2-phi1)
    + sin1^2/(lambda2 cos2^2)].  Wrong.  Correct:
    a_C/W1^2 = L1/cos2 [eps1/W1^2 cos(phi1+phi2) - sin(phi1+phi2) - sin1^2/(lambda2 cos2^2)]."""
    r = offset_crank_slider(PHIS, L1, LAM2, LAME, W1, EPS1)
    worst_printed = 0.0
    for i, p in enumerate(PHIS):
        (_, _, a), (phi2, _, _) = cs_rates(p)
        s1, c2, k = math.sin(p), math.cos(phi2), EPS1 / W1**2
        printed = L1 / c2 * (k * math.cos(phi2 - p) + math.sin(phi2 - p) + s1**2 / (LAM2 * c2**2))
        corrected = L1 / c2 * (k * math.cos(p + phi2) - math.sin(p + phi2)
                               - s1**2 / (LAM2 * c2**2))
        assert rel(corrected, a / W1**2, L1) < 1e-7
        assert rel(r.a_C[i], a, (W1**2 + EPS1) * L1) < 1e-7
        worst_printed = max(worst_printed, abs(printed - a / W1**2) / L1)
    assert worst_printed > 0.5


# --- working mode: sine mechanism, Eqs. (14)-(21) ----------------------------------------------

def test_paper000_eq14_sine_positions_alpha90():
    """X3 = L1 (1 - cos phi1), X32 = L1 sin phi1 (slot perpendicular to the motion).  Correct."""
    r = inclined_slot(PHIS, L1, math.pi / 2)
    for i, p in enumerate(PHIS):
        assert L1 * (1 - math.cos(p)) == pytest.approx(x3_con(p, L1, math.pi / 2), abs=1e-15)
        assert L1 * math.sin(p) == pytest.approx(slot_positions(p, L1, math.pi / 2)["along"],
                                                 abs=1e-15)
        assert r.X3[i] == pytest.approx(L1 * (1 - math.cos(p)), abs=1e-17)


def test_paper000_eq15_velocity_chain_rule():
    """V3 = dX3/dt = W1 dX3/dphi1 (text says "differentiate (13)"; it is (14)).  Correct, for
    any alpha and eps1."""
    h = 1e-5
    for alpha in SLOT:
        for p in PHIS:
            _, v3, _ = time_derivatives(lambda q, a=alpha: x3_con(q, L1, a), p, W1, EPS1)
            dx_dphi = (x3_con(p + h, L1, alpha) - x3_con(p - h, L1, alpha)) / (2 * h)
            assert rel(W1 * dx_dphi, v3, W1 * L1 / math.sin(alpha)) < 1e-8


def test_paper000_eq16_sine_transfer_function_alpha90():
    """U31 = dX3/dphi1 = V3/W1 = L1 sin phi1 (alpha = 90 deg).  Correct."""
    r = inclined_slot(PHIS, L1, math.pi / 2, W1)
    for i, p in enumerate(PHIS):
        _, v3, _ = time_derivatives(lambda q: x3_con(q, L1, math.pi / 2), p, W1, 0.0)
        assert rel(L1 * math.sin(p), v3 / W1, L1) < 1e-9
        assert r.U31[i] == pytest.approx(L1 * math.sin(p), abs=1e-17)


def test_paper000_eq17_sine_velocities_alpha90():
    """V3 = W1 L1 sin phi1, and (unnumbered) V32 = W1 L1 cos phi1 (alpha = 90 deg).  Correct."""
    for p in PHIS:
        _, v3, _ = time_derivatives(lambda q: x3_con(q, L1, math.pi / 2), p, W1, EPS1)
        _, v32, _ = time_derivatives(lambda q: slot_positions(q, L1, math.pi / 2)["along"], p,
                                     W1, EPS1)
        assert rel(W1 * L1 * math.sin(p), v3, W1 * L1) < 1e-9
        assert rel(W1 * L1 * math.cos(p), v32, W1 * L1) < 1e-9


def test_paper000_eq18_sine_accelerations_alpha90_a32_sign_wrong():
    """a3 = W1^2 L1 cos phi1 (correct for eps1 = 0); printed a32 = +W1^2 L1 sin phi1 is wrong:
    d^2(L1 sin phi1)/dt^2 = -W1^2 L1 sin phi1 (+ eps1 L1 cos phi1)."""
    r = inclined_slot(PHIS, L1, math.pi / 2, W1, 0.0)
    worst = 0.0
    for i, p in enumerate(PHIS):
        _, _, a3 = time_derivatives(lambda q: x3_con(q, L1, math.pi / 2), p, W1, 0.0)
        _, _, a32 = time_derivatives(lambda q: slot_positions(q, L1, math.pi / 2)["along"], p,
                                     W1, 0.0)
        sc = W1**2 * L1
        assert rel(W1**2 * L1 * math.cos(p), a3, sc) < 1e-7
        assert rel(-(W1**2) * L1 * math.sin(p), a32, sc) < 1e-7
        assert rel(r.a32[i], a32, sc) < 1e-7
        worst = max(worst, abs(W1**2 * L1 * math.sin(p) - a32) / sc)
    assert worst > 1.9  # printed sign wrong: off by 2 W1^2 L1 at phi1 = 90 deg


def test_paper000_eq19_inclined_slot_positions():
    """Printed X3 = L1 (1 - cos phi1)/sin alpha and dX3/dt = W1 L1 sin phi1 are wrong for
    alpha != 90 deg; correct X3 = L1 (1 - cos phi1 + sin phi1/tg alpha).  The printed X3 is the
    displacement from the extreme position with phi1 counted from the crank position there.
    The unnumbered X32 = L1 sin phi1 / sin alpha and U31 = L1 (sin phi1 + cos phi1/tg alpha)
    that follow (19) are correct."""
    for alpha in SLOT:
        r = inclined_slot(PHIS, L1, alpha, W1)
        worst_x, worst_v = 0.0, 0.0
        phi_min = alpha - math.pi / 2
        x3_min = x3_con(phi_min, L1, alpha)
        for i, p in enumerate(PHIS):
            ref = x3_con(p, L1, alpha)
            _, v3, _ = time_derivatives(lambda q, a=alpha: x3_con(q, L1, a), p, W1, 0.0)
            printed = L1 * (1 - math.cos(p)) / math.sin(alpha)
            corrected = L1 * (1 - math.cos(p) + math.sin(p) / math.tan(alpha))
            assert corrected == pytest.approx(ref, abs=1e-15)
            assert r.X3[i] == pytest.approx(ref, abs=1e-15)
            # printed form, re-read with the crank angle counted from the extreme position
            shifted = L1 * (1 - math.cos(p - phi_min)) / math.sin(alpha)
            assert shifted == pytest.approx(ref - x3_min, abs=1e-15)
            assert L1 * math.sin(p) / math.sin(alpha) == pytest.approx(
                slot_positions(p, L1, alpha)["along"], abs=1e-15)
            u31 = L1 * (math.sin(p) + math.cos(p) / math.tan(alpha))
            assert rel(u31, v3 / W1, L1) < 1e-8
            worst_x = max(worst_x, abs(printed - ref) / L1)
            worst_v = max(worst_v, abs(W1 * L1 * math.sin(p) - v3) / (W1 * L1))
        if alpha != math.pi / 2:
            assert worst_x > 0.1 and worst_v > 0.1
        else:
            assert worst_x < 1e-12 and worst_v < 1e-8


def test_paper000_eq20_inclined_slot_velocities():
    """V3 = W1 L1 (sin phi1 + cos phi1/tg alpha), V32 = W1 L1 cos phi1/sin alpha.  Correct
    (any eps1)."""
    for alpha in SLOT:
        r = inclined_slot(PHIS, L1, alpha, W1, EPS1)
        for i, p in enumerate(PHIS):
            _, v3, _ = time_derivatives(lambda q, a=alpha: x3_con(q, L1, a), p, W1, EPS1)
            _, v32, _ = time_derivatives(lambda q, a=alpha: slot_positions(q, L1, a)["along"], p,
                                         W1, EPS1)
            sc = W1 * L1 / math.sin(alpha)
            assert rel(W1 * L1 * (math.sin(p) + math.cos(p) / math.tan(alpha)), v3, sc) < 1e-8
            assert rel(W1 * L1 * math.cos(p) / math.sin(alpha), v32, sc) < 1e-8
            assert rel(r.V3[i], v3, sc) < 1e-8 and rel(r.V32[i], v32, sc) < 1e-8


def test_paper000_eq21_inclined_slot_accelerations_a32_sign_wrong():
    """a3 = W1^2 L1 (cos phi1 - sin phi1/tg alpha): correct for eps1 = 0 (add eps1 U31 in
    general).  Printed a32 = +W1^2 L1 sin phi1/sin alpha is wrong: correct
    a32 = -W1^2 L1 sin phi1/sin alpha (+ eps1 L1 cos phi1/sin alpha)."""
    for alpha in SLOT:
        r0 = inclined_slot(PHIS, L1, alpha, W1, 0.0)
        r1 = inclined_slot(PHIS, L1, alpha, W1, EPS1)
        sc = (W1**2 + EPS1) * L1 / math.sin(alpha)
        worst = 0.0
        for i, p in enumerate(PHIS):
            _, _, a3 = time_derivatives(lambda q, a=alpha: x3_con(q, L1, a), p, W1, 0.0)
            _, _, a32 = time_derivatives(lambda q, a=alpha: slot_positions(q, L1, a)["along"],
                                         p, W1, 0.0)
            _, _, a3e = time_derivatives(lambda q, a=alpha: x3_con(q, L1, a), p, W1, EPS1)
            _, _, a32e = time_derivatives(lambda q, a=alpha: slot_positions(q, L1, a)["along"],
                                          p, W1, EPS1)
            printed_a3 = W1**2 * L1 * (math.cos(p) - math.sin(p) / math.tan(alpha))
            printed_a32 = W1**2 * L1 * math.sin(p) / math.sin(alpha)
            assert rel(printed_a3, a3, sc) < 1e-7
            assert rel(-printed_a32, a32, sc) < 1e-7
            assert rel(r0.a3[i], a3, sc) < 1e-7 and rel(r0.a32[i], a32, sc) < 1e-7
            assert rel(r1.a3[i], a3e, sc) < 1e-7 and rel(r1.a32[i], a32e, sc) < 1e-7
            worst = max(worst, abs(printed_a32 - a32) / sc)
        assert worst > 0.5
