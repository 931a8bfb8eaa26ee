"""linkwork.sweep: chunked evaluation in-process and on an in-process dask cluster."""

import functools

import numpy as np
import pytest

from linkwork.errors import ParameterError
from linkwork.sweep import (
    MAX_TASK_CHUNKS,
    Generated,
    chunk_slices,
    evaluate,
    rich_progress,
    task_groups,
)


def _model(x, scale=1.0):
    """A vectorised 'model': per candidate a row (N, 3) -> dict of per-candidate results."""
    x = np.asarray(x)
    return {"sum": scale * x.sum(axis=1), "max": x.max(axis=1)}


def test_chunk_slices_cover_in_order():
    sl = chunk_slices(10, 4)
    assert [(s.start, s.stop) for s in sl] == [(0, 4), (4, 8), (8, 10)]
    assert chunk_slices(0, 4) == []
    with pytest.raises(ParameterError, match="chunk_size"):
        chunk_slices(10, 0)


def test_in_process_matches_direct_call_and_bounds_chunks():
    rng = np.random.default_rng(0)
    x = rng.normal(size=(1003, 3))
    seen = []

    def model(c):
        seen.append(len(c))
        return _model(c)

    calls = []
    out = evaluate(model, x, chunk_size=100, progress=lambda d, t: calls.append((d, t)))
    ref = _model(x)
    np.testing.assert_array_equal(out["sum"], ref["sum"])
    np.testing.assert_array_equal(out["max"], ref["max"])
    assert max(seen) == 100 and sum(seen) == 1003
    assert calls[-1] == (1003, 1003) and len(calls) == 11


def test_mapping_candidates_tuple_results_and_combine():
    cand = {"a": np.arange(10.0), "b": np.arange(10.0) ** 2}
    out = evaluate(lambda c: (c["a"] + c["b"], c["a"] * 2), cand, chunk_size=3)
    np.testing.assert_array_equal(out[0], cand["a"] + cand["b"])
    np.testing.assert_array_equal(out[1], 2 * cand["a"])
    total = evaluate(lambda c: c["b"].sum(), cand, chunk_size=4, combine=lambda s, x: s + x)
    assert total == cand["b"].sum()
    with pytest.raises(ParameterError, match="same length"):
        evaluate(lambda c: c["a"], {"a": np.zeros(3), "b": np.zeros(4)})


def test_dask_in_process_cluster_gives_the_same_result():
    from dask.distributed import Client

    x = np.random.default_rng(1).normal(size=(500, 3))
    calls = []
    with Client(processes=False, dashboard_address=":0", n_workers=1,
                threads_per_worker=2) as client:
        out = evaluate(functools.partial(_model, scale=2.0), x, chunk_size=64, client=client,
                       progress=lambda d, t: calls.append(d))
        best = evaluate(functools.partial(_model, scale=1.0), x, chunk_size=64, client=client,
                        combine=lambda acc, r: {"max": np.maximum(acc["max"].max(),
                                                                  r["max"].max()),
                                                "sum": acc["sum"]})
    ref = _model(x, scale=2.0)
    np.testing.assert_array_equal(out["sum"], ref["sum"])
    assert sorted(calls)[-1] == 500 and len(calls) == 8
    assert float(np.max(best["max"])) == x.max()


def test_rich_progress_callback(capsys):
    from rich.console import Console

    with rich_progress("test", console=Console(file=None, force_terminal=False)) as cb:
        out = evaluate(np.square, np.arange(50.0), chunk_size=7, progress=cb)
    np.testing.assert_array_equal(out, np.arange(50.0) ** 2)


def _make(start, stop):
    return np.random.default_rng([7, start]).normal(size=(stop - start, 3))


def test_generated_candidates_in_process_and_on_dask():
    from dask.distributed import Client

    gen = Generated(1000, _make)
    made = []
    local = evaluate(lambda c: (made.append(len(c)), _model(c))[1], gen, chunk_size=250)
    assert made == [250] * 4
    direct = np.concatenate([_make(s, s + 250) for s in range(0, 1000, 250)])
    np.testing.assert_array_equal(local["sum"], direct.sum(axis=1))
    with Client(processes=False, dashboard_address=":0", n_workers=1,
                threads_per_worker=2) as client:
        dist = evaluate(_model, gen, chunk_size=250, client=client)
    np.testing.assert_array_equal(dist["sum"], local["sum"])
    with pytest.raises(ParameterError, match="n = -1"):
        Generated(-1, _make)


def _scaled_sum(x, *, weights, offset=0.0):
    """A model with inputs shared by every chunk: (N, 3) rows -> weighted sums + offset."""
    return np.asarray(x) @ weights + offset


