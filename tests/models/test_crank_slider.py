"""Offset crank-slider (paper 000, idle mode) against an independent construction and FDs."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from _paper000_geometry import (
    _crank_phi,
    _time_derivs,
    crank_slider_positions,
    time_derivatives,
    unwrap_pair,
)
from _paper000_loop_equations import DEV, RTOL, _close, _cs_reference
from _strategies import reals
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq, minimize_scalar

from linkwork.errors import AssemblyError, LinkworkError, ParameterError
from linkwork.models import crank_slider, sine
from linkwork.models import crank_slider as cs
from linkwork.models import crank_slider as cs_model
from linkwork.models.crank_slider import (
    dead_centres,
    max_pressure_angle,
    offset_crank_slider,
    pressure_angle,
    stroke,
)

PHI = np.linspace(0.0, 2 * np.pi, 73)
DESIGNS = [  # L1 [m], lambda2, lambda_e, omega1 [rad/s], eps1 [rad/s^2], branch
    (0.05, 4.0, 0.5, 12.566, 0.0, 1),
    (0.05, 4.0, 0.5, 12.566, 35.0, 1),
    (0.12, 2.6, -1.3, -7.0, -20.0, 1),
    (0.03, 3.0, 0.8, 20.0, 150.0, -1),
    (1.0, 1.6, 0.0, 1.0, 1.0, 1),
]


def _rel(a, b, scale):
    return abs(a - b) / scale


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch", DESIGNS)
def test_positions_match_independent_construction(L1, lam2, lame, w1, e1, branch):
    """Reference: the geometric construction of tests/_paper000_geometry.py. Tolerance: < 1e-11,
    rel=1e-12, abs=1e-13 * L1, rel=1e-14, abs=1e-15, abs=1e-15 * L1, abs=1e-7."""
    r = offset_crank_slider(PHI, L1, lam2, lame, w1, e1, branch)
    for i, p in enumerate(PHI):
        g = crank_slider_positions(p, L1, lam2, lame, branch)
        assert r.Y_C[i] == pytest.approx(g["Y_C"], rel=1e-12, abs=1e-13 * L1)
        assert r.X_C[i] == pytest.approx(g["X_C"], rel=1e-14, abs=1e-15)
        assert r.X_B[i] == pytest.approx(g["X_B"], abs=1e-15 * L1)
        assert abs(unwrap_pair(r.phi2[i], g["phi2"])) < 1e-11
        assert r.pressure_angle[i] == pytest.approx(g["mu"], abs=1e-7)


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch", DESIGNS)
def test_velocities_accelerations_match_time_differences_of_construction(
        L1, lam2, lame, w1, e1, branch):
    """omega2, eps2, V_C, a_C (with eps1 != 0) vs d/dt of the constructed positions."""
    phis = PHI[:-1:4]
    r = offset_crank_slider(phis, L1, lam2, lame, w1, e1, branch)
    vscale = abs(w1) * L1 + abs(e1) * L1 * 1e-3
    ascale = (w1 * w1 + abs(e1)) * L1
    for i, p in enumerate(phis):
        _, v, a = time_derivatives(
            lambda q: crank_slider_positions(q, L1, lam2, lame, branch)["Y_C"], p, w1, e1)
        ref_phi2 = crank_slider_positions(p, L1, lam2, lame, branch)["phi2"]
        _, w2, eps2 = time_derivatives(
            lambda q, ref=ref_phi2: ref + unwrap_pair(
                ref, crank_slider_positions(q, L1, lam2, lame, branch)["phi2"]), p, w1, e1)
        assert _rel(r.V_C[i], v, vscale) < 1e-7
        assert _rel(r.a_C[i], a, ascale) < 1e-6
        assert _rel(r.omega2[i], w2, abs(w1)) < 1e-7
        assert _rel(r.eps2[i], eps2, w1 * w1 + abs(e1)) < 1e-6


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch", DESIGNS)
def test_transfer_functions_match_finite_differences_of_position_functions(
        L1, lam2, lame, w1, e1, branch):
    """U21, V_qC, eps_q2, a_qC vs phi1-differences of the model's own phi2 and Y_C."""
    h = 1e-4
    r = offset_crank_slider(PHI, L1, lam2, lame, branch=branch)
    rp = offset_crank_slider(PHI + h, L1, lam2, lame, branch=branch)
    rm = offset_crank_slider(PHI - h, L1, lam2, lame, branch=branch)
    dphi2_p = np.angle(np.exp(1j * (rp.phi2 - r.phi2)))
    dphi2_m = np.angle(np.exp(1j * (r.phi2 - rm.phi2)))
    np.testing.assert_allclose(r.U21, (dphi2_p + dphi2_m) / (2 * h), rtol=0, atol=1e-7)
    np.testing.assert_allclose(r.eps_q2, (dphi2_p - dphi2_m) / h**2, rtol=0, atol=2e-5)
    np.testing.assert_allclose(r.V_qC, (rp.Y_C - rm.Y_C) / (2 * h), rtol=0, atol=1e-8 * L1)
    np.testing.assert_allclose(r.a_qC, (rp.Y_C - 2 * r.Y_C + rm.Y_C) / h**2, rtol=0,
                               atol=2e-5 * L1)
    np.testing.assert_allclose(r.eps_q2, (rp.U21 - rm.U21) / (2 * h), rtol=0, atol=1e-6)


