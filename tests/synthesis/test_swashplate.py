"""Synthesis of the swash-plate drive: known answers, infeasible requests, feasible-region map."""

import math

import numpy as np
import pytest

from linkwork.errors import InfeasibleError, ParameterError
from linkwork.models import swashplate as sw
from linkwork.synthesis import swashplate as syn

DEG = math.pi / 180
R = 0.1


@pytest.fixture(scope="module")
def known_4a():
    d = sw.scheme_4a(R, 0.2, 15 * DEG)
    return d, d.characteristics()


def _check_meets(req, design):
    """Independent check of every limit with the model's public functions."""
    c = sw.characteristics(*design.params)
    assert abs(c.H - req.H) <= req.H_tol + 1e-12
    assert c.delta_f <= req.delta_f + 1e-12 and c.delta_r <= req.delta_r + 1e-12
    ph = np.linspace(0, 2 * math.pi, 3601)
    d = sw.pressure_angle(ph, *design.params)
    assert d.max() <= max(req.delta_f, req.delta_r) + 1e-12
    if req.Pi_v_max is not None:
        assert np.abs(sw.first_transfer(ph, *design.params)).max() <= req.Pi_v_max + 1e-12
    assert bool(c.unimodal)
    return c


def test_synthesis_4a_known_answer_at_least_as_good(known_4a):
    _, c0 = known_4a
    req = syn.Request(scheme="4a", R=R, H=float(c0.H), H_tol=1e-3 * R,
                      delta_f=float(c0.delta_f) + 1e-12, delta_r=float(c0.delta_r) + 1e-12)
    res = syn.synthesize(req, n_candidates=512, n_refine=2)
    best = res.best
    assert best.scheme == "4a" and best.a == 0 and best.b == 0
    assert abs(best.r * math.cos(best.alpha) - R) < 1e-15
    c = _check_meets(req, best)
    assert c.L <= c0.L + 1e-9
    # ranked by the objective, table consistent with the designs
    assert np.all(np.diff(res.table["L"]) >= 0)
    assert abs(res.table["L"][0] - c.L) < 1e-12


def test_synthesis_scheme_1_beats_4a_and_approaches_the_minimax_optimum(known_4a):
    _, c0 = known_4a
    req = syn.Request(scheme="1", R=R, H=float(c0.H), H_tol=1e-3 * R,
                      delta_f=float(c0.delta_f), delta_r=float(c0.delta_r))
    res = syn.synthesize(req, n_candidates=1024, n_refine=2)
    c = _check_meets(req, res.best)
    assert c.L <= c0.L
    # independent optimum for equal limits: a = b = 0, r = 2R/(1 + cos alpha) balances the
    # horizontal ellipse of the rod end: rho = R tan^2(alpha/2), l = rho / sin(delta),
    # with 2 r sin(alpha) ~ H (alpha from the stroke)
    al = 15 * DEG
    for _ in range(50):
        r = 2 * R / (1 + math.cos(al))
        al = math.asin(c0.H / (2 * r))
    L_opt = c0.H + R * math.tan(al / 2) ** 2 / math.sin(c0.delta_f)
    assert c.L <= L_opt * 1.03


def test_synthesis_velocity_limit_point_and_phi_f():
    # a request built from a known asymmetric scheme-1 design (feasible by construction)
    d = sw.scheme_1(R, 0.1, 0.25, 17 * DEG, 0.02, 0.01)
    c0 = d.characteristics()
    s90 = float(d.position(90 * DEG))
    Pi, u = 600 / 60, 12
    v_allow = float(sw.max_slide_speed(*d.params, omega=2 * math.pi * Pi / u)) * 1.01
    lim = float(sw.allowed_first_transfer(v_allow, Pi, u))
    req = syn.Request(scheme="1", R=R, H=float(c0.H), H_tol=5e-4,
                      delta_f=float(c0.delta_f) + 0.2 * DEG, delta_r=float(c0.delta_r) + 0.2 * DEG,
                      Pi_v_max=lim, phi_f=float(c0.phi_f), phi_f_tol=1 * DEG,
                      point=(90 * DEG, s90), point_tol=5e-4)
    res = syn.synthesize(req, n_candidates=2048, n_refine=2)
    c = _check_meets(req, res.best)
    assert c.L <= c0.L + 1e-9
    assert abs(c.phi_f - c0.phi_f) <= 1 * DEG + 1e-9
    assert abs(sw.position(90 * DEG, *res.best.params) - s90) <= 5e-4 + 1e-12
    assert float(sw.max_slide_speed(*res.best.params, omega=2 * math.pi * Pi / u)) <= v_allow