def test_shared_inputs_in_process_and_scattered_once_on_dask(monkeypatch):
    """``shared`` reaches every chunk as keyword arguments; on a cluster it is scattered once
    (one broadcast of the whole mapping), not sent with each of the 8 tasks."""
    from dask.distributed import Client

    x = np.random.default_rng(2).normal(size=(500, 3))
    w = np.array([1.0, -2.0, 0.5])
    ref = x @ w + 3.0
    local = evaluate(_scaled_sum, x, chunk_size=64, shared={"weights": w, "offset": 3.0})
    np.testing.assert_array_equal(local, ref)
    with Client(processes=False, dashboard_address=":0", n_workers=2,
                threads_per_worker=1) as client:
        calls = []
        real = client.scatter

        def spy(data, **kw):
            calls.append((len(data), kw.get("broadcast")))
            return real(data, **kw)

        monkeypatch.setattr(client, "scatter", spy)
        dist = evaluate(_scaled_sum, x, chunk_size=64, client=client,
                        shared={"weights": w, "offset": 3.0})
    np.testing.assert_array_equal(dist, ref)
    assert calls == [(2, True)]


def test_shared_inputs_of_consecutive_calls_on_one_cluster():
    """Calls that share inputs under the same names, one after the other on the same cluster,
    each get their own data: scattered under the mapping's names, every second call's tasks
    were cancelled for 'lost dependencies' (or waited for ever) while the previous call's
    data under those names was released (20 of 40 calls failed on a process cluster)."""
    from dask.distributed import Client

    x = np.random.default_rng(3).normal(size=(200, 3))
    with Client(processes=False, dashboard_address=":0", n_workers=1,
                threads_per_worker=1) as client:
        for k in range(8):
            w = np.array([1.0, -2.0, 0.5]) * (k + 1)
            got = evaluate(_scaled_sum, x, chunk_size=50, client=client,
                           shared={"weights": w, "offset": float(k)})
            np.testing.assert_array_equal(got, x @ w + k)


def _slow_first(x):
    """Chunk 0 finishes last: results arrive out of order."""
    import time

    if x[0] == 0.0:
        time.sleep(0.3)
    return np.asarray(x, dtype=float)


def test_dask_combine_folds_in_candidate_order_as_results_arrive():
    """Results gathered as they complete are folded by ``combine`` in candidate order (the
    first chunk, which finishes last, still comes first), and the progress reaches N."""
    from dask.distributed import Client

    order = []

    def fold(acc, r):
        order.append(int(r[0]))
        return np.concatenate([acc, r])

    done = []
    with Client(processes=False, dashboard_address=":0", n_workers=2,
                threads_per_worker=1) as client:
        out = evaluate(_slow_first, np.arange(40.0), chunk_size=10, client=client,
                       combine=fold, progress=lambda d, t: done.append((d, t)))
    np.testing.assert_array_equal(out, np.arange(40.0))
    assert order == [10, 20, 30]
    assert done[-1] == (40, 40) and len(done) == 4


def test_aligned_copies_only_unaligned_arrays_everywhere_in_a_chunk():
    """Arrays that arrive over the network may start at any byte; ``aligned`` copies those
    (same values) in arrays, mappings, tuples and lists, and returns aligned arrays as they
    are."""
    from linkwork.sweep import aligned

    raw = bytearray(8 * 10 + 1)
    u = np.frombuffer(memoryview(raw)[1:], dtype=np.float64)
    u[...] = np.arange(10.0)
    assert not u.flags.aligned
    a = np.arange(5.0)
    out = aligned({"u": u, "a": a, "t": (u, 3), "l": [a, "x"]})
    assert out["u"].flags.aligned and np.array_equal(out["u"], np.arange(10.0))
    assert out["a"] is a and out["l"][0] is a and out["l"][1] == "x"
    assert out["t"][0].flags.aligned and out["t"][1] == 3 and isinstance(out["t"], tuple)
    assert aligned(u).flags.aligned and aligned(a) is a


