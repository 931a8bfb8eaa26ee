"""Path generation by a four-bar (linkwork.synthesis.path).

Planted problems: target points generated from a known crank-rocker must be recovered (error
below 1e-20 of the squared size of the path: the exact designs exist). Every returned design is
recomputed by the independent model of tests/_synthesis_reference.py (Norton's half-angle
closed form, not linkwork's): its error (to 1e-9 relative, or 1e-24 L^2 absolute near zero),
order, one circuit and Grashof. The closed form of path.coupler_point is compared with
linkwork.models.fourbar over designs x angles (1e-12 of the link lengths).
"""

from __future__ import annotations

import itertools
import math

import _synthesis_reference as ref
import numpy as np
import pytest

from linkwork.errors import InfeasibleError, ParameterError
from linkwork.models.fourbar import fourbar
from linkwork.synthesis.path import check_design, coupler_point, path, task

PLANT = dict(r1=4.0, r2=1.0, r3=3.5, r4=3.0, rcx=1.5, rcy=1.2, x0=0.5, y0=-0.3, theta0=0.3)
FAST = dict(progress=False, n_candidates=2**13, n_refine=10, seed=3)


def _targets(th: np.ndarray, p: dict = PLANT, branch: int = 1) -> np.ndarray:
    x, y, ok = coupler_point(th, p, branch)
    assert ok.all()
    return np.c_[x, y]


def _independent(res, closed: bool = False, timing=None) -> None:
    """Every design recomputed by the reference model."""
    L = float(np.hypot(*np.ptp(res.points, axis=0)))
    for d in res.designs:
        p = dict(d.params)
        e = ref.error(p, d.branch, res.points)
        assert e == pytest.approx(d.error, rel=1e-9, abs=1e-24 * L * L)
        assert ref.ordered(p["theta2"])[0]
        assert ref.one_circuit(p, d.branch, closed)
        if "grashof" in res.constraints:
            assert ref.crank_rocker(p)
        if timing is not None:
            assert np.allclose(np.mod(p["theta2"], 2 * math.pi), np.mod(timing, 2 * math.pi))


def test_coupler_point_equals_the_fourbar_closed_form_over_designs_and_angles():
    rng = np.random.default_rng(0)
    th = np.linspace(0, 2 * math.pi, 37)
    for br in (1, -1):
        a, b, c, d = 1.0, rng.uniform(3, 4, (5, 1)), rng.uniform(2.5, 3.5, (5, 1)), 3.8
        p = dict(r1=d, r2=a, r3=b, r4=c, rcx=0.7, rcy=-0.4, x0=0.0, y0=0.0, theta0=0.0)
        x, y, ok = coupler_point(th, p, br)
        fb = fourbar(th, a, b, c, d, branch=br, coupler_point=(0.7, -0.4), on_failure="nan")
        assert np.array_equal(ok, fb.valid)
        assert np.allclose(x[ok], fb.xP[ok], atol=1e-12) and np.allclose(y[ok], fb.yP[ok],
                                                                           atol=1e-12)


def test_coupler_point_moves_with_the_frame_placement():
    th = np.linspace(0, 6, 13)
    p0 = dict(PLANT, x0=0.0, y0=0.0, theta0=0.0)
    x, y, _ = coupler_point(th, p0)
    X, Y, _ = coupler_point(th, PLANT)
    c, s = math.cos(0.3), math.sin(0.3)
    assert np.allclose(X, 0.5 + c * x - s * y, atol=1e-13)
    assert np.allclose(Y, -0.3 + s * x + c * y, atol=1e-13)


def test_planted_free_timing_open_path_is_recovered():
    pts = _targets(np.linspace(0.2, 5.5, 8))
    res = path(pts, **FAST)
    L = float(np.hypot(*np.ptp(pts, axis=0)))
    assert res.best.error < 1e-20 * L * L
    _independent(res)
    assert res.n_evaluated == 2**13
    assert res.rejected["grashof"] > 0  # the default bounds hold non-crank-rockers too