def test_broadcast_designs_against_angles():
    L1 = np.array([[0.05], [0.08], [0.1]])
    lam2 = np.array([[4.0], [3.0], [5.0]])
    lame = np.array([[0.5], [-0.4], [1.0]])
    r = offset_crank_slider(PHI, L1, lam2, lame, 10.0, 3.0)
    assert r.Y_C.shape == (3, PHI.size)
    for k in range(3):
        one = offset_crank_slider(PHI, L1[k, 0], lam2[k, 0], lame[k, 0], 10.0, 3.0)
        for name in ("phi2", "Y_C", "U21", "V_qC", "eps_q2", "a_C", "eps2", "V_C"):
            np.testing.assert_array_equal(getattr(r, name)[k], getattr(one, name))


def test_scalar_input_gives_scalar_shaped_result():
    r = offset_crank_slider(0.3, 0.05, 4.0, 0.5)
    g = crank_slider_positions(0.3, 0.05, 4.0, 0.5)
    assert np.shape(r.Y_C) == () and float(r.Y_C) == pytest.approx(g["Y_C"], rel=1e-13)


@settings(max_examples=80, deadline=None)
@given(phi1=reals(-10, 10), L1=st.floats(1e-3, 2.0), lame=reals(-3, 3),
       extra=st.floats(0.01, 5.0), branch=st.sampled_from([1, -1]))
def test_property_loop_closure(phi1, L1, lame, extra, branch):
    lam2 = abs(lame) + 1.0 + extra
    r = offset_crank_slider(phi1, L1, lam2, lame, branch=branch)
    B = np.array([L1 * math.cos(phi1), L1 * math.sin(phi1)])
    C = np.array([float(r.X_C), float(r.Y_C)])
    rod = lam2 * L1 * np.array([math.sin(float(r.phi2)), math.cos(float(r.phi2))])
    np.testing.assert_allclose(B + rod, C, atol=1e-12 * (1 + lam2) * L1)
    assert math.hypot(*(C - B)) == pytest.approx(lam2 * L1, rel=1e-12)
    assert float(r.X_C) == pytest.approx(lame * L1, rel=1e-15, abs=1e-15 * L1)
    assert branch * math.cos(float(r.phi2)) > 0


@settings(max_examples=60, deadline=None)
@given(phi1=reals(0, 2 * np.pi), lame=reals(-2, 2), extra=st.floats(0.05, 4.0),
       w1=reals(-30, 30), e1=reals(-100, 100))
def test_property_velocity_is_chain_rule_of_transfer_function(phi1, lame, extra, w1, e1):
    """Velocity closure: d/dt (B + BC) has zero X component and Y component V_C."""
    L1, lam2 = 0.07, abs(lame) + 1.0 + extra
    r = offset_crank_slider(phi1, L1, lam2, lame, w1, e1)
    vB = w1 * L1 * np.array([-math.sin(phi1), math.cos(phi1)])
    p2 = float(r.phi2)
    vBC = lam2 * L1 * float(r.omega2) * np.array([math.cos(p2), -math.sin(p2)])
    np.testing.assert_allclose(vB + vBC, [0.0, float(r.V_C)], atol=1e-10 * (1 + abs(w1)))


