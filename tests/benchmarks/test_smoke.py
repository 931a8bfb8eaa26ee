"""Keep benchmarks/kinematics.py from rotting: run it tiny (n=100), no timing assertions."""

from __future__ import annotations

import numpy as np
import pytest
from _benchmarks import BENCHMARKS, load_benchmark


@pytest.fixture(scope="module")
def bench():
    return load_benchmark("kinematics")


def test_benchmark_runs_and_all_contenders_agree(bench):
    use_pl = bench.have_pylinkage()
    rows = bench.run(sizes=(100,), repeat=1, pylinkage=use_pl, no_numba=False)
    names = {(r["mechanism"], r["contender"]) for r in rows}
    for mech in ("four-bar", "crank-slider"):
        for who in ("plain NumPy", "closed form", "engine", "engine + reactions"):
            assert (mech, who) in names
        assert ((mech, "pylinkage (numba)") in names) == use_pl
    text = bench.table(rows)
    assert "closed form / plain NumPy" in text


def test_benchmark_check_catches_a_disagreement(bench):
    cons = bench.fourbar_contenders(50, with_engine=False)
    ref = cons[0].output(cons[0].run())
    bad = list(ref)
    bad[3] = bad[3] * (1 + 1e-6)
    with pytest.raises(AssertionError, match="closed form disagrees"):
        bench.check([c for c in cons if c.name == "closed form"], tuple(bad), "four-bar")


def test_benchmark_plain_numpy_fourbar_is_the_open_branch(bench):
    from linkwork.models.fourbar import fourbar

    t = np.linspace(0, 2 * np.pi, 37)
    plain = bench.numpy_fourbar(t, 0.1, 0.3, 0.2, 0.3, 10.0)
    r = fourbar(t, 0.1, 0.3, 0.2, 0.3, 10.0, branch=+1)
    np.testing.assert_allclose(np.angle(np.exp(1j * (plain[0] - r.theta3))), 0, atol=1e-12)
    np.testing.assert_allclose(plain[2], r.omega3, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(plain[4], r.eps3, rtol=1e-9, atol=1e-9)


def test_tolerance_study_benchmark_runs_tiny_and_its_checks_bite():
    """benchmarks/tolerance_study.py (issue 6): tiny sizes, no dask, no timing assertions; every
    contender agrees with the plain NumPy re-solve, and the checks catch a 1e-6 change."""
    tol = load_benchmark("tolerance_study")
    result = tol.run(sizes=(20, 60), positions=24, repeat=1, resolve_n=3, dask_n=0)
    names = {(r["contender"], r["samples"]) for r in result["rows"]}
    assert {("force method", 0), ("displacement method", 0), ("plain NumPy re-solve", 3),
            ("plain NumPy, factorised once", 3), ("tolerance_study", 20),
            ("tolerance_study", 60), ("plain NumPy affine map, lean kernel", 60)} <= names
    assert len(result["agreement"]) == 9
    assert all(v <= 1e-9 for v in result["agreement"].values())
    assert "speed-up vs plain re-solve" in tol.table(result, markdown=True)
    prob = tol.load_problem(24)
    cyc = tol.cycle_contenders(prob)
    out = [c.output(c.run()) for c in cyc]
    out[1] = out[1].copy()
    out[1][7] *= 1 + 1e-6                     # fy of joint A (row 6 + 1) at every position
    with pytest.raises(AssertionError, match="displacement method disagrees"):
        tol.check_cycle(out, [c.name for c in cyc], len(prob.model.joints))
    cons, resolve = tol.study_contenders(prob, (20,), 3, 0)
    results, _ = tol._first_calls(cons)
    i = [c.name for c in cons].index("tolerance_study")
    key = f"tolerance_study#{i}"
    peaks, draws = results[key]
    results[key] = (peaks * (1 + 1e-6), draws)
    with pytest.raises(AssertionError, match=r"tolerance_study \(N=20\) disagrees"):
        tol.check_study(results, cons, 3, resolve)


def test_synthesis_benchmark_runs_tiny():
    """benchmarks/synthesis.py on the planted problem, tiny, without pylinkage and Dask: the
    exact answer (f = 0) is found; no timing assertions."""
    mod = load_benchmark("synthesis")
    rows = mod.main(["--repeat", "1", "--problems", "planted", "--candidates", "2048",
                     "--no-pylinkage", "--no-dask", "--no-throughput"])
    assert rows[0]["contender"] == "linkwork" and rows[0]["error"] < 1e-20


def test_report_benchmark_runs_tiny():
    """benchmarks/report.py on one example, once, without the GIF; no timing assertions."""
    mod = load_benchmark("report")
    rows = mod.run([BENCHMARKS.parent / "examples" / "swashplate_4a.toml"], repeat=1,
                   gif_frames=0)
    assert len(rows) == 1 and rows[0]["bytes"] > 10_000 and rows[0]["positions"] == 361
    assert "report [s]" in mod.table(rows)
