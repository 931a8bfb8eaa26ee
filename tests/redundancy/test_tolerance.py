"""Monte-Carlo tolerance study: equals per-sample solves, independent of chunking and of the
executor (in-process or dask.distributed), linear in the tolerance width."""

from __future__ import annotations

import numpy as np
import pytest
from _fourbar_reference import geometry, spatial_model, wrenches
from _spatial_cases import TOLS as LOOM_TOLS
from _spatial_cases import _problem

from linkwork import redundancy as rd
from linkwork.errors import ParameterError
from linkwork.redundancy import Tolerance, solve_reactions, tolerance_study

PHI = np.linspace(0.0, 2 * np.pi, 36, endpoint=False)
TOLS = [Tolerance("O", "a", "tx", 2e-4), Tolerance("O", "a", "ty", 2e-4),
        Tolerance("B", "b", "dz", 2e-5, "uniform"), Tolerance("C", "a", "tx", 3e-4, mean=1e-4),
        Tolerance("A", "a", "ty", 1e-4, "uniform")]


def _setup():
    m = spatial_model(z=(0.0, 0.02, 0.02, 0.0))
    return m, geometry(PHI), wrenches(PHI, z_g=(0.01, 0.02, 0.01))


def test_tolerance_study_equals_per_sample_solves():
    m, g, w = _setup()
    st = tolerance_study(m, g, w, TOLS, 12, seed=4, chunk_size=5)
    assert st.peaks.shape == (12, 4, 7)
    slot = {"O": 0, "A": 1, "B": 2, "C": 3}
    comp = {"dx": 0, "dy": 1, "dz": 2, "tx": 3, "ty": 4, "tz": 5}
    for s in (0, 5, 11):
        dev = np.zeros((4, 2, 6))
        for t, v in zip(TOLS, st.draws[s], strict=True):
            dev[slot[t.joint], 0 if t.side == "a" else 1, comp[t.component]] += v
        r = solve_reactions(m, g, w, dev)
        for j, name in enumerate("OABC"):
            assert np.isclose(st.sample(name, "fz")[s], np.max(np.abs(r.fz[j])), rtol=1e-9)
            assert np.isclose(st.sample(name, "bending")[s], np.max(r.bending()[j]), rtol=1e-9)
            assert np.isclose(st.peaks[s, j, 0], np.max(np.abs(r.fx[j])), rtol=1e-9)
    r0 = solve_reactions(m, g, w)
    assert np.allclose(st.nominal[:, 6], np.max(r0.bending(), axis=1), rtol=1e-9)


def test_tolerance_study_chunking_invariant_and_seeded():
    m, g, w = _setup()
    a = tolerance_study(m, g, w, TOLS, 40, seed=1, chunk_size=7)
    b = tolerance_study(m, g, w, TOLS, 40, seed=1, chunk_size=1000)
    assert np.array_equal(a.draws, b.draws)
    assert np.allclose(a.peaks, b.peaks, rtol=1e-12, atol=0)


def test_chunks_larger_than_the_kernel_block_equal_per_sample_solves(monkeypatch):
    """A chunk (unit of work of Dask and of the progress bar) runs the kernel in blocks of
    KERNEL_BLOCK samples: blocks of 7 over chunks of 250 (last block and chunk partial) give
    the same peaks as one block per chunk and as the per-sample solve."""
    import linkwork.redundancy.tolerance as tol
    m, g, w = _setup()
    one = tolerance_study(m, g, w, TOLS, 250, seed=5, chunk_size=250)
    monkeypatch.setattr(tol, "KERNEL_BLOCK", 7)
    blocked = tolerance_study(m, g, w, TOLS, 250, seed=5, chunk_size=120)
    assert np.allclose(blocked.peaks, one.peaks, rtol=1e-12, atol=0)
    slot = {"O": 0, "A": 1, "B": 2, "C": 3}
    comp = {"dx": 0, "dy": 1, "dz": 2, "tx": 3, "ty": 4, "tz": 5}
    for s in (6, 7, 119, 120, 249):      # the edges of blocks and chunks
        dev = np.zeros((4, 2, 6))
        for t, v in zip(TOLS, blocked.draws[s], strict=True):
            dev[slot[t.joint], 0 if t.side == "a" else 1, comp[t.component]] += v
        r = solve_reactions(m, g, w, dev)
        for j in range(4):
            assert np.isclose(blocked.peaks[s, j, 2], np.max(np.abs(r.fz[j])), rtol=1e-9)
            assert np.isclose(blocked.peaks[s, j, 6], np.max(r.bending()[j]), rtol=1e-9)


def test_tolerance_study_distributions():
    m, g, w = _setup()
    st = tolerance_study(m, g, w, TOLS, 4000, seed=2, chunk_size=2000)
    assert np.all(np.abs(st.draws[:, 2]) <= 2e-5)               # uniform within +-limit
    assert np.isclose(np.std(st.draws[:, 0]), 2e-4 / 3, rtol=0.05)  # normal: limit = 3 sigma
    assert np.isclose(np.mean(st.draws[:, 3]), 1e-4, atol=5e-6)
    pc = st.percentiles((5, 95))
    assert pc["B"]["bending"]["p5"] < pc["B"]["bending"]["p95"]