def test_assembly_error_lists_ranges():
    """lambda2 = 1.2 < |lambda_e| + 1 = 1.5: fails where |0.5 - cos phi1| >= 1.2,
    i.e. cos phi1 <= -0.7, phi1 in [134.43, 225.57] deg."""
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    with pytest.raises(AssemblyError) as ei:
        offset_crank_slider(phi, 0.05, 1.2, 0.5)
    (lo, hi), = ei.value.ranges
    assert math.degrees(lo) == pytest.approx(135.0) and math.degrees(hi) == pytest.approx(225.0)
    assert "lambda2 = 1.2" in str(ei.value) and "1.5" in str(ei.value)
    assert isinstance(ei.value, ValueError) and isinstance(ei.value, LinkworkError)


def test_assembly_nan_mode_masks_bad_positions():
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    r = offset_crank_slider(phi, 0.05, 1.2, 0.5, on_failure="nan")
    expected_bad = np.abs(0.5 - np.cos(phi)) >= 1.2
    np.testing.assert_array_equal(~r.valid, expected_bad)
    assert np.isnan(r.Y_C[expected_bad]).all() and np.isfinite(r.Y_C[~expected_bad]).all()


def test_assembly_limit_exact_is_locked():
    """lambda2 == |lambda_e| + 1: the rod is perpendicular to the guide at phi1 = pi."""
    with pytest.raises(AssemblyError):
        offset_crank_slider(np.array([0.0, np.pi]), 0.05, 1.5, 0.5)
    r = offset_crank_slider(np.array([0.0, np.pi / 2]), 0.05, 1.5, 0.5)
    assert np.isfinite(r.a_C).all()


@pytest.mark.parametrize("kw,name", [
    ({"L1": -0.05}, "L1"), ({"L1": 0.0}, "L1"), ({"lambda2": -4.0}, "lambda2"),
    ({"lambda_e": float("nan")}, "lambda_e"), ({"branch": 0}, "branch"),
    ({"omega1": float("inf")}, "omega1"),
])
def test_bad_parameters(kw, name):
    args = {"phi1": PHI, "L1": 0.05, "lambda2": 4.0, "lambda_e": 0.5} | kw
    with pytest.raises(ParameterError) as ei:
        offset_crank_slider(**args)
    assert ei.value.parameter == name


@pytest.mark.parametrize("lam2,lame,branch", [(4.0, 0.5, 1), (2.6, -1.3, 1), (3.0, 0.8, -1),
                                              (1.6, 0.0, 1)])
def test_stroke_and_dead_centres_vs_numerical_extremes(lam2, lame, branch):
    L1 = 0.05

    def y(p):
        return crank_slider_positions(p, L1, lam2, lame, branch)["Y_C"]

    grid = np.linspace(0, 2 * np.pi, 721)
    ys = np.array([y(p) for p in grid])
    top = minimize_scalar(lambda p: -y(p), bracket=(grid[ys.argmax()] - 0.05,
                                                   grid[ys.argmax()], grid[ys.argmax()] + 0.05),
                          tol=1e-12)
    bot = minimize_scalar(y, bracket=(grid[ys.argmin()] - 0.05, grid[ys.argmin()],
                                      grid[ys.argmin()] + 0.05), tol=1e-12)
    assert float(stroke(L1, lam2, lame)) == pytest.approx(-top.fun - bot.fun, rel=1e-10)
    p_top, p_bot = dead_centres(lam2, lame, branch)
    assert abs(unwrap_pair(float(p_top), top.x)) < 1e-5
    assert abs(unwrap_pair(float(p_bot), bot.x)) < 1e-5
    r = offset_crank_slider(np.array([p_top, p_bot]), L1, lam2, lame, branch=branch)
    np.testing.assert_allclose(r.V_qC, 0.0, atol=1e-14)
    assert float(r.Y_C[0]) == pytest.approx(-top.fun, rel=1e-12)


def test_stroke_zero_offset_is_twice_crank():
    assert float(stroke(0.05, 4.0, 0.0)) == pytest.approx(0.1, rel=1e-14)


def test_stroke_rejects_short_rod():
    with pytest.raises(ParameterError, match="lambda2"):
        stroke(0.05, 1.4, 0.5)


def test_pressure_angle_max():
    phi = np.linspace(0, 2 * np.pi, 3601)
    mu = pressure_angle(phi, 4.0, 0.5)
    assert float(mu.max()) == pytest.approx(float(max_pressure_angle(4.0, 0.5)), rel=1e-9)
    assert float(max_pressure_angle(4.0, 0.5)) == pytest.approx(math.asin(1.5 / 4.0))


