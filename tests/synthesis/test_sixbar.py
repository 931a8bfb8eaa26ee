"""Six-bar path generation through the engine (linkwork.synthesis.sixbar).

The coupler point of the engine model is compared with an independent construction (the
four-bar closed form of the path module for C, a circle intersection for D with the engine's
branch rule, then P on CD) to 1e-12; a planted Stephenson III six-bar is recovered (targets with
timing, bounds 5 % around it) to an error below 1e-20 of the squared path size; the design's
planar file gives the targets back through the engine.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork import io
from linkwork.errors import ParameterError
from linkwork.planar.kinematics import kinematics
from linkwork.synthesis import sixbar as S
from linkwork.synthesis.design import coupler_point

P = dict(r1=4.0, r2=1.0, r3=3.5, r4=3.0, x0=0.0, y0=0.0, theta0=0.0, cx=1.5, cy=1.5, r5=3.5,
         r6=3.0, x6=4.0, y6=4.0, px=1.0, py=0.5)
X = np.array([P[k] for k in S.SIXBAR_PARAMS])


def _reference(th, br=(1, 1)):
    """Stephenson III: C on the coupler by the four-bar closed form, D by intersecting the
    circles (C, r5) and (O6, r6) on the left of C -> O6 for branch +1, P on CD."""
    four = dict(r1=P["r1"], r2=P["r2"], r3=P["r3"], r4=P["r4"], rcx=P["cx"], rcy=P["cy"],
                x0=P["x0"], y0=P["y0"], theta0=P["theta0"])
    cx, cy, ok = coupler_point(th, four, br[0])
    assert ok.all()
    C = np.c_[cx, cy]
    O6 = np.array([P["x6"], P["y6"]])
    s = O6 - C
    f = np.hypot(s[:, 0], s[:, 1])
    a = (P["r5"] ** 2 - P["r6"] ** 2 + f ** 2) / (2 * f)
    h = np.sqrt(P["r5"] ** 2 - a ** 2)
    e = s / f[:, None]
    left = np.c_[-e[:, 1], e[:, 0]]
    D = C + a[:, None] * e + br[1] * h[:, None] * left
    u = (D - C) / P["r5"]
    return C + P["px"] * u + P["py"] * np.c_[-u[:, 1], u[:, 0]]


def test_engine_coupler_point_equals_an_independent_construction():
    th = np.linspace(0.0, 2 * math.pi, 37)
    for br in ((1, 1), (1, -1)):
        x, y, ok = S.coupler_points(X[None, :], np.array([br]), th, "stephenson")
        assert ok.all()
        ref = _reference(th, br)
        assert np.allclose(x[0], ref[:, 0], atol=1e-12) and np.allclose(y[0], ref[:, 1],
                                                                          atol=1e-12)


def test_planted_stephenson_sixbar_is_recovered(tmp_path):
    th = np.linspace(0.3, 5.0, 8)
    pts = _reference(th)
    b = {k: (0.95 * v, 1.05 * v) if v > 0 else (v - 0.05, v + 0.05) for k, v in P.items()}
    res = S.sixbar_path(pts, timing=th, bounds=b, seed=0, n_candidates=128, n_refine=2)
    L = float(np.hypot(*np.ptp(pts, axis=0)))
    assert res.best.error < 1e-20 * L * L
    assert res.candidate_points_per_second > 0
    f = res.best.to_toml(tmp_path / "six.toml")
    doc = io.load(f)
    kin = kinematics(doc.mechanism(), th + res.best.params["theta0"])
    Q = kin.point("link5", "P")
    assert np.allclose(Q.x, pts[:, 0], atol=1e-9 * L) and np.allclose(Q.y, pts[:, 1],
                                                                      atol=1e-9 * L)


def test_bad_kind_and_bounds():
    pts = _reference(np.linspace(0.3, 5.0, 4))
    with pytest.raises(ParameterError, match="kind"):
        S.sixbar_path(pts, kind="klann")
    with pytest.raises(ParameterError, match="unknown parameter"):
        S.sixbar_path(pts, bounds={"r9": (1, 2)})