def test_synthesis_infeasible_pressure_angle_names_limit_and_closest():
    # scheme 2 (alpha = 90 deg): at phi = 0 the rod end is R + b off the slide, at pi R - b:
    # the rod's horizontal projection reaches R, so delta >= asin(R / l_max) with l_max = 5 R
    req = syn.Request(scheme="2", R=R, H=0.05, H_tol=1e-3, delta_f=3 * DEG, delta_r=3 * DEG)
    with pytest.raises(InfeasibleError, match="pressure angle") as ei:
        syn.synthesize(req, n_candidates=256, n_refine=1)
    assert ei.value.key in ("delta_f", "delta_r")
    assert abs(ei.value.closest_value - math.asin(0.2)) < 0.1 * DEG


def test_synthesis_infeasible_stroke():
    # scheme 4a: H = 2 R tan(alpha) <= 2 R tan(60 deg) within the default bounds
    req = syn.Request(scheme="4a", R=R, H=0.5, H_tol=1e-3, delta_f=30 * DEG,
                      delta_r=30 * DEG)
    with pytest.raises(InfeasibleError, match="stroke H") as ei:
        syn.synthesize(req, n_candidates=256, n_refine=1)
    assert ei.value.key == "H"
    assert abs(ei.value.closest_value - 2 * R * math.tan(60 * DEG)) < 1e-6


def test_feasible_region_map(known_4a):
    d0, c0 = known_4a
    req = syn.Request(scheme="4a", R=R, H=float(c0.H), H_tol=1e-2 * R,
                      delta_f=2 * DEG, delta_r=2 * DEG)
    reg = syn.feasible_region(req, d0, "alpha", "l", x_range=(14 * DEG, 16 * DEG), n=25)
    assert reg.feasible.shape == (25, 25)
    assert 0 < reg.feasible.mean() < 1
    # every feasible cell meets the limits by the model's own characteristics
    j, i = np.argwhere(reg.feasible)[0]
    d = sw.scheme_4a(R, reg.y[j] * R, reg.x[i])
    _check_meets(req, d)
    with pytest.raises(ParameterError, match="free parameter"):
        syn.feasible_region(req, d0, "b", "l")


def test_request_validation():
    with pytest.raises(ParameterError, match="scheme"):
        syn.Request(scheme="5", R=R, H=0.05, H_tol=0.0, delta_f=0.1, delta_r=0.1)
    with pytest.raises(ParameterError, match="delta_f"):
        syn.Request(scheme="1", R=R, H=0.05, H_tol=0.0, delta_f=0.0, delta_r=0.1)
    with pytest.raises(ParameterError, match="bounds"):
        syn.Request(scheme="4a", R=R, H=0.05, H_tol=0.0, delta_f=0.1, delta_r=0.1,
                    bounds={"a": (0, 1)})


def test_evaluate_candidates_vectorised_matches_single():
    req = syn.Request(scheme="4b", R=R, H=0.05, H_tol=1e-3, delta_f=8 * DEG, delta_r=8 * DEG)
    X = np.array([[1.0, 2.0, 14 * DEG, 0.05], [1.02, 1.5, 16 * DEG, -0.03]])
    m = syn.evaluate_candidates(X, req, n_grid=720)
    for i in range(2):
        c = sw.characteristics(R, X[i, 0] * R, X[i, 1] * R, X[i, 2], 0.0, X[i, 3] * R)
        assert abs(m["H"][i] - c.H) < 1e-12 and abs(m["delta_f"][i] - c.delta_f) < 1e-12
        assert m["feasible"][i] == (abs(c.H - 0.05) <= 1e-3 and c.delta_f <= 8 * DEG
                                    and c.delta_r <= 8 * DEG and bool(c.unimodal))