def test_result_exports(tmp_path):
    r = offset_crank_slider(PHI, 0.05, 4.0, 0.5, 12.0, 1.0)
    d = r.to_dict()
    assert d["units"]["a_C"] == "m/s^2" and len(d["columns"]["Y_C"]) == PHI.size
    text = r.to_csv(tmp_path / "c.csv").read_text().splitlines()
    assert text[0].startswith("phi1 [rad]") and len(text) == PHI.size + 1


def test_dead_centres_named_fields():
    dc = dead_centres(4.0, 0.5)
    r = offset_crank_slider(np.array([dc.phi1_top, dc.phi1_bottom]), 0.05, 4.0, 0.5)
    assert r.Y_C[0] > r.Y_C[1]
    assert float(r.Y_C[0] - r.Y_C[1]) == pytest.approx(float(stroke(0.05, 4.0, 0.5)), rel=1e-12)


def test_every_result_field_documented_with_unit():
    import dataclasses

    from linkwork.models.crank_slider import CrankSliderResult
    doc = CrankSliderResult.__doc__ or ""
    nomenclature = (Path(__file__).resolve().parents[2] / "docs" / "nomenclature.md").read_text()
    for f in dataclasses.fields(CrankSliderResult):
        assert f.name in CrankSliderResult.units, f.name
        assert f.name in doc, f.name
        if f.name not in ("valid", "branch", "L1", "lambda2", "lambda_e", "omega1", "eps1",
                          "phi1"):
            assert f"`{f.name}`" in nomenclature, f.name


def test_phi2_ranges_and_continuity_per_branch():
    phi = np.linspace(0, 2 * np.pi, 721)
    up = offset_crank_slider(phi, 0.05, 3.0, 0.8, branch=1)
    down = offset_crank_slider(phi, 0.05, 3.0, 0.8, branch=-1)
    assert np.all(np.abs(up.phi2) < np.pi / 2)
    assert np.all((down.phi2 > np.pi / 2) & (down.phi2 < 1.5 * np.pi))
    for r in (up, down):
        assert np.abs(np.diff(r.phi2)).max() < 0.01  # no wrap-around jumps over the cycle
    # mirror assembly: the rod direction is reflected in the horizontal line through B
    np.testing.assert_allclose(np.sin(down.phi2), np.sin(up.phi2), atol=1e-15)
    np.testing.assert_allclose(np.cos(down.phi2), -np.cos(up.phi2), atol=1e-15)


@settings(max_examples=60, deadline=None)
@given(phi1=reals(0, 2 * np.pi), lame=reals(-2, 2), extra=st.floats(0.2, 4.0),
       branch=st.sampled_from([1, -1]))
def test_property_transfer_functions_are_derivatives(phi1, lame, extra, branch):
    """Random designs: U21, V_qC, eps_q2, a_qC equal central differences of phi2 and Y_C."""
    L1, lam2, h = 0.05, abs(lame) + 1.0 + extra, 1e-4
    r, rp, rm = (offset_crank_slider(phi1 + d, L1, lam2, lame, branch=branch)
                 for d in (0.0, h, -h))
    scale = 1.0 + abs(float(r.U21))
    assert abs(float(r.U21) - float(rp.phi2 - rm.phi2) / (2 * h)) < 1e-6 * scale
    assert abs(float(r.V_qC) - float(rp.Y_C - rm.Y_C) / (2 * h)) < 1e-6 * L1 * scale
    assert abs(float(r.eps_q2) - float(rp.U21 - rm.U21) / (2 * h)) < 1e-5 * scale**3
    assert abs(float(r.a_qC) - float(rp.V_qC - rm.V_qC) / (2 * h)) < 1e-5 * L1 * scale**3


@pytest.mark.parametrize("phi1", [np.linspace(0.0, 2 * np.pi, 37), np.array([]), 0.7])
def test_fast_assembled_result_is_the_dataclass_built_by_its_init(phi1):
    """offset_crank_slider builds its result with Result._assemble (no dataclass __init__):
    it must carry exactly the dataclass's fields, be frozen, compare equal to the object the
    __init__ builds from the same fields and export alike."""
    import dataclasses

    from linkwork.models.crank_slider import CrankSliderResult
    r = offset_crank_slider(phi1, 0.05, 4.0, 0.3, 10.0, 2.0)
    names = [f.name for f in dataclasses.fields(CrankSliderResult)]
    assert sorted(vars(r)) == sorted(names)
    again = CrankSliderResult(**{n: getattr(r, n) for n in names})
    assert repr(again) == repr(r)
    assert again.to_dict() == r.to_dict()
    assert np.asarray(r.valid).dtype == bool and np.all(r.valid)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.Y_C = 0.0  # type: ignore[misc]


