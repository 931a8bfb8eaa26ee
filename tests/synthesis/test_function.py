"""Function generation (linkwork.synthesis.function).

Checks: the output at the precision points equals the wanted one (1e-9 rad / 1e-9 of the
stroke), recomputed through the planar engine (the design's mechanism(), not the closed form
the synthesis used); the reported structural error over the range equals the engine's
(1e-9); planted functions (the output of a known linkage) are recovered by least squares
(structural error below 1e-8 rad, lengths to 1e-6); bad input is named.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork.errors import InfeasibleError, ParameterError
from linkwork.models.crank_slider import offset_crank_slider
from linkwork.models.fourbar import fourbar
from linkwork.planar.kinematics import kinematics
from linkwork.synthesis.function import (
    chebyshev_spacing,
    crank_slider_function,
    fourbar_function,
)

DEG = math.pi / 180


def _engine_output(design, phi):
    mech = design.mechanism()
    kin = kinematics(mech, phi)
    if design.kind == "fourbar":
        return kin.angle("rocker")
    return kin.point("slider", "B").y - design.params["Y0"]


def test_chebyshev_spacing_of_three_points():
    # Norton Eq. (5.40): x_j = (a+b)/2 - (b-a)/2 cos((2j-1) pi / 2n)
    x = chebyshev_spacing(1.0, 10.0, 3)
    assert np.allclose(x, [5.5 - 4.5 * math.cos(math.pi / 6), 5.5, 5.5 + 4.5 * math.cos(
        math.pi / 6)], rtol=1e-15)


def test_log_function_precision_points_are_met_through_the_engine():
    res = fourbar_function(np.log10, (1.0, 10.0), (30 * DEG, 60 * DEG), (110 * DEG, 60 * DEG))
    cheb = next(d for d in res.designs if d.precision_inputs is not None)
    xp = chebyshev_spacing(1.0, 10.0, 3)
    want = 110 * DEG + 60 * DEG * np.log10(xp)
    out = _engine_output(cheb, cheb.precision_inputs)
    assert np.allclose(np.mod(out - want + math.pi, 2 * math.pi) - math.pi, 0, atol=1e-9)
    # the structural error over the range, recomputed by the engine
    eng = _engine_output(cheb, cheb.input)
    err = np.mod(eng - cheb.wanted + math.pi, 2 * math.pi) - math.pi
    assert np.allclose(err, cheb.structural_error, atol=1e-9)
    assert cheb.max_error < 2 * DEG
    # least squares refined on the structural error does not do worse in the max or RMS
    assert min(d.max_error for d in res.designs) <= cheb.max_error


def test_planted_fourbar_function_is_recovered():
    """The rocker angle of a known four-bar as the function: least squares recovers it
    (structural error 1e-9 rad, lengths 1e-9)."""
    a, b, c, d = 0.4, 1.1, 0.9, 1.0

    def f(x):  # x: the crank angle in degrees; y: the rocker angle [rad]
        return fourbar(np.radians(np.asarray(x, dtype=float)), a, b, c, d).theta4

    psi0, psi1 = f(np.array([40.0, 130.0]))
    res = fourbar_function(f, (40.0, 130.0), (40 * DEG, 90 * DEG),
                           (float(psi0), float(psi1 - psi0)), d=1.0, n_least_squares=61)
    best = res.best
    assert best.max_error < 1e-9
    assert best.params["a"] == pytest.approx(a, rel=1e-9)
    assert best.params["b"] == pytest.approx(b, rel=1e-9)
    assert best.params["c"] == pytest.approx(c, rel=1e-9)


def test_planted_crank_slider_function_is_recovered():
    """The slide of a known offset crank-slider (paper 000's model) as the function."""
    L1, L2, e = 0.05, 0.2, 0.02

    def Y(x):
        return offset_crank_slider(np.radians(np.asarray(x, dtype=float)), L1, L2 / L1,
                                   e / L1).Y_C

    Ya, Yb = Y(np.array([20.0, 110.0]))
    stroke = float(Yb - Ya)
    res = crank_slider_function(lambda x: Y(x) - Ya, (20.0, 110.0), (20 * DEG, 90 * DEG),
                                stroke, datum=float(Ya), n_least_squares=61)
    best = res.best
    assert best.max_error < 1e-9 * abs(stroke)
    assert best.params["L1"] == pytest.approx(L1, rel=1e-9)
    assert best.params["L2"] == pytest.approx(L2, rel=1e-9)
    assert best.params["e"] == pytest.approx(e, rel=1e-9)
    eng = _engine_output(best, best.input)
    assert np.allclose(eng - best.wanted, best.structural_error, atol=1e-9 * abs(stroke))


def test_crank_slider_with_free_datum_meets_its_precision_points():
    res = crank_slider_function(np.sqrt, (1.0, 4.0), (30 * DEG, 120 * DEG), 0.08)
    cheb = next(d for d in res.designs if d.precision_inputs is not None)
    out = _engine_output(cheb, cheb.precision_inputs)
    xp = chebyshev_spacing(1.0, 4.0, 3)
    want = 0.08 * (np.sqrt(xp) - 1.0)
    assert np.allclose(out, want, atol=1e-9 * 0.08)


def test_bad_input_is_named():
    with pytest.raises(ParameterError, match="too few"):
        fourbar_function(np.log10, (1, 10), (0.5, 1.0), (2.0, 1.0), n_points=2)
    with pytest.raises(ParameterError, match="phi_range"):
        fourbar_function(np.log10, (1, 10), (0.5, 7.0), (2.0, 1.0))
    with pytest.raises(ParameterError, match="x_range"):
        fourbar_function(np.log10, (1, 1), (0.5, 1.0), (2.0, 1.0))
    with pytest.raises(InfeasibleError, match="defect-free four-bar"):
        # a rocker turning 170 deg while the crank turns 10: no four-bar does that
        fourbar_function(lambda x: x, (0.0, 1.0), (0.0, 10 * DEG), (0.0, 170 * DEG))


def test_design_file_reads_back(tmp_path):
    from linkwork import io

    res = fourbar_function(np.log10, (1.0, 10.0), (30 * DEG, 60 * DEG), (110 * DEG, 60 * DEG))
    f = res.best.to_toml(tmp_path / "f.toml")
    doc = io.load(f)
    kin = kinematics(doc.mechanism(), res.best.input)
    assert np.allclose(kin.angle("rocker"), _engine_output(res.best, res.best.input), atol=1e-12)


def test_free_start_angles_are_searched():
    res = fourbar_function(np.log10, (1.0, 10.0), (None, 60 * DEG), (None, 60 * DEG))
    assert res.best.max_error < 0.1 * DEG
    assert res.input_range[1] == pytest.approx(60 * DEG)