def test_torque_objective_equals_peak_drive_torque_of_the_kinetostatics():
    # objective "torque": peak |sum of F Pi_v| over u slides, unit force against each slide's
    # forward stroke; compare with drive_forces (frictionless) on the same designs
    req = syn.Request(scheme="4b", R=R, H=0.05, H_tol=1e-3, delta_f=8 * DEG, delta_r=8 * DEG,
                      objective="torque", u=5)
    X = np.array([[1.0, 2.0, 14 * DEG, 0.05], [1.02, 1.5, 16 * DEG, -0.03]])
    m = syn.evaluate_candidates(X, req, n_grid=720)
    for i in range(2):
        d = sw.Design(R, X[i, 0] * R, X[i, 1] * R, X[i, 2], 0.0, X[i, 3] * R)
        c = d.characteristics()

        def load(phi, c=c):
            return np.where(np.mod(phi - c.phi_min, 2 * math.pi) < c.phi_f, 1.0, 0.0)

        f = sw.drive_forces(d, load, u=5, phi=np.linspace(0, 2 * math.pi, 180, endpoint=False))
        assert abs(m["objective"][i] - np.max(np.abs(f.M_total)) / R) < 1e-9


def test_benchmark_script_runs_tiny(capsys):
    import importlib.util
    import sys
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "swashplate_synthesis.py"
    spec = importlib.util.spec_from_file_location("linkwork_bench_swashplate", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    mod.main(["--n", "64", "--loop-n", "5", "--no-dask"])
    assert "candidates/s" in capsys.readouterr().out


def test_synthesis_on_in_process_dask_cluster_matches_in_process():
    from dask.distributed import Client

    req = syn.Request(scheme="4a", R=R, H=0.05, H_tol=5e-4, delta_f=3 * DEG, delta_r=3 * DEG)
    local = syn.synthesize(req, n_candidates=256, n_refine=1, chunk_size=64)
    with Client(processes=False, dashboard_address=":0", n_workers=1,
                threads_per_worker=1) as client:
        dist = syn.synthesize(req, n_candidates=256, n_refine=1, chunk_size=64, client=client)
    assert dist.n_feasible == local.n_feasible
    np.testing.assert_allclose(dist.table["L"], local.table["L"], rtol=1e-12)


def test_general_scheme_never_worse_than_its_special_cases():
    # scheme 1 contains 4a and 4b (a = 0): for the same request its best L is not larger
    reqs = {s: syn.Request(scheme=s, R=R, H=0.05, H_tol=5e-4, delta_f=5 * DEG,
                           delta_r=5 * DEG) for s in ("1", "4a", "4b")}
    best = {s: float(syn.synthesize(q, n_candidates=512, n_refine=2).table["L"][0])
            for s, q in reqs.items()}
    assert best["1"] <= best["4b"] * (1 + 1e-3) and best["4b"] <= best["4a"] * (1 + 1e-6)
    assert best["1"] <= best["4a"]


def test_rank_breaks_near_ties_of_the_objective_by_axial_size():
    m = {"objective": np.array([0.30, 0.2, 0.2 * (1 + 1e-6), 0.2 * (1 + 1e-2)]),
         "L": np.array([0.01, 0.5, 0.1, 0.05])}
    mask = np.array([True, True, True, True])
    order = syn._rank(m, mask)
    # 0.2 and 0.2 (1 + 1e-6) tie: the shorter drive first; a 1 % worse objective comes after
    # both however short it is
    assert list(order) == [2, 1, 3, 0]
    assert list(syn._rank(m, np.array([True, False, False, True]))) == [1, 0]


def test_at_bounds_names_parameters_on_the_search_box():
    """The README request (R 100 mm, H 60 mm, 10 deg) drives the rod length l to its lower
    search bound 0.3 R: at_bounds says so (checked against the table and the box), and a design
    away from every bound is reported as such."""
    req = syn.Request(scheme="1", R=0.1, H=0.06, H_tol=1e-3, delta_f=10 * DEG, delta_r=10 * DEG)
    res = syn.synthesize(req, n_candidates=1024, n_refine=2)
    box = dict(zip(req.free, req.search_bounds(), strict=True))
    flagged = res.at_bounds(0)
    for name, side, bound in flagged:
        v = res.table[name][0] / (1.0 if name == "alpha" else req.R)
        assert bound == box[name][0 if side == "lower" else 1]
        assert abs(v - bound) <= 1e-4 * (box[name][1] - box[name][0])
    assert ("l", "lower", 0.3) in flagged
    # a tiny tolerance and a widened box: nothing sits on it
    wide = syn.Request(scheme="1", R=0.1, H=0.06, H_tol=1e-3, delta_f=10 * DEG,
                       delta_r=10 * DEG, bounds={"l": (0.05, 5.0)})
    res2 = syn.synthesize(wide, n_candidates=1024, n_refine=2)
    assert all(n != "l" for n, _, _ in res2.at_bounds(0))
    assert res2.table["L"][0] <= res.table["L"][0] + 1e-9   # the wider box is at least as good
