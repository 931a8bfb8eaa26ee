"""Offset crank-slider (paper 000, idle mode) against an independent construction and FDs."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from _paper000_geometry import crank_slider_positions, time_derivatives, unwrap_pair
from _strategies import reals
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

from linkwork.errors import AssemblyError, LinkworkError, ParameterError
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
    assert float(r.X_C) == pytest.approx(lame * L1, abs=1e-15)
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
def test_fast_path_equals_the_checked_path_exactly(L1, lam2, lame, w1, e1, branch,
                                                  monkeypatch):
    """One design in Python floats over a float64 array takes a path with plain comparisons
    instead of the named checks; the same call with numpy scalars and a list of angles takes
    the checked path.  Both run the same arithmetic, so every field must be bit-identical."""
    from linkwork.models import crank_slider as cs

    paths = []
    evaluate = cs._evaluate

    def spy(*args):
        paths.append("checked" if args[-1] is not None else "fast")
        return evaluate(*args)

    monkeypatch.setattr(cs, "_evaluate", spy)
    fast = offset_crank_slider(PHI, L1, lam2, lame, w1, e1, branch)
    checked = offset_crank_slider(list(PHI), np.float64(L1), np.float64(lam2), np.float64(lame),
                                  np.float64(w1), np.float64(e1), branch)
    assert paths == ["fast", "checked"]
    for name, val in vars(fast).items():
        np.testing.assert_array_equal(np.asarray(val), np.asarray(getattr(checked, name)),
                                      err_msg=name)
    ints = offset_crank_slider(PHI, 1, 4, 0, 3, 2, branch)       # ints are numbers too
    ref = offset_crank_slider(PHI, 1.0, 4.0, 0.0, 3.0, 2.0, branch)
    np.testing.assert_array_equal(ints.a_C, ref.a_C)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_angle_on_the_fast_path_is_named_without_warnings(bad):
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