def test_single_position_result_exports(tmp_path):
    r = offset_crank_slider(0.7, 0.05, 4.0, 0.3, 10.0)
    d = r.to_dict()
    assert d["columns"] == {} and d["Y_C"] == pytest.approx(float(r.Y_C))
    rows = (r.to_csv(tmp_path / "one.csv")).read_text().splitlines()
    assert len(rows) == 2 and "Y_C [m]" in rows[0]
    assert float(rows[1].split(",")[rows[0].split(",").index("Y_C [m]")]) == float(r.Y_C)


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch", DESIGNS)
def test_python_numbers_and_numpy_arguments_give_identical_results(L1, lam2, lame, w1, e1,
                                                                   branch):
    """One design in Python floats over a float64 array keeps Python floats in the arithmetic
    (the checks return them as they are); the same call with numpy scalars and a list of angles
    converts them. Both run the same arithmetic, so every field must be bit-identical."""
    fast = offset_crank_slider(PHI, L1, lam2, lame, w1, e1, branch)
    checked = offset_crank_slider(list(PHI), np.float64(L1), np.float64(lam2), np.float64(lame),
                                  np.float64(w1), np.float64(e1), branch)
    for name, val in vars(fast).items():
        np.testing.assert_array_equal(np.asarray(val), np.asarray(getattr(checked, name)),
                                      err_msg=name)
    ints = offset_crank_slider(PHI, 1, 4, 0, 3, 2, branch)       # ints are numbers too
    ref = offset_crank_slider(PHI, 1.0, 4.0, 0.0, 3.0, 2.0, branch)
    np.testing.assert_array_equal(ints.a_C, ref.a_C)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_angle_is_named_without_warnings(bad):
    """pytest turns warnings into errors here: np.cos(inf) must never run."""
    phi = PHI.copy()
    phi[5] = bad
    with pytest.raises(ParameterError) as ei:
        offset_crank_slider(phi, 0.05, 4.0, 0.5, 10.0)
    assert ei.value.parameter == "phi1"


def test_valid_mask_of_a_fully_assembled_cycle_is_shared_and_read_only():
    """Results are immutable: an all-True mask is made once per shape and cannot be written
    through one result into another; a cycle with failing positions gets its own mask."""
    a = offset_crank_slider(PHI, 0.05, 4.0, 0.5)
    b = offset_crank_slider(PHI, 0.07, 3.0, 0.2, 5.0)
    assert a.valid.all() and not a.valid.flags.writeable
    with pytest.raises(ValueError):
        a.valid[0] = False
    assert b.valid.all()
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    c = offset_crank_slider(phi, 0.05, 1.2, 0.5, on_failure="nan")
    assert not c.valid.all() and offset_crank_slider(phi, 0.05, 4.0, 0.5).valid.all()


@pytest.mark.parametrize("lambda_e, words", [(np.nan, "must be finite"),
                                             (None, "must be a number")])
def test_crank_slider_assembly_limit_refuses_non_numbers(lambda_e, words):
    """Was NaN, returned silently; the limit of a real offset is |lambda_e| + 1."""
    with pytest.raises(ParameterError, match=rf"^lambda_e = .*{words}"):
        cs_model.assembly_limit(lambda_e)
    assert cs_model.assembly_limit(-0.5) == 1.5


CS_DESIGNS = [  # L1 [m], lambda2, lambda_e, omega1 [rad/s], eps1 [rad/s^2], branch
    (0.05, 4.0, 0.5, 12.566, 0.0, 1),
    (0.05, 4.0, 0.5, 12.566, 35.0, 1),
    (0.12, 2.6, -1.3, -7.0, -20.0, 1),
    (0.03, 3.0, 0.8, 20.0, 150.0, -1),
]