def test_tolerance_peaks_scale_with_width_without_loads():
    """No loads: reactions are linear in the deviations, so doubling every tolerance (same
    seed) doubles every peak."""
    m, g, _ = _setup()
    w0 = np.zeros((len(PHI), 3, 6))
    tols = [Tolerance(t.joint, t.side, t.component, t.limit, t.distribution) for t in TOLS]
    tols2 = [Tolerance(t.joint, t.side, t.component, 2 * t.limit, t.distribution) for t in TOLS]
    a = tolerance_study(m, g, w0, tols, 30, seed=3)
    b = tolerance_study(m, g, w0, tols2, 30, seed=3)
    assert np.allclose(b.peaks, 2 * a.peaks, rtol=1e-9, atol=1e-12)


def test_tolerance_study_dask_client_same_result():
    distributed = pytest.importorskip("dask.distributed")
    m, g, w = _setup()
    local = tolerance_study(m, g, w, TOLS, 30, seed=5, chunk_size=10)
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1,
                            dashboard_address=":0") as client:
        remote = tolerance_study(m, g, w, TOLS, 30, seed=5, chunk_size=10, client=client)
    assert np.allclose(local.peaks, remote.peaks, rtol=1e-12, atol=0)


def test_tolerance_study_exports(tmp_path):
    m, g, w = _setup()
    st = tolerance_study(m, g, w, TOLS, 10, seed=0)
    import json

    data = json.loads(st.to_json(tmp_path / "t.json").read_text())
    assert data["n_samples"] == 10 and "p95" in data["percentiles"]["B"]["bending"]
    lines = st.to_csv(tmp_path / "t.csv").read_text().splitlines()
    assert len(lines) == 11 and lines[0].startswith("fx_O [N]")


def test_tolerance_bad_input():
    m, g, w = _setup()
    with pytest.raises(ParameterError, match="side"):
        Tolerance("O", "c", "tx", 1e-4)
    with pytest.raises(ParameterError, match="component"):
        Tolerance("O", "a", "rx", 1e-4)
    with pytest.raises(ParameterError, match="n_samples"):
        tolerance_study(m, g, w, TOLS, 0)
    with pytest.raises(ParameterError, match=r"tolerance\.joint"):
        tolerance_study(m, g, w, [Tolerance("Z", "a", "tx", 1e-4)], 5)


def test_tolerance_percentiles_half_normal_analytic():
    """No loads, one normal tolerance t ~ N(0, sigma): every reaction is t g(phi), so the peak
    over the cycle is |t| max|g| and its percentiles are those of a half-normal distribution:
    p50 = 0.6745 sigma max|g|, p95 = 1.9600 sigma max|g|."""
    m, g, _ = _setup()
    w0 = np.zeros((len(PHI), 3, 6))
    sigma = 1e-4
    st = tolerance_study(m, g, w0, [Tolerance("C", "a", "tx", 3 * sigma)], 20000, seed=11,
                         chunk_size=5000)
    dev = np.zeros((4, 2, 6))
    dev[3, 0, 3] = 1.0
    unit = solve_reactions(m, g, w0, dev)          # reactions per radian of tilt
    gmax = np.max(unit.bending()[2])
    pc = st.percentiles((50, 95))["B"]["bending"]
    assert np.isclose(pc["p50"], 0.67449 * sigma * gmax, rtol=0.03)
    assert np.isclose(pc["p95"], 1.95996 * sigma * gmax, rtol=0.03)


def test_tolerance_study_percentiles_against_brute_force_per_sample_solves():
    model, geom, w = _problem()
    st = rd.tolerance_study(model, geom, w, LOOM_TOLS, 120, seed=11, chunk_size=50)
    # the draws follow the distributions
    assert np.all(np.abs(st.draws[:, 2]) <= 3e-5)
    # brute force: one full solve per sample (displacement method: another formulation)
    slot = {"a": 0, "b": 1}
    names = [j.name for j in model.joints]
    comps = ("dx", "dy", "dz", "tx", "ty", "tz")
    peaks = np.zeros_like(st.peaks)
    for i in range(st.n_samples):
        dev = np.zeros((len(names), 2, 6))
        for t, v in zip(LOOM_TOLS, st.draws[i], strict=True):
            dev[names.index(t.joint), slot[t.side], comps.index(t.component)] += v
        r = rd.solve_reactions(model, geom, w, dev, method="displacement")
        c = r.components()
        peaks[i, :, :6] = np.max(np.abs(c), axis=-1)
        peaks[i, :, 6] = np.max(np.hypot(c[:, 3], c[:, 4]), axis=-1)
    assert np.max(np.abs(peaks - st.peaks)) <= 1e-9 * np.max(np.abs(peaks))
    pct = st.percentiles((50, 95))
    for j, name in enumerate(st.joints):
        for k, q in enumerate(st.quantities):
            assert pct[name][q]["p95"] == pytest.approx(np.percentile(peaks[:, j, k], 95),
                                                        rel=1e-9, abs=1e-12)
    nom = rd.solve_reactions(model, geom, w).components()
    assert np.allclose(st.nominal[:, :6], np.max(np.abs(nom), axis=-1), rtol=1e-9, atol=1e-12)


def test_tolerance_study_on_dask_equals_in_process():
    distributed = pytest.importorskip("distributed")
    model, geom, w = _problem(24)
    local = rd.tolerance_study(model, geom, w, LOOM_TOLS, 60, seed=5, chunk_size=25)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        remote = rd.tolerance_study(model, geom, w, LOOM_TOLS, 60, seed=5, chunk_size=25,
                                    client=client)
    assert np.array_equal(local.peaks, remote.peaks)
    assert np.array_equal(local.draws, remote.draws)
