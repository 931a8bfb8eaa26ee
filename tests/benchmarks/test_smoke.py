"""Keep benchmarks/kinematics.py from rotting: run it tiny (n=100), no timing assertions."""

from __future__ import annotations

import functools

import numpy as np
import pytest
from _benchmarks import BENCHMARKS, load_benchmark


@pytest.fixture(scope="module")
def bench():
    return load_benchmark("kinematics")


def test_benchmark_runs_and_all_contenders_agree(bench):
    """Every case at a tiny size: every contender agrees with its reference (checked inside
    run), the table prints min / median / max and judges the targets."""
    use_pl = bench.have_pylinkage()
    fused = bench._fused() is not None
    result = bench.run(sizes=(100,), repeat=1, pylinkage=use_pl, no_numba=False, fused=fused,
                       n_designs=5)
    names = {(r["case"], r["contender"]) for r in result["rows"]}
    for case, who in (("four-bar closed form", "closed form"),
                      ("four-bar closed form", "flat NumPy, same algorithm"),
                      ("crank-slider closed form", "flat NumPy, same algorithm"),
                      ("four-bar engine", "engine"),
                      ("four-bar engine + reactions", "engine + reactions"),
                      ("four-bar, one position (fixed cost)", "engine"),
                      ("four-bar designs (5 x 360)", "engine, one batch call"),
                      ("four-bar designs (5 x 360)", "engine, one call per design")):
        assert (case, who) in names
    assert (("four-bar engine", "fused numba loop") in names) == fused
    assert (("four-bar engine", "pylinkage (numba)") in names) == use_pl
    numba = bench._have_numba()
    for case, who in (("four-bar engine", "engine, backend=numba"),
                      ("four-bar, one position (fixed cost)", "engine, backend=numba"),
                      ("four-bar designs (5 x 360)", "engine, one batch call, backend=numba")):
        assert ((case, who) in names) == numba
    assert bool(result["compile"]) == numba
    assert all(v <= 1e-9 for v in result["agreement"].values())
    text = bench.table(result)
    assert "library / flat NumPy (same algorithm, same outputs)" in text
    assert "min / median / max" in text


def test_benchmark_check_catches_a_disagreement(bench):
    case = bench.fourbar_case(50, fused=False)
    flat = case.contenders[1]
    real = flat.output
    flat.output = lambda r: tuple(x * (1 + 1e-6) if i == 3 else x
                                  for i, x in enumerate(real(r)))
    with pytest.raises(AssertionError, match="flat NumPy, same algorithm disagrees"):
        bench.check(case)


def test_benchmark_fused_engine_equals_the_engine_with_reactions(bench):
    """The fused numba loop of the engine's four-bar (Newton-Euler written for it) gives the
    engine's kinematics and reactions to 1e-12: an independent check of both; so do the rows
    of inverse_dynamics' compiled backend (backend="numba")."""
    pytest.importorskip("numba")
    case = bench.engine_case(73, reactions=True, fused=True)
    errs, _ = bench.check(case)
    assert errs["fused numba loop"] < 1e-12
    # the compiled backend's rows (issue 20 item 2): the engine's numbers to rounding
    for who in ("engine + reactions (numba backend)", "engine + reactions, both by numba",
                "reactions alone, NumPy backend", "reactions alone, numba backend"):
        assert errs[who] < 1e-12, who


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
    result = tol.run(sizes=(20, 60), positions=24, repeat=1, resolve_n=3, dask_n=0,
                     fused=False)
    names = {(r["contender"], r["samples"]) for r in result["rows"]}
    assert {("force method", 0), ("displacement method", 0), ("plain NumPy re-solve", 3),
            ("plain NumPy, factorised once", 3), ("tolerance_study", 20),
            ("tolerance_study", 60), ("plain NumPy affine map, lean kernel", 60),
            ("library kernel", 60), ("flat NumPy lean kernel", 60)} <= names
    assert len(result["agreement"]) == 10
    assert all(v <= 1e-9 for v in result["agreement"].values())
    assert "x re-solve" in tol.table(result, markdown=True)
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


def test_tolerance_study_benchmark_dask_rows_on_a_process_cluster():
    """The dask rows run on LocalCluster(processes=True) and on as many plain processes, both
    equal to the in-process study, and the table judges them."""
    tol = load_benchmark("tolerance_study")
    result = tol.run(sizes=(40,), positions=12, repeat=1, resolve_n=2, dask_n=40, workers=(1,),
                     fused=False)
    (row,) = result["dask"]
    assert row["workers"] == 1 and set(row["times"]) == {"in-process", "cluster", "plain"}
    assert all(len(v) == 1 for v in row["times"].values())
    agree = result["agreement"]
    assert agree["tolerance_study, process cluster, 1 worker, N=40 vs in-process"] == 0.0
    assert agree["tolerance_study, 1 plain process, N=40 vs in-process"] == 0.0
    text = tol.table(result)
    assert "one cluster alive at a time" in text and "1 plain process" in text