def _near_dead_centres(lam2, lame, branch):
    # 7 angles: the two dead centres found numerically (+1e-4 rad) and 5 spread angles
    def yc(p, s):
        return s * (math.sin(p) + branch * math.sqrt(lam2**2 - (lame - math.cos(p))**2))
    tops = []
    for s in (1.0, -1.0):
        best = min((minimize_scalar(lambda p, s=s: -yc(p, s), bounds=(b0, b0 + 2.5),
                                    method="bounded", options={"xatol": 1e-12})
                    for b0 in np.linspace(-np.pi, np.pi, 5)), key=lambda r: r.fun)
        tops.append(best.x)
    return [tops[0] + 1e-4, tops[1] - 1e-4, 0.3, 1.7, 2.9, 4.1, 5.5]


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch", CS_DESIGNS)
def test_offset_crank_slider_against_loop_equations(L1, lam2, lame, w1, e1, branch):
    """Reference: the loop equations solved by Newton with complex-step rates
    (tests/_paper000_loop_equations.py). Tolerance: _close (RTOL = 1e-6 relative, floor 1e-9
    of the scale), < 1e-9, rel=1e-12."""
    angles = _near_dead_centres(lam2, lame, branch)
    res = cs.offset_crank_slider(np.array(angles), L1, lam2, lame, w1, e1, branch)
    for k, p in enumerate(angles):
        ref = _cs_reference(L1, lam2, lame, w1, e1, branch, p)
        L = L1
        w = max(abs(w1), 1.0)
        _close(res.Y_C[k], ref["Y_C"], L, "Y_C")
        # phi2 is an angle: compare modulo 2 pi
        d = math.remainder(res.phi2[k] - ref["phi2"], 2 * math.pi)
        assert abs(d) <= 1e-9, ("phi2", res.phi2[k], ref["phi2"])
        _close(res.V_C[k], ref["V_C"], L * w, "V_C")
        _close(res.omega2[k], ref["omega2"], w, "omega2")
        _close(res.a_C[k], ref["a_C"], L * (w * w + abs(e1)), "a_C")
        _close(res.eps2[k], ref["eps2"], w * w + abs(e1), "eps2")
        # transfer functions: the derivatives with respect to phi1 (omega1 = 1, eps1 = 0)
        r1 = _cs_reference(L1, lam2, lame, 1.0, 0.0, branch, p)
        _close(res.V_qC[k], r1["V_C"], L, "V_qC")
        _close(res.U21[k], r1["omega2"], 1.0, "U21")
        _close(res.eps_q2[k], r1["eps2"], 1.0, "eps_q2")
        _close(res.a_qC[k], r1["a_C"], L, "a_qC")
        # conventions: X_C = e, the '+' root for branch=+1 (slider above the pin)
        assert res.X_C[k] == pytest.approx(lame * L1, rel=1e-12)
        assert branch * (res.Y_C[k] - L1 * math.sin(p)) > 0
        # pressure angle: acute angle between rod (B->C) and guide (Y axis)
        bc = np.array([lame * L1 - L1 * math.cos(p), ref["Y_C"] - L1 * math.sin(p)])
        mu = math.acos(abs(bc[1]) / np.hypot(*bc))
        _close(res.pressure_angle[k], mu, 1.0, "pressure_angle")
        _close(cs.pressure_angle(p, lam2, lame), mu, 1.0, "pressure_angle()")


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch", CS_DESIGNS)
def test_crank_slider_stroke_and_dead_centres_by_search(L1, lam2, lame, w1, e1, branch):
    """Reference: the loop equations solved by Newton with complex-step rates
    (tests/_paper000_loop_equations.py); scipy minimize_scalar. Tolerance: < 1e-5, rel=1e-9,
    rel=1e-8, rel=1e-6."""
    def yc(p):
        return float(cs.offset_crank_slider(p, L1, lam2, lame, branch=branch).Y_C)
    # independent: maximise the slider position from the loop equations directly
    def y_ref(p):
        return _cs_reference(L1, lam2, lame, 1.0, 0.0, branch, p)["Y_C"]
    grid = np.linspace(0, 2 * np.pi, 721)
    ys = np.array([L1 * (math.sin(p) + branch * math.sqrt(lam2**2 - (lame - math.cos(p))**2))
                   for p in grid])
    out = {}
    for sgn, key in ((1.0, "top"), (-1.0, "bottom")):
        i = int(np.argmax(sgn * ys))
        r = minimize_scalar(lambda p, sgn=sgn: -sgn * y_ref(p),
                            bounds=(grid[i] - 0.02, grid[i] + 0.02),
                            method="bounded", options={"xatol": 1e-10})
        out[key] = (r.x % (2 * np.pi), y_ref(r.x))
    dc = cs.dead_centres(lam2, lame, branch)
    # the position is stationary there, so the angle is only determined to ~sqrt(eps)
    assert abs(math.remainder(float(dc.phi1_top) - out["top"][0], 2 * np.pi)) < 1e-5
    assert abs(math.remainder(float(dc.phi1_bottom) - out["bottom"][0], 2 * np.pi)) < 1e-5
    assert yc(float(dc.phi1_top)) == pytest.approx(out["top"][1], rel=1e-9)
    assert yc(float(dc.phi1_bottom)) == pytest.approx(out["bottom"][1], rel=1e-9)
    assert float(cs.stroke(L1, lam2, lame)) == pytest.approx(out["top"][1] - out["bottom"][1],
                                                           rel=1e-8)
    # max pressure angle by brute force
    mus = [math.asin(min(1.0, abs(lame - math.cos(p)) / lam2)) for p in grid]
    assert float(cs.max_pressure_angle(lam2, lame)) == pytest.approx(max(mus), rel=1e-6)


