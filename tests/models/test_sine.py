"""Sine mechanism with inclined slot (paper 000, working mode) vs construction, FDs, statics."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from _paper000_geometry import _crank_phi, _time_derivs, slot_positions, time_derivatives
from _paper000_loop_equations import _close, _sine_reference
from _strategies import reals
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq, minimize_scalar

from linkwork.errors import InfeasibleError, LinkworkError, ParameterError
from linkwork.models import sine
from linkwork.models.sine import (
    alpha_for_stroke,
    check_alpha,
    extreme_positions,
    force_ratio,
    inclined_slot,
    stroke,
    working_range,
)

PHI = np.linspace(0.0, 2 * np.pi, 73)
CASES = [  # L1 [m], alpha [rad], omega1 [rad/s], eps1 [rad/s^2]
    (0.05, math.radians(60), 12.566, 0.0),
    (0.05, math.radians(60), 12.566, 40.0),
    (0.05, math.radians(90), 12.566, -30.0),
    (0.08, math.radians(125), -9.0, 15.0),
    (1.0, math.radians(20), 1.0, 1.0),
]


def _X3_construction(phi, L1, alpha):
    """Slider displacement from its phi1 = 0 position, towards the crank axis (-x)."""
    return slot_positions(0.0, L1, alpha)["x_P"] - slot_positions(phi, L1, alpha)["x_P"]


@pytest.mark.parametrize("L1,alpha,w1,e1", CASES)
def test_positions_match_independent_construction(L1, alpha, w1, e1):
    """Reference: the geometric construction of tests/_paper000_geometry.py. Tolerance:
    abs=1e-13 * L1 / 0.05."""
    r = inclined_slot(PHI, L1, alpha, w1, e1)
    for i, p in enumerate(PHI):
        assert r.X3[i] == pytest.approx(_X3_construction(p, L1, alpha), abs=1e-13 * L1 / 0.05)
        assert r.X32[i] == pytest.approx(slot_positions(p, L1, alpha)["along"],
                                         abs=1e-13 * L1 / 0.05)


@pytest.mark.parametrize("L1,alpha,w1,e1", CASES)
def test_velocities_accelerations_match_time_differences_of_construction(L1, alpha, w1, e1):
    """Reference: the geometric construction of tests/_paper000_geometry.py. Tolerance: < 1e-8,
    < 1e-7."""
    phis = PHI[:-1:3]
    r = inclined_slot(phis, L1, alpha, w1, e1)
    vscale = (abs(w1) + 1e-3 * abs(e1)) * L1 / math.sin(alpha)
    ascale = (w1 * w1 + abs(e1)) * L1 / math.sin(alpha)
    for i, p in enumerate(phis):
        _, v3, a3 = time_derivatives(lambda q: _X3_construction(q, L1, alpha), p, w1, e1)
        _, v32, a32 = time_derivatives(lambda q: slot_positions(q, L1, alpha)["along"], p, w1, e1)
        assert abs(r.V3[i] - v3) / vscale < 1e-8
        assert abs(r.V32[i] - v32) / vscale < 1e-8
        assert abs(r.a3[i] - a3) / ascale < 1e-7
        assert abs(r.a32[i] - a32) / ascale < 1e-7


@pytest.mark.parametrize("L1,alpha,w1,e1", CASES)
def test_transfer_functions_match_finite_differences_of_position_functions(L1, alpha, w1, e1):
    h = 1e-4
    r, rp, rm = (inclined_slot(PHI + d, L1, alpha) for d in (0.0, h, -h))
    np.testing.assert_allclose(r.U31, (rp.X3 - rm.X3) / (2 * h), atol=1e-8 * L1 / math.sin(alpha))
    np.testing.assert_allclose(r.U321, (rp.X32 - rm.X32) / (2 * h), atol=1e-8 * L1)
    np.testing.assert_allclose(r.a_q3, (rp.X3 - 2 * r.X3 + rm.X3) / h**2, atol=1e-5 * L1)
    np.testing.assert_allclose(r.a_q32, (rp.X32 - 2 * r.X32 + rm.X32) / h**2, atol=1e-5 * L1)


@settings(max_examples=80, deadline=None)
@given(phi1=reals(-10, 10), L1=st.floats(1e-3, 2.0), alpha=st.floats(0.05, math.pi - 0.05))
def test_property_loop_closure_pin_on_slot(phi1, L1, alpha):
    """The pin B equals slider point P(x) + X32 * slot direction, with x_P = L1 - X3."""
    r = inclined_slot(phi1, L1, alpha)
    P = np.array([L1 - float(r.X3), 0.0])
    d = np.array([math.cos(alpha), math.sin(alpha)])
    B = np.array([L1 * math.cos(phi1), L1 * math.sin(phi1)])
    np.testing.assert_allclose(P + float(r.X32) * d, B, atol=1e-12 * L1 / math.sin(alpha))


@settings(max_examples=60, deadline=None)
@given(phi1=reals(0, 2 * np.pi), alpha=st.floats(0.05, math.pi - 0.05),
       w1=reals(-30, 30), e1=reals(-100, 100))
def test_property_velocity_closure(phi1, alpha, w1, e1):
    """v_B = v_slider + v_rel: (-V3, 0) + V32 * d equals the pin velocity; same for accel."""
    L1 = 0.05
    r = inclined_slot(phi1, L1, alpha, w1, e1)
    d = np.array([math.cos(alpha), math.sin(alpha)])
    vB = w1 * L1 * np.array([-math.sin(phi1), math.cos(phi1)])
    aB = L1 * (e1 * np.array([-math.sin(phi1), math.cos(phi1)])
               - w1 * w1 * np.array([math.cos(phi1), math.sin(phi1)]))
    tol = 1e-10 * (1 + w1 * w1 + abs(e1)) / math.sin(alpha)
    np.testing.assert_allclose(np.array([-float(r.V3), 0.0]) + float(r.V32) * d, vB, atol=tol)
    # the slider translates, so no Coriolis term: a_B = a_slider + a_rel
    np.testing.assert_allclose(np.array([-float(r.a3), 0.0]) + float(r.a32) * d, aB, atol=tol)


def test_alpha_90_is_classical_sine_mechanism():
    r = inclined_slot(PHI, 0.05, math.pi / 2, 10.0)
    np.testing.assert_allclose(r.X3, 0.05 * (1 - np.cos(PHI)), atol=1e-17)
    np.testing.assert_allclose(r.X32, 0.05 * np.sin(PHI), atol=1e-17)


def test_broadcast_designs():
    L1 = np.array([[0.05], [0.1]])
    al = np.array([[math.radians(60)], [math.radians(100)]])
    r = inclined_slot(PHI, L1, al, 12.0, 2.0)
    assert r.a3.shape == (2, PHI.size)
    for k in range(2):
        one = inclined_slot(PHI, L1[k, 0], al[k, 0], 12.0, 2.0)
        np.testing.assert_array_equal(r.a3[k], one.a3)
        np.testing.assert_array_equal(r.X32[k], one.X32)


@pytest.mark.parametrize("alpha", [math.radians(a) for a in (15, 45, 60, 90, 120, 165)])
def test_stroke_and_extreme_positions_vs_numerical_extremes(alpha):
    L1 = 0.05
    grid = np.linspace(0, 2 * np.pi, 721)
    xs = np.array([_X3_construction(p, L1, alpha) for p in grid])
    res = []
    for sign, idx in ((1, xs.argmin()), (-1, xs.argmax())):
        res.append(minimize_scalar(lambda p, s=sign: s * _X3_construction(p, L1, alpha),
                                   bracket=(grid[idx] - 0.05, grid[idx], grid[idx] + 0.05),
                                   tol=1e-12))
    lo, hi = res[0], res[1]
    assert float(stroke(L1, alpha)) == pytest.approx(-hi.fun - lo.fun, rel=1e-12)
    p_min, p_max = extreme_positions(alpha)
    assert math.cos(float(p_min) - lo.x) == pytest.approx(1.0, abs=1e-10)
    assert math.cos(float(p_max) - hi.x) == pytest.approx(1.0, abs=1e-10)
    r = inclined_slot(np.array([p_min, p_max]), L1, alpha)
    np.testing.assert_allclose(r.U31, 0.0, atol=1e-16)
    np.testing.assert_allclose(r.X3, [lo.fun, -hi.fun], rtol=1e-12)


def test_alpha_for_stroke_both_solutions():
    L1, H = 0.05, 0.16
    a1, a2 = alpha_for_stroke(L1, H)
    assert float(a1) < math.pi / 2 < float(a2)
    for a in (a1, a2):
        assert float(stroke(L1, a)) == pytest.approx(H, rel=1e-14)
    assert float(a1) + float(a2) == pytest.approx(math.pi)
    b1, b2 = alpha_for_stroke(L1, 2 * L1)
    assert float(b1) == float(b2) == pytest.approx(math.pi / 2)


def test_alpha_for_stroke_too_short():
    with pytest.raises(ParameterError) as ei:
        alpha_for_stroke(0.05, 0.08)
    assert ei.value.parameter == "H" and "2*L1 = 0.1" in str(ei.value)


@pytest.mark.parametrize("alpha", [0.0, math.pi, -0.1, 4.0, float("nan")])
def test_alpha_outside_open_interval(alpha):
    with pytest.raises(ParameterError) as ei:
        inclined_slot(PHI, 0.05, alpha)
    assert ei.value.parameter == "alpha"


def test_bad_L1():
    with pytest.raises(LinkworkError):
        inclined_slot(PHI, -0.05, 1.0)


# --- jamming: an independent static equilibrium of the slider -------------------------------

def _slider_equilibrium(phi1, alpha, f1, f2, F=1.0):
    """Enumerate the Coulomb sign cases of the slider's force balance; return the consistent
    solutions (N, Q) or []. Unknowns: N normal force of the block on the slot along
    n = (-sin a, cos a), Q guide reaction along y.  Friction directions from the kinematics of
    the independent construction (finite differences)."""
    L1 = 1.0
    _, v3, _ = time_derivatives(lambda q: _X3_construction(q, L1, alpha), phi1, 1.0, 0.0)
    _, vrel, _ = time_derivatives(lambda q: slot_positions(q, L1, alpha)["along"], phi1, 1.0, 0.0)
    vx = -v3  # slider velocity along +x
    if abs(vx) < 1e-9 or abs(vrel) < 1e-9:
        return None  # dead position or sliding reversal: friction direction undefined
    sv, sr = math.copysign(1, vx), math.copysign(1, vrel)
    n = np.array([-math.sin(alpha), math.cos(alpha)])
    d = np.array([math.cos(alpha), math.sin(alpha)])
    sols = []
    for sN, sQ in itertools.product((1, -1), (1, -1)):
        # friction on the slot drags it along the block's relative velocity: +f1|N| sr d
        colN = n + f1 * sN * sr * d  # coefficients of N (|N| = sN N)
        colQ = np.array([-f2 * sQ * sv, 1.0])  # guide: normal Q along y, friction -f2|Q| sv x
        A = np.column_stack([colN, colQ])
        rhs = np.array([F * sv, 0.0])  # load F opposes the motion
        if abs(np.linalg.det(A)) < 1e-14:
            continue
        N, Q = np.linalg.solve(A, rhs)
        if sN * N >= 0 and sQ * Q >= 0:
            sols.append((N, Q))
    return sols


@pytest.mark.parametrize("f1,f2", [(0.1, 0.1), (0.15, 0.05), (0.05, 0.3)])
def test_working_range_vs_static_equilibrium(f1, f2):
    lo, hi = working_range(f1, f2)
    assert float(lo) == pytest.approx(math.atan(f1) + math.atan(f2))
    phis = np.linspace(0.01, 2 * np.pi, 181)
    for alpha, should_run in ((float(lo) + 0.01, True), (float(hi) - 0.01, True),
                              (float(lo) - 0.01, False), (float(hi) + 0.01, False)):
        states = [_slider_equilibrium(p, alpha, f1, f2) for p in phis]
        runs = all(s for s in states if s is not None)
        assert runs is should_run, (math.degrees(alpha), should_run)


@pytest.mark.parametrize("alpha_deg", [20, 45, 60, 90, 130, 160])
def test_force_ratio_is_worst_case_of_static_equilibrium(alpha_deg):
    alpha, f1, f2 = math.radians(alpha_deg), 0.1, 0.12
    etas = []
    for p in np.linspace(0.013, 2 * np.pi, 241):
        sols = _slider_equilibrium(p, alpha, f1, f2)
        if sols is None:
            continue
        # the least-|N| consistent solution is what a driven slider needs
        N = min(abs(s[0]) for s in sols)
        etas.append(1.0 / (N * math.sin(alpha)))
    assert min(etas) == pytest.approx(float(force_ratio(alpha, f1, f2)), rel=1e-9)


def test_check_alpha_messages():
    assert float(check_alpha(math.radians(60), 0.1, 0.1)) == pytest.approx(math.radians(60))
    with pytest.raises(ParameterError) as ei:
        check_alpha(math.radians(8), 0.1, 0.1)
    assert "working range (11.42, 168.6) deg" in str(ei.value) and "8 deg" in str(ei.value)


def test_working_range_impossible_friction():
    with pytest.raises(InfeasibleError):
        working_range(1.0, 1.0)
    with pytest.raises(ParameterError):
        working_range(-0.1, 0.1)


def test_extreme_positions_named_fields():
    ep = extreme_positions(math.radians(60))
    assert float(ep.phi1_min) == pytest.approx(math.radians(330))
    assert float(ep.phi1_max) == pytest.approx(math.radians(150))


def test_every_result_field_documented_with_unit():
    import dataclasses
    from pathlib import Path

    from linkwork.models.sine import InclinedSlotResult
    doc = InclinedSlotResult.__doc__ or ""
    nomenclature = (Path(__file__).resolve().parents[2] / "docs" / "nomenclature.md").read_text()
    for f in dataclasses.fields(InclinedSlotResult):
        assert f.name in InclinedSlotResult.units, f.name
        assert f.name in doc, f.name
        if f.name not in ("L1", "alpha", "omega1", "eps1", "phi1", "X_B", "Y_B"):
            assert f"`{f.name}`" in nomenclature, f.name


SINE_DESIGNS = [  # L1, alpha, omega1, eps1
    (0.05, math.radians(90.0), 12.566, 0.0),
    (0.05, math.radians(60.0), 12.566, 40.0),
    (0.08, math.radians(127.0), -9.0, -15.0),
    (0.02, math.radians(25.0), 30.0, 200.0),
]


@pytest.mark.parametrize("L1,alpha,w1,e1", SINE_DESIGNS)
def test_inclined_slot_against_loop_equations(L1, alpha, w1, e1):
    """Reference: the loop equations solved by Newton with complex-step rates
    (tests/_paper000_loop_equations.py). Tolerance: rtol=1e-12, atol=1e-15, _close (RTOL =
    1e-6 relative, floor 1e-9 of the scale)."""
    ext = [alpha - np.pi / 2 + 1e-4, alpha + np.pi / 2 - 1e-4]
    angles = np.array([*ext, 0.0, 0.9, 2.2, 3.6, 5.1])
    res = sine.inclined_slot(angles, L1, alpha, w1, e1)
    r1 = sine.inclined_slot(angles, L1, alpha)
    w = max(abs(w1), 1.0)
    scale = L1 / math.sin(alpha)
    for k, p in enumerate(angles):
        ref = _sine_reference(L1, alpha, w1, e1, p)
        _close(res.X3[k], ref["X3"], scale, "X3")
        _close(res.X32[k], ref["X32"], scale, "X32")
        _close(res.V3[k], ref["V3"], scale * w, "V3")
        _close(res.V32[k], ref["V32"], scale * w, "V32")
        _close(res.a3[k], ref["a3"], scale * (w * w + abs(e1)), "a3")
        _close(res.a32[k], ref["a32"], scale * (w * w + abs(e1)), "a32")
        ref1 = _sine_reference(L1, alpha, 1.0, 0.0, p)
        _close(r1.U31[k], ref1["V3"], scale, "U31")
    # Eq. (14): X3 = L1 (1 - cos phi1) at alpha = 90 deg, X32 = L1 sin phi1
    r90 = sine.inclined_slot(angles, L1, np.pi / 2)
    np.testing.assert_allclose(r90.X3, L1 * (1 - np.cos(angles)), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(r90.X32, L1 * np.sin(angles), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("L1,alpha,w1,e1", SINE_DESIGNS)
def test_sine_stroke_and_extremes_by_search(L1, alpha, w1, e1):
    """Reference: the loop equations solved by Newton with complex-step rates
    (tests/_paper000_loop_equations.py); scipy minimize_scalar. Tolerance: < 1e-5, < 1e-9,
    rel=1e-9, rel=1e-12."""
    def x3(p):
        return _sine_reference(L1, alpha, 1.0, 0.0, p)["X3"]
    grid = np.linspace(0, 2 * np.pi, 361)
    vals = np.array([L1 * (1 - math.cos(p) + math.sin(p) / math.tan(alpha)) for p in grid])
    found = {}
    for sgn, key in ((1.0, "max"), (-1.0, "min")):
        i = int(np.argmax(sgn * vals))
        r = minimize_scalar(lambda p, sgn=sgn: -sgn * x3(p),
                            bounds=(grid[i] - 0.03, grid[i] + 0.03),
                            method="bounded", options={"xatol": 1e-10})
        found[key] = (r.x % (2 * np.pi), x3(r.x))
    ex = sine.extreme_positions(alpha)
    assert abs(math.remainder(float(ex.phi1_max) - found["max"][0], 2 * np.pi)) < 1e-5
    assert abs(math.remainder(float(ex.phi1_min) - found["min"][0], 2 * np.pi)) < 1e-5
    H = found["max"][1] - found["min"][1]
    assert float(sine.stroke(L1, alpha)) == pytest.approx(H, rel=1e-9)
    lo, hi = sine.alpha_for_stroke(L1, H)
    for a_ in (float(lo), float(hi)):
        assert 0 < a_ < np.pi
        gridv = [_sine_reference(L1, a_, 1.0, 0.0, p)["X3"] for p in (a_ - np.pi / 2,
                                                                        a_ + np.pi / 2)]
        assert gridv[1] - gridv[0] == pytest.approx(H, rel=1e-9)
    assert min(abs(float(lo) - alpha), abs(float(hi) - alpha)) < 1e-9
    assert float(lo) + float(hi) == pytest.approx(np.pi, rel=1e-12)


def _slider_load(alpha, f1, f2, sigma):
    """Load P the ram carries against its motion (+x) for block normal force N = 1.

    Newton's law of the ram, written from scratch: unknowns N-direction fixed (N = 1), guide
    normal G, load P.  Block on slot: N n + sigma f1 N d (friction dragging the ram along the
    block's relative sliding direction sigma d), n the slot normal with n_x > 0; guide: G along
    y and friction -f2 |G| along x; load -P along x.
    """
    d = np.array([math.cos(alpha), math.sin(alpha)])
    n = np.array([math.sin(alpha), -math.cos(alpha)])
    fb = n + sigma * f1 * d
    G = -fb[1]
    return fb[0] - f2 * abs(G)


@pytest.mark.parametrize("f1,f2", [(0.12, 0.10), (0.3, 0.05), (0.0, 0.2), (0.5, 0.5)])
def test_working_range_from_ram_equilibrium(f1, f2):
    lo, hi = sine.working_range(f1, f2)

    def worst(a):
        return min(_slider_load(a, f1, f2, s) for s in (1.0, -1.0))
    a_lo = brentq(worst, 1e-6, np.pi / 2, xtol=1e-14)
    a_hi = brentq(worst, np.pi / 2, np.pi - 1e-6, xtol=1e-14)
    assert float(lo) == pytest.approx(a_lo, rel=1e-9)
    assert float(hi) == pytest.approx(a_hi, rel=1e-9)
    for a in np.linspace(float(lo) + 1e-3, float(hi) - 1e-3, 7):
        eta = worst(a) / math.sin(a)
        assert float(sine.force_ratio(a, f1, f2)) == pytest.approx(eta, rel=1e-9, abs=1e-12)
    sine.check_alpha(0.5 * (float(lo) + float(hi)), f1, f2)
    with pytest.raises(ParameterError, match="alpha"):
        sine.check_alpha(float(lo) * 0.99, f1, f2)


def _ram_x(phi1: float, L1: float, alpha: float) -> float:
    """x of the slot's crossing with y = 0: the point of the line through B along alpha."""
    bx, by = L1 * math.cos(phi1), L1 * math.sin(phi1)
    d = np.array([math.cos(alpha), math.sin(alpha)])
    # solve B + t d = (x, 0) as a 2x2 system
    _t, x = np.linalg.solve(np.array([[d[0], -1.0], [d[1], 0.0]]), np.array([-bx, -by]))
    return float(x)


SINE_REVIEW = [  # L1, alpha, omega1, eps1, phi0
    (0.043, math.radians(23.0), 9.1, -17.0, 1.2),
    (0.11, math.radians(151.0), -4.4, 33.0, 5.7),
    (0.02, math.radians(97.0), 50.0, 0.0, 3.3),
]


@pytest.mark.parametrize("L1,alpha,w1,e1,phi0", SINE_REVIEW)
def test_inclined_slot_against_construction_and_time_differences(L1, alpha, w1, e1, phi0):
    """Reference: the geometric construction of tests/_paper000_geometry.py; central finite
    differences. Tolerance: rel=1e-12, abs=1e-15, rel=1e-7, rel=1e-5, abs=1e-3."""
    res = sine.inclined_slot(phi0, L1, alpha, w1, e1)
    x0 = _ram_x(0.0, L1, alpha)  # ram position at phi1 = 0 (X3 = 0 there)
    ram = lambda t: x0 - _ram_x(_crank_phi(t, phi0, w1, e1), L1, alpha)  # noqa: E731
    assert float(res.X3) == pytest.approx(ram(0.0), rel=1e-12, abs=1e-15)
    v, a = _time_derivs(ram, 0.0, h=1e-4 / abs(w1))
    assert float(res.V3) == pytest.approx(v, rel=1e-7)
    assert float(res.a3) == pytest.approx(a, rel=1e-5)
    # block in the slot: distance along d from the crossing point to the crank pin
    blk = lambda t: ((L1 * math.sin(_crank_phi(t, phi0, w1, e1)))  # noqa: E731
                     / math.sin(alpha))
    assert float(res.X32) == pytest.approx(blk(0.0), rel=1e-12, abs=1e-15)
    v, a = _time_derivs(blk, 0.0, h=1e-4 / abs(w1))
    assert float(res.V32) == pytest.approx(v, rel=1e-7)
    assert float(res.a32) == pytest.approx(a, rel=1e-5)
    # stroke and extremes by a dense scan of the construction
    grid = np.linspace(0.0, 2 * math.pi, 20001)
    xs = np.array([x0 - _ram_x(p, L1, alpha) for p in grid])
    assert float(sine.stroke(L1, alpha)) == pytest.approx(np.ptp(xs), rel=1e-7)
    ext = sine.extreme_positions(alpha)
    assert math.remainder(float(ext.phi1_max) - grid[np.argmax(xs)], 2 * math.pi) == \
        pytest.approx(0.0, abs=1e-3)
    assert math.remainder(float(ext.phi1_min) - grid[np.argmin(xs)], 2 * math.pi) == \
        pytest.approx(0.0, abs=1e-3)


def test_working_range_against_direct_statics():
    """Slider statics solved as a linear system: jamming exactly at alpha = rho1 + rho2."""
    f1, f2 = 0.17, 0.08

    def load_over_normal(alpha: float, sigma: float) -> float:
        # block pushes the slider with N along n = (sin a, -cos a) plus friction sigma f1 N d;
        # the guide reacts with Ny (normal) and friction -f2 |Ny| against +x motion; F the load.
        n = np.array([math.sin(alpha), -math.cos(alpha)])
        d = np.array([math.cos(alpha), math.sin(alpha)])
        push = n + sigma * f1 * d
        return push[0] - f2 * abs(push[1])

    lo, hi = sine.working_range(f1, f2)
    grid = np.linspace(1e-3, math.pi - 1e-3, 200001)
    worst = np.minimum(*[np.array([load_over_normal(a, s) for a in grid[::50]])
                         for s in (1.0, -1.0)])
    ok = grid[::50][worst > 0]
    assert ok.min() == pytest.approx(float(lo), abs=2e-3)
    assert ok.max() == pytest.approx(float(hi), abs=2e-3)


def test_alpha_for_stroke_shape_mismatch_is_named():
    with pytest.raises(ParameterError, match=r"shapes.*L1.*H"):
        sine.alpha_for_stroke(np.full(2, 0.05), np.full(3, 0.2))
    lo, hi = sine.alpha_for_stroke(np.array([[0.05], [0.04]]), np.array([0.2, 0.1]))
    np.testing.assert_allclose(2 * np.array([[0.05], [0.04]]) / np.sin(lo), [[0.2, 0.1]] * 2)
    np.testing.assert_allclose(lo + hi, np.pi)


def test_force_ratio_curve_is_positive_exactly_inside_the_working_range():
    """Reference: the curve samples :func:`sine.force_ratio`, and the working range of
    :func:`sine.working_range` is where it is positive (the jamming limits: eta = 0 there, the
    closed form sin(alpha - rho1 - rho2) = 0 of docs/sine_press.md). Tolerance: one sample."""
    curve = sine.force_ratio_curve(0.1, 0.12, n=2001)
    np.testing.assert_array_equal(curve.eta, sine.force_ratio(curve.slot_angle, 0.1, 0.12))
    lo, hi = curve.working
    inside = (curve.slot_angle > lo) & (curve.slot_angle < hi)
    step = curve.slot_angle[1] - curve.slot_angle[0]
    clear = (np.abs(curve.slot_angle - lo) > step) & (np.abs(curve.slot_angle - hi) > step)
    np.testing.assert_array_equal((curve.eta > 0)[clear], inside[clear])
    assert abs(lo - (np.arctan(0.1) + np.arctan(0.12))) < 1e-12