def test_swashplate_benchmark_dask_rows_and_their_check():
    """benchmarks/swashplate_synthesis.py with a 1-worker process cluster: the cluster's and
    the plain process's screening equal the in-process one; a plain process that returns
    another screening is caught before timing."""
    sw = load_benchmark("swashplate_synthesis")
    result = sw.run(n=64, loop_n=3, repeat=1, workers=(1,))
    assert result["agreement"]["screen, process cluster, 1 worker vs in-process"] == 0.0
    assert result["agreement"]["screen, 1 plain process vs in-process"] == 0.0
    assert "the screening of 64 candidates" in sw.table(result)
    common = load_benchmark("_common")
    req, _, x = sw.problem(8)
    fn = functools.partial(sw.syn.evaluate_candidates, req=req)

    def other(procs):
        return {k: v + 1.0 for k, v in procs.evaluate(fn, x, 4).items()}

    with pytest.raises(AssertionError, match="1 plain process"):
        common.cluster_rounds((1,), lambda: sw.evaluate(fn, x, chunk_size=4),
                              lambda cl: sw.evaluate(fn, x, chunk_size=4, client=cl),
                              other, sw.check_same, repeat=1)


def test_plain_processes_split_the_candidates_in_order():
    """benchmarks/_common.PlainProcesses: equal consecutive shares, one per process, chunked
    there; arrays and dicts of arrays joined in candidate order."""
    common = load_benchmark("_common")
    procs = common.PlainProcesses(2)
    try:
        x = np.arange(11.0)
        assert np.array_equal(procs.evaluate(np.square, x, 3), x ** 2)
        d = {"a": np.arange(5.0), "b": -np.arange(5.0)}
        got = procs.evaluate(dict, d, 2)
        assert set(got) == {"a", "b"} and all(np.array_equal(got[k], d[k]) for k in d)
    finally:
        procs.close()


def test_cpu_lines_of_calls_below_the_clock_resolution():
    """benchmarks/_common.cpu_lines: os.times counts in 10 ms ticks, so a tiny call can read
    0 s in every process (it divided by zero in one CI run); the bound is then undefined."""
    common = load_benchmark("_common")
    zero = {"in-process": {"client": 0.0},
            "process cluster, 1 worker": {"client": 0.0, "scheduler": 0.01, "workers": [0.0]}}
    assert "undefined (below the CPU clock's 10 ms resolution)" in "\n".join(
        common.cpu_lines(zero))
    some = {"in-process": {"client": 1.2},
            "process cluster, 2 workers": {"client": 0.1, "scheduler": 0.2,
                                           "workers": [0.5, 0.6]}}
    assert "= 2.00 (the speed-up on free cores at most)" in "\n".join(common.cpu_lines(some))


def test_cpu_split_counts_a_local_scheduler_once():
    """benchmarks/_common.cpu_split: a LocalCluster's scheduler runs in the client's process,
    so its CPU is the client's (measured twice before: client 0.13 s and scheduler 0.14 s of
    one process); it is then reported as one process, and cpu_lines bounds the speed-up by all
    processes' CPU on this machine's cores (1.2 s in-process against 0.1 + 0.5 + 0.6 s on 2
    cores: 2.00)."""
    from dask.distributed import Client

    common = load_benchmark("_common")
    with Client(processes=False, dashboard_address=":0", n_workers=1,
                threads_per_worker=1) as client:
        split = common.cpu_split(lambda: sum(range(1000)), client, repeat=1)
    assert split["scheduler"] is None and len(split["workers"]) == 1
    lines = "\n".join(common.cpu_lines({
        "in-process": {"client": 1.2},
        "process cluster, 2 workers": {"client": 0.1, "scheduler": None,
                                       "workers": [0.5, 0.6]}}))
    assert "client and scheduler (one process) 0.10 s" in lines
    cores = __import__("os").cpu_count()
    assert f"(all / {cores} cores) = {1.2 * cores / 1.2:.2f}" in lines


def test_long_cycle_benchmark_runs_tiny():
    """benchmarks/long_cycle.py at tiny sizes: the chunked study equals the whole cycle, the
    long run agrees with the check run, peaks are reported."""
    lc = load_benchmark("long_cycle")
    result = lc.run(n=3000, dyn_n=2000, check_n=500, chunk=700)
    assert result["chunked"]["columns"] > 50 and result["chunked"]["csv_bytes"] > 0
    agree = result["agreement"]
    assert agree["analyze_chunked vs analyze, n=500: Q_mean"] <= 1e-12
    assert agree["dead centres, n=3000 vs n=500 [rad]"] <= 1e-10
    assert agree["extremes, n=3000 vs n=500 (relative)"] <= 1e-6 + 100 * (2 * np.pi / 500) ** 2
    assert "2 GiB" in lc.report(result)


def test_cli_benchmark_splits_the_wall_time(tmp_path):
    """benchmarks/cli.py: one command, one round: the phases add up to the wall time and the
    command writes what it wrote when probed."""
    cli = load_benchmark("cli")
    result = cli.run(1, [("analyze sine_press", ["analyze", str(BENCHMARKS.parent / "examples"
                                                               / "sine_press.toml")])])
    ph = result["commands"]["analyze sine_press"]
    parts = sum(ph[p][0] for p in ("start-up", "imports", "computation", "output"))
    assert abs(parts - ph["total"][0]) < 1e-9
    assert ph["computation"][0] > 0 and ph["imports"][0] > 0 and ph["output"][0] > 0


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
