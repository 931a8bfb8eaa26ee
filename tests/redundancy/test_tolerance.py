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


def test_kernel_row_blocks_and_padding_equal_per_sample_solves(monkeypatch):
    """The affine map runs in blocks of KERNEL_ROWS rows (positions x components), the last
    padded with zeros: 7-row blocks (864 rows = 123 x 7 + 3) and 5-sample blocks give the
    default's peaks to 1e-12 and the per-sample solve's to 1e-9."""
    import linkwork.redundancy.tolerance as tol
    m, g, w = _setup()
    ref = tolerance_study(m, g, w, TOLS, 23, seed=8, chunk_size=23)
    monkeypatch.setattr(tol, "KERNEL_ROWS", 7)
    monkeypatch.setattr(tol, "KERNEL_BLOCK", 5)
    odd = tolerance_study(m, g, w, TOLS, 23, seed=8, chunk_size=11)
    assert np.allclose(odd.peaks, ref.peaks, rtol=1e-12, atol=0)
    slot = {"O": 0, "A": 1, "B": 2, "C": 3}
    comp = {"dx": 0, "dy": 1, "dz": 2, "tx": 3, "ty": 4, "tz": 5}
    for s in (0, 4, 5, 10, 11, 22):
        dev = np.zeros((4, 2, 6))
        for t, v in zip(TOLS, odd.draws[s], strict=True):
            dev[slot[t.joint], 0 if t.side == "a" else 1, comp[t.component]] += v
        r = solve_reactions(m, g, w, dev)
        for j in range(4):
            for k, arr in enumerate((r.fx, r.fy, r.fz, r.mx, r.my, r.mz)):
                scale = np.max(np.abs(ref.peaks[:, :, k]))
                assert abs(odd.peaks[s, j, k] - np.max(np.abs(arr[j]))) <= 1e-9 * scale
            assert np.isclose(odd.peaks[s, j, 6], np.max(r.bending()[j]), rtol=1e-9)


_KERNEL_FAULTS = r"""
import resource, sys
import numpy as np
sys.path.insert(0, {tests!r})
sys.path.insert(0, {shared!r})
from _fourbar_reference import geometry, spatial_model, wrenches
from test_tolerance import TOLS
import linkwork.redundancy.tolerance as tol

PHI = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)  # a full cycle: a 0.8 MB map


def _setup():
    return (spatial_model(z=(0.0, 0.02, 0.02, 0.0)), geometry(PHI),
            wrenches(PHI, z_g=(0.01, 0.02, 0.01)))

captured = {{}}
real = tol.evaluate
def spy(func, draws, **kw):
    captured.update(func.keywords, **kw["shared"], draws=draws)
    return real(func, draws, **kw)
tol.evaluate = spy
m, g, w = _setup()
tol.tolerance_study(m, g, w, TOLS, 2000, seed=1)
d = captured.pop("draws")
zb, n, nj = captured["zb"], captured["n"], captured["n_joints"]
# as a dask worker receives it: an unaligned copy (Dask's frames start at any byte)
raw = bytearray(zb.nbytes + 1)
zu = np.frombuffer(memoryview(raw)[1:], dtype=np.float64).reshape(zb.shape)
zu[...] = zb
assert not zu.flags.aligned


def work(out):  # in a thread, as on a dask worker (its own malloc arena)
    tol._chunk(d, zb=zu, n=n, n_joints=nj)
    a = resource.getrusage(resource.RUSAGE_THREAD).ru_minflt
    got = tol._chunk(d, zb=zu, n=n, n_joints=nj)
    out.append(resource.getrusage(resource.RUSAGE_THREAD).ru_minflt - a)
    assert np.array_equal(got, tol._chunk(d, zb=zb, n=n, n_joints=nj))

import threading
out = []
th = threading.Thread(target=work, args=(out,))
th.start()
th.join()
# touched once a chunk: the result, and the aligned copy of the map
buffers = d.shape[0] * nj * 7 * 8 + zb.nbytes
print(out[0], buffers // 4096)
"""


def test_kernel_reuses_its_buffers_under_dask_malloc_settings():
    """Under dask's worker setting MALLOC_TRIM_THRESHOLD_=65536 (every temporary over 128 kB
    a fresh mmap, freed heap returned at once), run in a thread as a dask worker runs it, on an
    unaligned affine map as a worker receives it, a chunk of 2000 samples touches little more
    than its result and one aligned copy of the map: page faults (getrusage of the thread, a
    fresh interpreter) below twice their pages; the same peaks as from the aligned map. The
    block buffers are made once per thread. Measured on the loom four-bar's full size on a
    worker: 5 518 faults a chunk before the map was aligned once (matmul copied it every
    block), 1 767 here in a thread when the strided moments were squared in place (NumPy
    copied them), 3 380 for the kernel before (a new product per block)."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    if not sys.platform.startswith("linux"):
        pytest.skip("glibc malloc thresholds")
    code = _KERNEL_FAULTS.format(tests=str(Path(__file__).parent),
                                 shared=str(Path(__file__).parents[1]))
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "MALLOC_TRIM_THRESHOLD_": "65536"}, check=True,
                         timeout=120, cwd=Path(__file__).parents[1])
    faults, pages = (int(v) for v in res.stdout.split())
    assert faults < 2 * pages + 100


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