def test_assembly_error_lists_the_ranges():
    phi = np.linspace(0, 2 * np.pi, 361)
    with pytest.raises(AssemblyError) as ei:
        cs.offset_crank_slider(phi, 0.05, 1.4, 0.5)
    # the rod (1.4) cannot reach the guide where |0.5 - cos phi| >= 1.4: cos phi <= -0.9
    bad = np.degrees(phi[np.abs(0.5 - np.cos(phi)) >= 1.4])
    rng = ei.value.ranges
    assert rng, "no ranges in the AssemblyError"
    lo, hi = np.degrees(rng[0][0]), np.degrees(rng[-1][1])
    assert lo == pytest.approx(bad.min(), abs=1.01) and hi == pytest.approx(bad.max(), abs=1.01)
    msg = str(ei.value)
    assert "deg" in msg or "rad" in msg
    # on_failure="nan" gives NaN exactly there, with a mask
    r = cs.offset_crank_slider(phi, 0.05, 1.4, 0.5, on_failure="nan")
    assert np.array_equal(~r.valid, np.abs(0.5 - np.cos(phi)) >= 1.4)
    assert np.all(np.isfinite(r.Y_C[r.valid]))


def test_non_broadcasting_inputs_name_the_shapes():
    """Designs that do not broadcast against the angles gave NumPy's bare broadcast error."""
    with pytest.raises(ParameterError, match=r"shapes.*'L1': \(3,\)"):
        cs.offset_crank_slider([0.1, 0.2], [0.05, 0.06, 0.07], 4.0, 0.5)
    with pytest.raises(ParameterError, match=r"shapes.*'L1': \(3,\)"):
        sine.inclined_slot([0.1, 0.2], [0.05, 0.06, 0.07], 1.0)
    assert cs.offset_crank_slider([], 0.05, 4.0, 0.5).Y_C.shape == (0,)
    assert sine.inclined_slot([], 0.05, 1.0).X3.shape == (0,)


CS_QUANTITIES = {"Y_C", "V_C", "omega2", "a_C", "eps2", "V_qC", "U21", "eps_q2", "a_qC",
                 "pressure_angle", "pressure_angle()"}


def test_every_crank_slider_quantity_is_compared_with_the_loop_equations():
    """What the old report (it only printed the largest deviation per quantity) showed, asserted:
    one design (eps1 != 0) run through the loop-equation comparison compares every kinematic
    quantity of ``offset_crank_slider`` and ``pressure_angle`` with the reference of
    tests/_paper000_loop_equations.py, and the largest relative deviation of each is within
    RTOL = 1e-6 (measured: <= 3e-9).  Runs the comparison itself, so it does not depend on the
    order of the tests."""
    DEV.clear()
    test_offset_crank_slider_against_loop_equations(*CS_DESIGNS[1])
    assert set(DEV) == CS_QUANTITIES
    assert max(DEV.values()) <= RTOL, DEV