def test_planted_prescribed_timing_is_recovered_with_that_timing():
    th = np.linspace(0.2, 5.5, 8)
    pts = _targets(th)
    res = path(pts, timing=th, **FAST)
    L = float(np.hypot(*np.ptp(pts, axis=0)))
    assert res.best.error < 1e-20 * L * L
    _independent(res, timing=th)


def test_planted_closed_path_clockwise_on_the_other_branch():
    th = -np.linspace(0.0, 2 * math.pi, 10, endpoint=False)  # crank turning clockwise
    pts = _targets(th, branch=-1)
    res = path(pts, closed=True, **FAST)
    L = float(np.hypot(*np.ptp(pts, axis=0)))
    assert res.best.error < 1e-18 * L * L
    _independent(res, closed=True)


def test_approximate_problem_meets_constraints_and_transmission_angle():
    # five points on a straight line: no exact crank-rocker through them in order is asked
    pts = np.c_[np.full(6, 20.0), np.linspace(20.0, 45.0, 6)] * 1e-3
    mu = math.radians(30)
    res = path(pts, constraints=("grashof", "order", ("transmission", mu)), **FAST)
    _independent(res)
    for d in res.designs:
        assert d.checks["min_transmission_angle"] >= mu - 1e-9
        # the reference: transmission angle over the whole turn of the crank-rocker
        p = d.params
        for t in (0.0, math.pi):
            cos = (p["r3"] ** 2 + p["r4"] ** 2 - (p["r1"] - p["r2"] * math.cos(t)) ** 2
                   - (p["r2"] * math.sin(t)) ** 2) / (2 * p["r3"] * p["r4"])
            m = math.acos(cos)
            assert min(m, math.pi - m) >= mu - 1e-9


