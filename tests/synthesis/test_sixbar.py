"""Six-bar path generation (linkwork.synthesis.sixbar).

* The closed form the search screens and refines with (``sixbar_point``) equals the engine
  (``coupler_points``: the planar engine on the design's ``mechanism()``) for Stephenson III and
  Watt II on all four branch pairs, to 1e-12 of the size; the engine's coupler point equals an
  independent construction written here (the four-bar closed form of the path module for C, a
  circle intersection for D with the engine's branch rule, then P on CD) to 1e-12.
* Planted six-bars are recovered from bounds of +-50 % around them (lengths) and +-2 (of a
  path about 4 long; the frame angle over a whole turn), not the 5 % of the first version: the
  Stephenson III with timing and with free timing to an error below 1e-20 of the squared path
  size; the Watt II with timing to 1e-10 (its driving four-bar scaled about O4 leaves the
  rocker's angle and so the path unchanged: a one-parameter family of exact designs along
  which the refinement converges slowly). Each design re-solved by the engine at the targets
  (its planar file read back).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from linkwork import io
from linkwork.errors import InfeasibleError, ParameterError
from linkwork.planar.kinematics import kinematics
from linkwork.synthesis import sixbar as S
from linkwork.synthesis.design import coupler_point

P = dict(r1=4.0, r2=1.0, r3=3.5, r4=3.0, x0=0.0, y0=0.0, theta0=0.0, cx=1.5, cy=1.5, r5=3.5,
         r6=3.0, x6=4.0, y6=4.0, px=1.0, py=0.5)
X = np.array([P[k] for k in S.SIXBAR_PARAMS])
BRANCHES = [(1, 1), (1, -1), (-1, 1), (-1, -1)]
TH = np.linspace(0.3, 5.0, 8)


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


@pytest.mark.parametrize("kind", S.KINDS)
def test_closed_form_equals_the_engine(kind):
    th = np.linspace(0.0, 2 * math.pi, 37)
    Xs = np.array([X, X * np.r_[[1.1, 0.9, 1.0, 1.05], np.ones(11)]])
    for br in BRANCHES:
        b = np.array([br, br])
        x, y, ok = S.sixbar_point(th, Xs, b, kind)
        xe, ye, oke = S.coupler_points(Xs, b, th, kind)
        assert np.array_equal(ok, oke) and ok.any()
        assert np.allclose(x[ok], xe[ok], atol=1e-12 * 4) and np.allclose(y[ok], ye[ok],
                                                                             atol=1e-12 * 4)


@pytest.mark.parametrize("kind", S.KINDS)
def test_the_engines_batch_of_designs_equals_the_closed_form(kind):
    """sixbar.mechanism of arrays over the designs (the engine's batch, one kinematics call for
    all of them) gives the closed form's P and assembly at every crank angle, all four branch
    pairs, to 1e-12 of the size; each design of the batch is the one-design model's."""
    rng = np.random.default_rng(2)
    Xs = X * (1 + 0.05 * rng.standard_normal((48, 15)))
    br = np.array(BRANCHES * 12)
    th = np.linspace(0.0, 2 * math.pi, 37)
    p = {k: Xs[:, i] for i, k in enumerate(S.SIXBAR_PARAMS)}
    batch = S.mechanism(p, kind, (br[:, 0], br[:, 1]))
    assert batch.n_designs == 48
    kin = kinematics(batch, p["theta0"][:, None] + th, on_failure="nan")
    x, y, ok = S.sixbar_point(th, Xs, br, kind)
    assert np.array_equal(np.asarray(kin.valid), ok) and ok.mean() > 0.5
    Q = kin.point("link5", "P")
    assert np.allclose(Q.x[ok], x[ok], atol=1e-12 * 4) and np.allclose(Q.y[ok], y[ok],
                                                                       atol=1e-12 * 4)
    one = dict(zip(S.SIXBAR_PARAMS, map(float, Xs[5]), strict=True))
    alone = kinematics(S.mechanism(one, kind, tuple(br[5])), one["theta0"] + th,
                       on_failure="nan").point("link5", "P")
    assert np.allclose(Q.x[5], alone.x, atol=1e-12 * 4, equal_nan=True)


def _bounds():
    b = {k: (0.5 * v, 1.5 * v) if k in ("r1", "r2", "r3", "r4", "r5", "r6") else (v - 2, v + 2)
         for k, v in P.items()}
    b["theta0"] = (0.0, 2 * math.pi)
    return b


def _targets(kind):
    x, y, ok = S.sixbar_point(TH, X[None, :], [(1, 1)], kind)
    assert ok.all()
    pts = np.c_[x[0], y[0]]
    return pts, float(np.hypot(*np.ptp(pts, axis=0)))