def _slider_y(phi1: float, L1: float, L2: float, e: float, branch: int) -> float:
    """Y of the slider on the guide X = e: root of |C - B| = L2 on the branch's side of B."""
    bx, by = L1 * math.cos(phi1), L1 * math.sin(phi1)
    f = lambda y: (e - bx) ** 2 + (y - by) ** 2 - L2 * L2  # noqa: E731
    if branch == 1:
        return brentq(f, by, by + L2, xtol=1e-15, rtol=1e-15)
    return brentq(f, by - L2, by, xtol=1e-15, rtol=1e-15)


CS_REVIEW = [  # L1, lambda2, lambda_e, omega1, eps1, branch, phi0
    (0.037, 2.9, -1.3, 7.3, -41.0, 1, 2.61),
    (0.081, 3.3, 0.9, -15.0, 120.0, -1, 4.9),
    (0.012, 5.7, 0.0, 31.0, 7.5, 1, 0.05),
]


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch,phi0", CS_REVIEW)
def test_crank_slider_against_construction_and_time_differences(L1, lam2, lame, w1, e1,
                                                                branch, phi0):
    """Reference: the geometric construction of tests/_paper000_geometry.py; central finite
    differences. Tolerance: rel=1e-12, abs=1e-15, abs=1e-12, rel=1e-7, rel=1e-5."""
    L2, e = lam2 * L1, lame * L1
    res = crank_slider.offset_crank_slider(phi0, L1, lam2, lame, w1, e1, branch)
    y_ref = _slider_y(phi0, L1, L2, e, branch)
    assert float(res.Y_C) == pytest.approx(y_ref, rel=1e-12, abs=1e-15)
    # rod angle from +Y towards +X: atan2(X_C - X_B, Y_C - Y_B)
    phi2_ref = math.atan2(e - L1 * math.cos(phi0), y_ref - L1 * math.sin(phi0))
    assert math.remainder(float(res.phi2) - phi2_ref, 2 * math.pi) == pytest.approx(0, abs=1e-12)
    # motion in time with eps1 != 0: phi1(t) = phi0 + w1 t + e1 t^2 / 2, derivatives at t = 0
    v, a = _time_derivs(lambda t: _slider_y(_crank_phi(t, phi0, w1, e1), L1, L2, e, branch), 0.0,
                        h=1e-4 / abs(w1))
    assert float(res.V_C) == pytest.approx(v, rel=1e-7)
    assert float(res.a_C) == pytest.approx(a, rel=1e-5)

    def rod_angle(t):
        p = _crank_phi(t, phi0, w1, e1)
        return math.atan2(e - L1 * math.cos(p), _slider_y(p, L1, L2, e, branch) - L1 * math.sin(p))

    w2, e2 = _time_derivs(lambda t: np.unwrap([phi2_ref, rod_angle(t)])[1], 0.0, h=1e-4 / abs(w1))
    assert float(res.omega2) == pytest.approx(w2, rel=1e-7)
    assert float(res.eps2) == pytest.approx(e2, rel=1e-5)
    # pressure angle: acute angle between the rod and the guide, computed from the vectors
    rod = np.array([e - L1 * math.cos(phi0), y_ref - L1 * math.sin(phi0)])
    mu = math.acos(abs(rod[1]) / np.linalg.norm(rod))
    assert float(res.pressure_angle) == pytest.approx(mu, abs=1e-12)


@pytest.mark.parametrize("lam2,lame,branch", [(2.9, -1.3, 1), (3.3, 0.9, -1), (2.05, 1.0, -1)])
def test_crank_slider_characteristics_against_a_dense_scan(lam2, lame, branch):
    L1 = 0.037
    grid = np.linspace(0.0, 2 * math.pi, 200001)
    ys = np.array([_slider_y(p, L1, lam2 * L1, lame * L1, branch) for p in grid[::10]])
    g = grid[::10]
    assert float(crank_slider.stroke(L1, lam2, lame)) == pytest.approx(np.ptp(ys), rel=1e-8)
    top, bottom = crank_slider.dead_centres(lam2, lame, branch)
    assert math.remainder(float(top) - g[np.argmax(ys)], 2 * math.pi) == pytest.approx(0, abs=4e-4)
    assert math.remainder(float(bottom) - g[np.argmin(ys)], 2 * math.pi) == pytest.approx(
        0, abs=4e-4)
    mu = np.arcsin(np.abs(lame - np.cos(g)) / lam2)
    assert float(crank_slider.max_pressure_angle(lam2, lame)) == pytest.approx(mu.max(), abs=1e-9)