def test_task_groups_guided_self_scheduling():
    """Tasks of a cluster by guided self-scheduling: each takes ceil(remaining / (2 threads))
    consecutive chunks, at most MAX_TASK_CHUNKS; together they cover every chunk once, in
    order. Counted by hand: 10 chunks on 2 threads -> 3, 2, 2, 1, 1, 1 (10/4 -> 3, 7/4 -> 2,
    5/4 -> 2, then single chunks); on 1 thread -> 5, 3, 1, 1."""
    def sizes(n, t):
        return [len(g) for g in task_groups(n, t)]

    assert sizes(10, 2) == [3, 2, 2, 1, 1, 1]
    assert sizes(10, 1) == [5, 3, 1, 1]
    assert sizes(4, 2) == [1, 1, 1, 1]
    assert sizes(0, 2) == [] and sizes(1, 8) == [1]
    for n, t in [(1000, 2), (37, 3), (9, 16)]:
        groups = task_groups(n, t)
        assert [i for g in groups for i in g] == list(range(n))
        assert max(len(g) for g in groups) <= MAX_TASK_CHUNKS
        assert all(len(g) == 1 for g in groups[-min(n, t):])   # the last tasks: one chunk
    with pytest.raises(ParameterError, match="threads"):
        task_groups(10, 0)


def _chunk_start(x):
    """Each candidate's result: the first candidate of the chunk it was evaluated in."""
    x = np.asarray(x)
    return np.full(len(x), x[0] if len(x) else -1.0)


def _make_index(start, stop):
    return np.arange(start, stop, dtype=float)


def test_dask_tasks_of_several_chunks_call_func_on_the_in_process_chunks():
    """On a cluster consecutive chunks travel as one task (10 chunks on 2 threads: 6 tasks),
    but ``func`` is still called once per chunk of ``chunk_size`` on the same candidates as
    in-process (each candidate's result names its chunk's first candidate), for arrays and for
    chunks generated on the workers; ``progress`` is called once per chunk and reaches N."""
    from dask.distributed import Client

    x = np.arange(95.0)
    local = evaluate(_chunk_start, x, chunk_size=10)
    np.testing.assert_array_equal(local, np.repeat(np.arange(0.0, 95.0, 10.0), 10)[:95])
    done = []
    with Client(processes=False, dashboard_address=":0", n_workers=2,
                threads_per_worker=1) as client:
        dist = evaluate(_chunk_start, x, chunk_size=10, client=client,
                        progress=lambda d, t: done.append((d, t)))
        gen = evaluate(_chunk_start, Generated(95, _make_index), chunk_size=10, client=client)
    np.testing.assert_array_equal(dist, local)
    np.testing.assert_array_equal(gen, local)
    assert len(done) == 10 and done[-1] == (95, 95)


def _fails_at_50(x):
    x = np.asarray(x)
    if x[0] == 50.0:
        raise ValueError("chunk 50 failed")
    return x * 1.0


def test_results_wait_on_the_workers_until_gather_bytes(monkeypatch):
    """On a cluster the first finished task's results are gathered at once (their size per
    candidate), the rest when GATHER_BYTES of them wait or after the last task: 95 candidates
    of 8 bytes in two gathers; with GATHER_BYTES = 0, one gather per batch of finished tasks.
    The results and the progress (once per chunk, reaching N) are the same either way, and a
    task's error is raised, not left waiting."""
    import distributed
    from dask.distributed import Client

    import linkwork.sweep as sweep

    calls = []
    real = distributed.Client.gather

    def spy(self, futures, *args, **kw):
        calls.append(len(futures))
        return real(self, futures, *args, **kw)

    monkeypatch.setattr(distributed.Client, "gather", spy)
    x = np.arange(95.0)
    local = evaluate(_chunk_start, x, chunk_size=10)
    with Client(processes=False, dashboard_address=":0", n_workers=2,
                threads_per_worker=1) as client:
        done: list[int] = []
        late = evaluate(_chunk_start, x, chunk_size=10, client=client,
                        progress=lambda d, t: done.append(d))
        assert len(calls) == 2 and sum(calls) == 6   # 10 chunks in 6 tasks
        assert len(done) == 10 and done[-1] == 95
        calls.clear()
        monkeypatch.setattr(sweep, "GATHER_BYTES", 0)
        done2: list[int] = []
        each = evaluate(_chunk_start, x, chunk_size=10, client=client,
                        progress=lambda d, t: done2.append(d))
        assert len(calls) >= 3 and sum(calls) == 6
        assert len(done2) == 10 and done2[-1] == 95
        monkeypatch.setattr(sweep, "GATHER_BYTES", 64 * 2**20)
        with pytest.raises(ValueError, match="chunk 50 failed"):
            evaluate(_fails_at_50, x, chunk_size=10, client=client)
        empty = evaluate(_chunk_start, x[:0], chunk_size=10, client=client)
    np.testing.assert_array_equal(late, local)
    np.testing.assert_array_equal(each, local)
    # no candidates: func on the empty selection, as in-process (divided by zero candidates
    # when the size per candidate was first learnt)
    assert empty.shape == (0,) and evaluate(_chunk_start, x[:0], chunk_size=10).shape == (0,)