def _engine_reaches(d, pts, L):
    P_ = kinematics(d.mechanism(), d.theta2 + d.params["theta0"]).point("link5", "P")
    assert np.allclose(P_.x, pts[:, 0], atol=1e-9 * L) and np.allclose(P_.y, pts[:, 1],
                                                                       atol=1e-9 * L)


def test_planted_stephenson_with_timing_from_wide_bounds(tmp_path):
    pts, L = _targets("stephenson")
    res = S.sixbar_path(pts, timing=TH, bounds=_bounds(), seed=0, n_candidates=2**13,
                        n_refine=6)
    assert res.best.error < 1e-20 * L * L
    assert np.allclose(np.mod(res.best.theta2, 2 * math.pi), np.mod(TH, 2 * math.pi))
    assert res.candidate_points_per_second > 0 and res.n_evaluated == 2**13
    doc = io.load(res.best.to_toml(tmp_path / "six.toml"))
    kin = kinematics(doc.mechanism(), TH + res.best.params["theta0"])
    Q = kin.point("link5", "P")
    assert np.allclose(Q.x, pts[:, 0], atol=1e-9 * L) and np.allclose(Q.y, pts[:, 1],
                                                                      atol=1e-9 * L)
    assert res.to_dict()["designs"][0]["error"] == res.best.error


def test_planted_stephenson_with_free_timing_from_wide_bounds():
    pts, L = _targets("stephenson")
    res = S.sixbar_path(pts, bounds=_bounds(), seed=0, n_candidates=2**13, n_refine=6)
    d = res.best
    assert d.error < 1e-20 * L * L
    assert d.checks["min_transmission_angle"] > 0
    _engine_reaches(d, pts, L)


def test_planted_watt_with_timing_from_wide_bounds():
    pts, L = _targets("watt")
    res = S.sixbar_path(pts, kind="watt", timing=TH, bounds=_bounds(), seed=0,
                        n_candidates=2**13, n_refine=6)
    d = res.best
    assert d.error < 1e-10 * L * L
    assert d.checks["engine_deviation"] <= 1e-9 * L and d.checks["max_deviation"] < 1e-5 * L


@pytest.mark.parametrize(("kind", "timing"), [("stephenson", None), ("watt", TH)])
def test_candidates_made_chunk_by_chunk_are_the_whole_samples(kind, timing):
    """The six-bar's global sample made in chunks (as each worker of a cluster makes its own)
    is bit for bit the sample made at once, dyads by construction and branch codes included,
    whatever the cut (odd starts and lengths)."""
    from linkwork.synthesis.sixbar import _candidates, _task

    pts, _ = _targets(kind)
    tk = _task(pts, kind, timing, _bounds(), ("grashof", "order"), False, False)
    n = 1000
    whole = _candidates(tk, n, 11, kind)
    assert set(whole["branch"][:4]) == {0.0, 1.0, 2.0, 3.0} or timing is not None
    for cuts in ([0, 512, 1000], [0, 3, 700, 701, 1000]):
        parts = [_candidates(tk, n, 11, kind, a, b) for a, b in itertools.pairwise(cuts)]
        for k, v in whole.items():
            assert np.array_equal(np.concatenate([p[k] for p in parts]), v), (cuts, k)


def test_dask_screening_gives_the_in_process_result():
    distributed = pytest.importorskip("distributed")
    pts, _ = _targets("stephenson")
    kw = dict(timing=TH, bounds=_bounds(), seed=1, n_candidates=2**11, n_refine=2)
    local = S.sixbar_path(pts, **kw)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = S.sixbar_path(pts, client=client, **kw)
    assert remote.best.params == local.best.params and remote.rejected == local.rejected


def test_bad_kind_bounds_and_infeasible():
    pts, _ = _targets("stephenson")
    with pytest.raises(ParameterError, match="kind"):
        S.sixbar_path(pts, kind="klann")
    with pytest.raises(ParameterError, match="unknown parameter"):
        S.sixbar_path(pts, bounds={"r9": (1, 2)})
    with pytest.raises(ParameterError, match=r"bounds\[r5\]"):
        S.sixbar_path(pts, bounds={"r5": (0.0, 2.0)})
    # a dyad far too short to reach from C to O6: nothing assembles
    far = dict(_bounds(), r5=(0.01, 0.02), r6=(0.01, 0.02), x6=(50.0, 51.0), y6=(50.0, 51.0))
    with pytest.raises(InfeasibleError, match="assembles"):
        S.sixbar_path(pts, timing=TH, bounds=far, seed=0, n_candidates=256, n_refine=2)