def test_check_design_finds_order_grashof_and_toggle_defects():
    pts = _targets(np.linspace(0.2, 5.5, 8))
    tk = task(pts)
    good = dict(PLANT, theta2=list(np.linspace(0.2, 5.5, 8)))
    assert check_design(good, 1, tk)[0] is None
    swapped = dict(good, theta2=list(np.linspace(0.2, 5.5, 8)[[0, 2, 1, 3, 4, 5, 6, 7]]))
    assert check_design(swapped, 1, tk)[0] == "order"
    # a triple rocker (non-Grashof): the crank cannot turn, and between two angles on either
    # side of its limit position the linkage must pass a toggle
    rocker = dict(r1=2.0, r2=1.6, r3=1.0, r4=1.9, rcx=0.5, rcy=0.3, x0=0.0, y0=0.0, theta0=0.0)
    assert check_design(dict(rocker, theta2=[0.2, 0.4, 0.6]), 1, tk)[0] == "grashof"
    grid = np.linspace(-math.pi, math.pi, 721)
    _, _, ok = coupler_point(grid, rocker, 1)
    assert not ok.all() and ok.any()
    inside = grid[ok]
    th3 = np.array([inside[len(inside) // 2], inside[-3], inside[2] + 2 * math.pi])
    tk_free = task(_targets(th3, rocker), constraints=("order",))
    # the short way between the two ends of the crank's range is assembled throughout ...
    assert check_design(dict(rocker, theta2=list(th3[:2])), 1,
                        task(_targets(th3[:2], rocker), timing=th3[:2],
                             constraints=("order",)))[0] is None
    # ... the way round through the unassembled range passes the toggle: a branch defect
    assert check_design(dict(rocker, theta2=list(th3)), 1, tk_free)[0] == "branch"


def test_too_few_points_and_bad_bounds_are_named():
    with pytest.raises(ParameterError, match="too few"):
        path([(0, 0), (1, 1)], progress=False)
    with pytest.raises(ParameterError, match="timing"):
        path([(0, 0), (1, 1), (2, 0)], timing=[0.1, 0.2], progress=False)
    with pytest.raises(ParameterError, match=r"bounds\[r2\]"):
        path([(0, 0), (1, 1), (2, 0)], bounds={"r2": (2.0, 1.0)}, progress=False)
    with pytest.raises(ParameterError, match="unknown parameter"):
        path([(0, 0), (1, 1), (2, 0)], bounds={"crank": (1.0, 2.0)}, progress=False)


def test_bounds_that_exclude_every_crank_rocker_raise_with_the_closest_value():
    pts = _targets(np.linspace(0.2, 5.5, 6))
    with pytest.raises(InfeasibleError, match="Grashof crank-rocker") as ex:
        path(pts, bounds={"r2": (5.0, 6.0), "r1": (1.0, 2.0), "r3": (1.0, 2.0),
                          "r4": (1.0, 2.0)}, **FAST)
    assert "closest achievable" in str(ex.value)


def test_impossible_transmission_angle_names_the_closest_reached():
    pts = _targets(np.linspace(0.2, 5.5, 6))
    with pytest.raises(InfeasibleError, match="transmission angle >= 89") as ex:
        path(pts, constraints=("grashof", "order", ("transmission", math.radians(89))), **FAST)
    assert "deg" in str(ex.value.closest)


def test_dask_screening_gives_the_in_process_result():
    distributed = pytest.importorskip("distributed")
    pts = _targets(np.linspace(0.2, 5.5, 6))
    kw = dict(progress=False, n_candidates=2**11, n_refine=2, seed=5)
    local = path(pts, **kw)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = path(pts, client=client, **kw)
    assert remote.best.params == local.best.params
    assert remote.rejected == local.rejected


@pytest.mark.parametrize("free_start", [False, True])
def test_candidates_made_chunk_by_chunk_are_the_whole_samples(free_start):
    """The global sample made in chunks (each worker of a cluster makes its own: the Sobol
    sequence fast-forwarded, the halves and branches by the candidate's index) is bit for bit
    the sample made at once, whatever the cut (odd starts and lengths included)."""
    from linkwork.synthesis.path import _candidates

    th = np.linspace(0.2, 5.5, 6)
    tk = task(_targets(th), timing=th if free_start else None, free_start=free_start)
    n = 1000
    whole = _candidates(tk, n, 7)
    assert set(whole) == ({"X", "branch", "start"} if free_start else {"X", "branch"})
    for cuts in ([0, 512, 1000], [0, 3, 700, 701, 1000], [0, 1000]):
        parts = [_candidates(tk, n, 7, a, b) for a, b in itertools.pairwise(cuts)]
        for k, v in whole.items():
            assert np.array_equal(np.concatenate([p[k] for p in parts]), v), (cuts, k)
    assert np.array_equal(whole["branch"][:4], [1, -1, 1, -1])


def test_design_file_runs_through_the_planar_study(tmp_path):
    from linkwork import io
    from linkwork.studies import planar as planar_study

    th = np.linspace(0.2, 5.5, 8)
    pts = _targets(th)
    res = path(pts, timing=th, **FAST)
    f = res.best.to_toml(tmp_path / "design.toml")
    doc = io.load(f)
    study = planar_study.analyze(doc)
    assert study.kinematics.valid.all()  # the file's range: a full turn of the crank-rocker
    from linkwork.planar.kinematics import kinematics

    k = kinematics(doc.mechanism(), th + res.best.params["theta0"])
    P = k.point("coupler", "P")
    assert np.allclose(P.x, pts[:, 0], atol=1e-9) and np.allclose(P.y, pts[:, 1], atol=1e-9)


def test_bounds_that_exclude_every_assembled_design_say_so():
    pts = _targets(np.linspace(0.2, 5.5, 6))
    b = {"r1": (10.0, 11.0), "r2": (1.0, 1.1), "r3": (1.0, 1.1), "r4": (1.0, 1.1)}
    with pytest.raises(InfeasibleError, match="assembles") as ex:
        path(pts, bounds=b, constraints=("order",), **FAST)
    assert "no candidate assembles" in str(ex.value)


def test_refinement_jacobian_equals_central_differences():
    """The coupler-point rows of the refinement's Jacobian (exact, by implicit differentiation
    of the loop closure) against central differences of the residuals (step 1e-6), for free
    timing, prescribed timing and timing with a free start: to 1e-7 of the largest entry."""
    from linkwork.synthesis import path as pa

    th = np.linspace(0.2, 5.5, 8)
    pts = _targets(th) + 0.01
    x9 = np.array([PLANT[k] for k in pa.PARAMS])
    for kw in ({}, {"timing": th}, {"timing": th, "free_start": True}):
        tk = task(pts, constraints=("order",), **kw)
        for br in (1.0, -1.0):
            v, s = pa._vector(x9, th, tk)
            args = (x9, tk.free, tk, s, br, 1e2)
            J = pa._jacobian(v, *args)
            Jc = np.empty_like(J)
            for j in range(len(v)):
                e = np.zeros(len(v))
                e[j] = 1e-6 * max(1.0, abs(v[j]))
                Jc[:, j] = (pa._residuals((v + e)[None, :], *args)[0]
                            - pa._residuals((v - e)[None, :], *args)[0]) / (2 * e[j])
            rows = slice(0, 2 * tk.n)
            assert np.abs(J[rows] - Jc[rows]).max() <= 1e-7 * np.abs(Jc[rows]).max()


def test_planted_timing_with_a_free_start_is_recovered():
    """Only the crank's advances between the points are prescribed (the literature's 18-point
    problem does this): the planted crank-rocker is found with the advances kept."""
    th = 1.1 + np.linspace(0.0, 4.0, 7)
    pts = _targets(th)
    res = path(pts, timing=th - 1.1, free_start=True, **FAST)
    L = float(np.hypot(*np.ptp(pts, axis=0)))
    assert res.best.error < 1e-20 * L * L
    _independent(res)
    for d in res.designs:
        adv = np.mod(np.diff(d.theta2) + math.pi, 2 * math.pi) - math.pi
        assert np.allclose(adv, np.diff(th), atol=1e-12)
    with pytest.raises(ParameterError, match="free_start"):
        path(pts, free_start=True, progress=False)


def test_frame_angle_bounded_by_a_full_turn_is_refined_across_zero():
    """theta0 of the planted linkage just below 2 pi (= -0.05 rad), bounds (0, 2 pi), the
    refinement started at theta0 = 0.02: it does not stop at the bound 0 (as a box bound
    would make it) but reaches the exact design, returned with theta0 inside the bounds."""
    from linkwork.synthesis import path as pa

    p = dict(PLANT, theta0=-0.05)
    th = np.linspace(0.2, 5.5, 8)
    pts = _targets(th, p)
    tk = task(pts, timing=th, bounds={"theta0": (0.0, 2 * math.pi)})
    x9 = np.array([dict(PLANT, theta0=0.02)[k] for k in pa.PARAMS])
    X, th_r, _ = pa._refine(x9, 1.0, th, tk, 200)
    assert X[8] == pytest.approx(2 * math.pi - 0.05, abs=1e-9)
    assert np.allclose(X[:8], [PLANT[k] for k in pa.PARAMS[:8]], atol=1e-9)
    assert np.array_equal(th_r, th)


def test_run_range_of_a_rocker_whose_points_straddle_zero(tmp_path):
    """A triple rocker (the crank swings from -1.65 to 1.65 rad) through points at crank
    angles -0.8 ... 0.8, kept within a turn as designs keep them (5.48, 5.98, 0.3, 0.8): the
    range it runs is the short way from the first point to the last (1.6 rad, assembled
    throughout), not back through pi; its planar file runs through the engine."""
    from linkwork import io
    from linkwork.planar.kinematics import kinematics
    from linkwork.synthesis.design import FourbarDesign

    rocker = dict(r1=2.0, r2=1.5, r3=1.2, r4=1.4, rcx=0.5, rcy=0.3, x0=0.0, y0=0.0,
                  theta0=0.0)
    th = np.array([-0.8, -0.3, 0.3, 0.8])
    pts = _targets(th, rocker)
    params = dict(rocker, theta2=list(np.mod(th, 2 * math.pi)))
    defect, checks = check_design(params, 1, task(pts, timing=th, constraints=("order",)))
    assert defect is None and not checks["crank_rotates"]
    d = FourbarDesign(params=params, branch=1, error=0.0, points=pts, checks=checks)
    run = d.run_range(9)
    assert np.allclose(np.mod(run - run[0], 2 * math.pi)[-1], 1.6)
    assert coupler_point(run, rocker, 1)[2].all()
    doc = io.load(d.to_toml(tmp_path / "rocker.toml"))
    assert kinematics(doc.mechanism(), doc.positions()).valid.all()