def test_balance_cuts_smaller_chunks_on_a_cluster_only():
    """``balance=4`` on 2 worker threads: 95 candidates in chunks of 50 are cut into at least
    8 chunks, 8 of 12 (ceil(95 / 8)), or of ``min_chunk`` = 20 where that is larger; in-process
    the chunks stay those of ``chunk_size``; a Generated source refuses it; bad values name
    the parameter."""
    from dask.distributed import Client

    x = np.arange(95.0)
    assert np.array_equal(evaluate(_chunk_start, x, chunk_size=50, balance=4),
                          evaluate(_chunk_start, x, chunk_size=50))
    with Client(processes=False, dashboard_address=":0", n_workers=2,
                threads_per_worker=1) as client:
        done = []
        cut = evaluate(_chunk_start, x, chunk_size=50, client=client, balance=4,
                       progress=lambda d, t: done.append(d))
        floor = evaluate(_chunk_start, x, chunk_size=50, client=client, balance=4,
                         min_chunk=20)
        plain = evaluate(_chunk_start, x, chunk_size=50, client=client)
    np.testing.assert_array_equal(cut, np.repeat(np.arange(0.0, 95.0, 12.0), 12)[:95])
    assert len(done) == 8 and done[-1] == 95  # one call per chunk (in the order they finish)
    np.testing.assert_array_equal(floor, np.repeat(np.arange(0.0, 95.0, 20.0), 20)[:95])
    np.testing.assert_array_equal(plain, np.repeat([0.0, 50.0], [50, 45]))
    with pytest.raises(ParameterError, match="balance = 2 is invalid: must be 0 for "
                                             "Generated candidates"):
        evaluate(_chunk_start, Generated(95, _make_index), balance=2, client="tcp://x:1")
    with pytest.raises(ParameterError, match="balance = -1 is invalid"):
        evaluate(_chunk_start, x, balance=-1)
    with pytest.raises(ParameterError, match="min_chunk = 0 is invalid"):
        evaluate(_chunk_start, x, min_chunk=0)


def _varied(x):
    """Results of three kinds by chunk: float rows, then (from candidate 40 on) int rows."""
    x = np.asarray(x)
    return x * 2.0 if x[0] < 40 else (x * 2).astype(np.int64)


@pytest.mark.parametrize("model", [
    lambda c: c * 1.5,                                          # array
    lambda c: (c[:, 0] + c[:, 1], c[:, :2] * 2),                # tuple
    lambda c: {"s": c.sum(axis=1), "m": c.max(axis=1)},         # mapping
    lambda c: float(c.sum()),                                   # a scalar per chunk
])
def test_results_joined_as_they_arrive_equal_concatenation(model):
    """In-process and on a cluster the chunks' results are copied into arrays over all
    candidates as they arrive (in any order); the result equals the concatenation of the
    chunks' results in order, bit for bit and with the same dtypes, for arrays, tuples and
    mappings, and a result that does not run over its chunk (a scalar) falls back to the
    concatenation."""
    from dask.distributed import Client

    x = np.random.default_rng(4).normal(size=(103, 3))
    parts = [model(x[i:i + 10]) for i in range(0, 103, 10)]
    first = parts[0]
    if isinstance(first, dict):
        want = {k: np.concatenate([p[k] for p in parts]) for k in first}
    elif isinstance(first, tuple):
        want = tuple(np.concatenate([p[i] for p in parts]) for i in range(len(first)))
    else:
        want = np.concatenate([np.atleast_1d(p) for p in parts])
    with Client(processes=False, dashboard_address=":0", n_workers=2,
                threads_per_worker=1) as client:
        remote = evaluate(model, x, chunk_size=10, client=client)
    for got in (evaluate(model, x, chunk_size=10), remote):
        for g, w in (zip(got.values(), want.values(), strict=True) if isinstance(want, dict)
                     else zip(got, want, strict=True) if isinstance(want, tuple)
                     else [(got, want)]):
            assert g.dtype == w.dtype
            np.testing.assert_array_equal(g, w)


def test_results_of_changing_dtype_join_as_numpy_concatenates():
    """Chunks whose results change dtype half-way (float, then int) are joined as
    ``np.concatenate`` joins them (floats), the chunks placed before the change included."""
    x = np.arange(100.0)
    got = evaluate(_varied, x, chunk_size=10)
    want = np.concatenate([_varied(x[i:i + 10]) for i in range(0, 100, 10)])
    assert got.dtype == want.dtype == np.float64
    np.testing.assert_array_equal(got, want)
