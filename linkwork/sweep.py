"""Chunked evaluation of a vectorised function over many candidates (sweeps, synthesis searches,
Monte-Carlo studies).

One function, :func:`evaluate`: it splits ``N`` candidates into chunks of ``chunk_size``, calls
a vectorised ``func`` on each chunk and joins the results in the original order. Memory stays
bounded by the chunk (a function that works on ``(chunk, n_angles)`` arrays never sees all
``N`` at once). It runs in-process by default; given a dask.distributed ``Client`` or a
scheduler address it spreads the chunks over that cluster instead (DESIGN.md, principle 7) --
same call, same result.

Example
-------
>>> import numpy as np
>>> from linkwork.sweep import evaluate
>>> x = np.linspace(0.0, 1.0, 100_001)
>>> y = evaluate(np.sqrt, x, chunk_size=10_000)          # in-process, 11 chunks
>>> bool(np.allclose(y, np.sqrt(x)))
True

With a cluster (``func`` must then be picklable: a module-level function or a
``functools.partial`` of one)::

    from dask.distributed import Client
    with Client("tcp://scheduler:8786") as client:
        y = evaluate(my_model, candidates, client=client)
    y = evaluate(my_model, candidates, client="tcp://scheduler:8786")  # connects and closes

Monte-Carlo samples made chunk by chunk (never all in memory)::

    def make(start, stop):
        rng = np.random.default_rng([42, start])
        return rng.normal(size=(stop - start, 3))
    stats = evaluate(model, Generated(10**8, make), combine=merge_stats)

A progress bar::

    with rich_progress("designs") as progress:
        y = evaluate(my_model, candidates, progress=progress)

Inputs every chunk needs (a model's matrices, a request) go in ``shared``: ``func`` is called
as ``func(chunk, **shared)``; on a cluster they are sent to every worker once
(``Client.scatter(..., broadcast=True)``), not inside every task::

    y = evaluate(peaks_of, draws, shared={"zmat": zmat}, client=client)

On a cluster the chunks go out as tasks of consecutive chunks (:func:`task_groups`: guided
self-scheduling, large tasks first and single chunks last, so that few tasks carry Dask's
per-task cost and the workers still finish together; ``func`` is still called once per chunk,
on the same chunks as in-process), submitted at once. ``progress`` is called once per chunk as
its task finishes; the results stay on the workers until about :data:`GATHER_BYTES` of them
can be gathered in one ``gather`` (the first task's at once, to learn their size; the rest
after the last task), each released on the workers as soon as it is here; ``combine`` folds
them in candidate order as soon as the next one in order is in.

Worker malloc settings: :mod:`linkwork.heap` (every task on a cluster runs inside
:func:`linkwork.heap.roomy_heap`).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Any

import numpy as np

from linkwork.errors import MissingExtraError, ParameterError
from linkwork.heap import roomy_heap

__all__ = [
    "DASK_INSTALL",
    "GATHER_BYTES",
    "MAX_TASK_CHUNKS",
    "Generated",
    "aligned",
    "check_client",
    "chunk_slices",
    "evaluate",
    "rich_progress",
    "roomy_heap",
    "task_groups",
]

#: How to install the optional dask extra (named by every "needs dask" message).
DASK_INSTALL = "pip install 'linkwork[dask]'"

# [scheme://]host[:port], host a name, an IPv4 address or a bracketed IPv6 address
_ADDRESS = re.compile(r"(?:(?P<scheme>[a-z]+)://)?(?P<host>\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+)"
                      r"(?::(?P<port>[0-9]{1,5}))?")
_SCHEMES = ("tcp", "tls", "ucx", "ws", "wss")

#: A progress callback: called as ``progress(done, total)`` with numbers of candidates.
Progress = Callable[[int, int], None]


def chunk_slices(n: int, chunk_size: int) -> list[slice]:
    """Slices that cover ``range(n)`` in order, each at most ``chunk_size`` long."""
    if int(chunk_size) < 1:
        raise ParameterError("chunk_size", chunk_size, "must be an integer >= 1")
    if int(n) < 0:
        raise ParameterError("n", n, "must be >= 0")
    cs = int(chunk_size)
    return [slice(i, min(i + cs, int(n))) for i in range(0, int(n), cs)]


#: On a cluster, finished tasks' results wait on the workers until about this many bytes of
#: them can be gathered at once (or the last task is done): bounds what the workers hold, and
#: spares them gathers while they compute (:func:`evaluate`).
GATHER_BYTES = 64 * 2**20


def _nbytes(res: Any) -> int:
    """Bytes of a chunk's result: its arrays (an array, a tuple or a mapping of them)."""
    if isinstance(res, Mapping):
        return sum(_nbytes(v) for v in res.values())
    if isinstance(res, (tuple, list)):
        return sum(_nbytes(v) for v in res)
    return int(getattr(res, "nbytes", 0))


#: The most chunks one task of a cluster carries (:func:`task_groups`): bounds the work lost
#: with a failed worker, the results a worker holds at once, and the wait between progress
#: updates.
MAX_TASK_CHUNKS = 8


def task_groups(n_chunks: int, threads: int) -> list[range]:
    """Consecutive chunk indices of each task of a cluster with ``threads`` worker threads in
    all, by guided self-scheduling (Polychronopoulos and Kuck, IEEE Trans. Computers C-36,
    1987): each task takes ``ceil(remaining / (2 threads))`` chunks, at most
    :data:`MAX_TASK_CHUNKS` and at least one.

    The first tasks are large, so that Dask's cost per task (a few ms of scheduler, client and
    worker CPU: messages, transitions, a gather) is paid a few times rather than once per
    chunk; the last ``2 threads`` or so are single chunks, so that a worker that finishes early
    takes the rest in small pieces and the workers finish together. 10 chunks on 2 threads:
    tasks of 3, 2, 2, 1, 1, 1 chunks.
    """
    if int(n_chunks) < 0:
        raise ParameterError("n_chunks", n_chunks, "must be >= 0")
    if int(threads) < 1:
        raise ParameterError("threads", threads, "must be an integer >= 1")
    out, i, n = [], 0, int(n_chunks)
    while i < n:
        k = min(MAX_TASK_CHUNKS, max(1, -(-(n - i) // (2 * int(threads)))))
        out.append(range(i, i + k))
        i += k
    return out


class Generated:
    """Candidates made chunk by chunk: ``make(start, stop)`` returns candidates
    ``start .. stop-1`` (an array or a dict of arrays, first axis over them), ``n`` in all.

    For Monte-Carlo studies too large to hold as one array: only one chunk exists at a time
    (on a cluster, it is made on the worker). Derive random streams from ``start`` (e.g.
    ``np.random.default_rng([seed, start])``) so the result does not depend on the chunking
    order.
    """

    def __init__(self, n: int, make: Callable[[int, int], Any]) -> None:
        if int(n) < 0:
            raise ParameterError("n", n, "must be >= 0")
        self.n = int(n)
        self.make = make

    def __len__(self) -> int:
        return self.n


def aligned(value: Any) -> Any:
    """``value`` with every NumPy array in it (itself, or the values of a mapping, tuple or
    list) aligned in memory, copied where it is not.

    Arrays that arrive over the network (Dask's frames) may start at any byte: NumPy then
    copies an unaligned operand for BLAS (``matmul``) at every call, and buffers it through
    every ufunc. Measured on a Dask worker: the tolerance study's affine map arrived unaligned
    and its kernel page-faulted 5 500 times a chunk and took 1.7x its time.
    """
    if isinstance(value, np.ndarray):
        return value if value.flags.aligned else np.require(value, requirements=["A"])
    if isinstance(value, Mapping):
        return {k: aligned(v) for k, v in value.items()}
    if isinstance(value, tuple | list):
        return type(value)(aligned(v) for v in value)
    return value


def _on_worker(func: Callable[..., Any], candidates: Any, bounds: Sequence[tuple[int, int]],
               shared: Mapping[str, Any]) -> list[Any]:
    """One task on a cluster worker: ``func(chunk, **shared)`` for each chunk ``bounds``
    (start, stop within the task's ``candidates``), on aligned arrays (:func:`aligned`),
    inside :func:`roomy_heap`; the chunks' results in order."""
    with roomy_heap():
        cand, kw = aligned(candidates), aligned(shared)
        return [func(_take(cand, slice(a, b)), **kw) for a, b in bounds]


def _make_on_worker(func: Callable[..., Any], make: Callable[[int, int], Any],
                    bounds: Sequence[tuple[int, int]], shared: Mapping[str, Any]) -> list[Any]:
    """One task of generated chunks on a cluster worker: each made there, then evaluated."""
    with roomy_heap():
        kw = aligned(shared)
        return [func(make(a, b), **kw) for a, b in bounds]


def _length(candidates: Any) -> int:
    if isinstance(candidates, Generated):
        return candidates.n
    if isinstance(candidates, Mapping):
        lengths = {k: len(np.asarray(v)) for k, v in candidates.items()}
        if not lengths:
            raise ParameterError("candidates", "{}", "must not be an empty mapping")
        if len(set(lengths.values())) != 1:
            raise ParameterError("candidates", lengths, "all arrays must have the same length")
        return next(iter(lengths.values()))
    arr = np.asarray(candidates)
    if arr.ndim == 0:
        raise ParameterError("candidates", candidates, "must be an array or a mapping of arrays "
                             "with the candidates on the first axis")
    return int(arr.shape[0])


def _take(candidates: Any, sl: slice) -> Any:
    if isinstance(candidates, Generated):
        return candidates.make(sl.start, sl.stop)
    if isinstance(candidates, Mapping):
        return {k: np.asarray(v)[sl] for k, v in candidates.items()}
    return np.asarray(candidates)[sl]


def _join(parts: Sequence[Any]) -> Any:
    first = parts[0]
    if isinstance(first, Mapping):
        return {k: np.concatenate([np.atleast_1d(np.asarray(p[k])) for p in parts])
                for k in first}
    if isinstance(first, tuple):
        return tuple(np.concatenate([np.atleast_1d(np.asarray(p[i])) for p in parts])
                     for i in range(len(first)))
    return np.concatenate([np.atleast_1d(np.asarray(p)) for p in parts])


class _Joined:
    """The chunks' results joined along the first axis as they arrive: what :func:`_join` of
    all of them in order gives, built in arrays over all ``n`` candidates that are made when
    the first result arrives, each result copied in (and let go) when it comes. No
    concatenation at the end (on a cluster: after the last result, while the workers idle),
    and one copy of the results in memory instead of two. A result whose arrays do not run
    over their chunk's candidates, or differ in structure, dtype or trailing shape from the
    first, is kept as it is, and the whole is then joined by :func:`_join` at the end."""

    def __init__(self, slices: Sequence[slice], n: int) -> None:
        self.slices, self.n = slices, n
        self.out: Any = None           # array, tuple or dict of arrays over all n candidates
        self.kind: tuple[Any, ...] = ()
        self.placed: list[int] = []
        self.kept: dict[int, Any] | None = None   # set when results cannot be placed

    @staticmethod
    def _leaves(res: Any) -> tuple[Any, list[Any]]:
        """(structure, arrays) of a result: an array, a tuple or a mapping of arrays."""
        if isinstance(res, Mapping):
            return ("mapping", tuple(res)), list(res.values())
        if isinstance(res, tuple):
            return ("tuple", len(res)), list(res)
        return ("array",), [res]

    def _place(self, i: int, res: Any) -> bool:
        kind, leaves = self._leaves(res)
        sl = self.slices[i]
        if not all(isinstance(a, np.ndarray) and a.ndim >= 1 and len(a) == sl.stop - sl.start
                   for a in leaves):
            return False
        if self.out is None:
            arrays = [np.empty((self.n, *a.shape[1:]), a.dtype) for a in leaves]
            self.kind = kind
            self.out = (dict(zip(kind[1], arrays, strict=True)) if kind[0] == "mapping"
                        else tuple(arrays) if kind[0] == "tuple" else arrays[0])
        if kind != self.kind:
            return False
        targets = self._leaves(self.out)[1]
        if any(a.dtype != t.dtype or a.shape[1:] != t.shape[1:]
               for a, t in zip(leaves, targets, strict=True)):
            return False
        for a, t in zip(leaves, targets, strict=True):
            t[sl] = a
        self.placed.append(i)
        return True

    def add(self, i: int, res: Any) -> None:
        """The result of chunk ``i`` (any order)."""
        if self.kept is None and self._place(i, res):
            return
        if self.kept is None:   # from now on keep every result; the placed ones as views
            self.kept = {j: self._view(j) for j in self.placed}
        self.kept[i] = res

    def _view(self, j: int) -> Any:
        sl = self.slices[j]
        if isinstance(self.out, dict):
            return {k: v[sl] for k, v in self.out.items()}
        if isinstance(self.out, tuple):
            return tuple(v[sl] for v in self.out)
        return self.out[sl]

    def result(self) -> Any:
        """The joined results of all chunks."""
        if self.kept is None:
            return self.out
        return _join([self.kept[j] for j in range(len(self.slices))])


def check_client(client: Any, *, option: str = "client") -> None:
    """Check a ``client`` argument of :func:`evaluate` before any work is done.

    ``None`` and a ``Client`` object pass. A scheduler address must read
    ``[scheme://]host[:port]`` (scheme tcp, tls, ucx, ws or wss; port 1-65535), else a
    :class:`~linkwork.errors.ParameterError` naming ``option``; dask.distributed must be
    installed, else a :class:`~linkwork.errors.MissingExtraError` naming ``pip install
    'linkwork[dask]'``. A well-formed address is not contacted here.
    """
    if client is None:
        return
    if isinstance(client, str):
        m = _ADDRESS.fullmatch(client)
        port = m and m["port"]
        if (m is None or (m["scheme"] is not None and m["scheme"] not in _SCHEMES)
                or (port and not 1 <= int(port) <= 65535)):
            raise ParameterError(option, client, "must be a dask scheduler address "
                                 "[scheme://]host[:port], e.g. tcp://10.0.0.1:8786 (scheme "
                                 f"{', '.join(_SCHEMES)}; port 1-65535)")
    try:
        import dask.distributed  # noqa: F401  (optional dependency)
    except ImportError:
        raise MissingExtraError(option, "dask", DASK_INSTALL) from None


def evaluate(func: Callable[..., Any], candidates: Any, *, chunk_size: int = 10_000,
             client: Any = None, progress: Progress | None = None,
             combine: Callable[[Any, Any], Any] | None = None,
             shared: Mapping[str, Any] | None = None, balance: int = 0,
             min_chunk: int = 1) -> Any:
    """Evaluate a vectorised ``func`` over candidates, chunk by chunk.

    Parameters
    ----------
    func : callable
        Takes one chunk of ``candidates`` (same type: an array slice, or a dict of array
        slices) and the ``shared`` inputs as keyword arguments, and returns an array, a tuple
        of arrays or a dict of arrays whose first axis runs over the chunk's candidates.
    candidates : ndarray, mapping of str to ndarray, or Generated
        ``N`` candidates along the first axis (e.g. an ``(N, k)`` parameter matrix, or
        ``{"r": (N,), "l": (N,)}``), or a :class:`Generated` that makes each chunk on demand.
    chunk_size : int
        Candidates per call of ``func``; bounds the memory ``func`` uses. On a cluster a task
        carries one or more consecutive chunks (:func:`task_groups`), ``func`` is still called
        on each chunk alone.
    client : dask.distributed.Client or str, optional
        Run the chunks on this cluster (a ``Client``, or a scheduler address such as
        ``"tcp://10.0.0.1:8786"``, connected for this call and closed afterwards). ``None``:
        in-process, in order. On a cluster the finished tasks' results are gathered in
        batches of about :data:`GATHER_BYTES` (and after the last task), not while every
        task finishes.
    progress : callable, optional
        ``progress(done, total)`` after each finished chunk (numbers of candidates).
    combine : callable, optional
        ``combine(accumulated, chunk_result) -> accumulated``, applied to the chunk results in
        order (the first result starts the accumulation); use it to keep only a summary
        (best-k, histograms, running sums) so that results need not fit in memory either.
    shared : mapping of str to object, optional
        Inputs every chunk needs, passed to ``func`` as keyword arguments; on a cluster they
        travel to each worker once (scattered before the chunks), not with every task.
    balance, min_chunk : int
        On a cluster, smaller chunks where needed so that each worker thread has at least
        ``balance`` of them (0: the chunks as ``chunk_size`` makes them), none below
        ``min_chunk`` candidates: the last tasks are then short, and a worker slowed by other
        load waits less for the others. Only for a ``func`` whose results do not depend on
        where the chunks are cut (not for a :class:`Generated` that makes each chunk from a
        seed of its own).

    Returns
    -------
    Same structure as one ``func`` result, joined along the first axis in candidate order, or
    the final accumulated value when ``combine`` is given. ``N = 0`` returns ``func`` applied
    to the empty selection.
    """
    check_client(client)
    if isinstance(balance, bool) or not isinstance(balance, int) or balance < 0:
        raise ParameterError("balance", balance, "must be an integer >= 0")
    if isinstance(min_chunk, bool) or not isinstance(min_chunk, int) or min_chunk < 1:
        raise ParameterError("min_chunk", min_chunk, "must be an integer >= 1")
    if balance and isinstance(candidates, Generated):
        raise ParameterError("balance", balance, "must be 0 for Generated candidates (each "
                             "chunk is made from a seed of its own: smaller chunks would "
                             "change the candidates)")
    n = _length(candidates)
    slices = chunk_slices(n, chunk_size) or [slice(0, 0)]
    kw = dict(shared or {})
    if client is None:
        joined = _Joined(slices, n)
        acc: Any = None
        for i, sl in enumerate(slices):
            res = func(_take(candidates, sl), **kw)
            if combine is None:
                joined.add(i, res)
            else:
                acc = res if i == 0 else combine(acc, res)
            del res
            if progress is not None:
                progress(sl.stop, n)
        return joined.result() if combine is None else acc
    return _evaluate_dask(func, candidates, slices, n, client, progress, combine, kw,
                          balance, min_chunk)


def _evaluate_dask(func: Callable[..., Any], candidates: Any, slices: list[slice], n: int,
                   client: Any, progress: Progress | None,
                   combine: Callable[[Any, Any], Any] | None, shared: dict[str, Any],
                   balance: int = 0, min_chunk: int = 1) -> Any:
    from dask.distributed import Client, as_completed

    own = isinstance(client, str)
    cl = Client(client) if own else client
    futures: list[Any] = []  # Future or None (gathered)
    try:
        # the shared inputs go to every worker once; the tasks refer to them. Scattered as a
        # list (random keys): a mapping's own keys would become the data's keys on the
        # cluster, and the same name scattered again by the next call while the previous
        # call's data under that name is being released got the new tasks cancelled ('lost
        # dependencies') or left waiting for ever (every second call on a process cluster)
        names = list(shared)
        scattered = (dict(zip(names, cl.scatter([shared[k] for k in names], broadcast=True,
                                                hash=False), strict=True)) if shared else {})
        threads = max(1, sum(cl.nthreads().values()))
        if balance and n and len(slices) < balance * threads:
            size = max(int(min_chunk), -(-n // (balance * threads)))
            slices = chunk_slices(n, min(size, slices[0].stop - slices[0].start))
        groups = task_groups(len(slices), threads)
        tasks = [(slices[g[0]].start, slices[g[-1]].stop) for g in groups]
        if isinstance(candidates, Generated):  # make each chunk on its worker
            futures = list(cl.map(functools.partial(_make_on_worker, func, candidates.make),
                                  [[(slices[i].start, slices[i].stop) for i in g]
                                   for g in groups], shared=scattered, pure=False))
        else:
            futures = list(cl.map(functools.partial(_on_worker, func),
                                  [_take(candidates, slice(lo, hi)) for lo, hi in tasks],
                                  [[(slices[i].start - lo, slices[i].stop - lo) for i in g]
                                   for g, (lo, _) in zip(groups, tasks, strict=True)],
                                  shared=scattered, pure=False))
        index = {f.key: t for t, f in enumerate(futures)}
        results: dict[int, Any] = {}   # chunk results waiting to be folded by combine
        joined = _Joined(slices, n)
        acc: Any = None
        folded = 0   # chunks folded by combine, in order
        done = 0
        pending: list[Any] = []   # finished tasks whose results are still on the workers
        held = 0                  # their candidates
        per: float | None = None  # bytes per candidate of the results gathered so far
        for batch in as_completed(futures).batches():
            for fut in batch:
                t = index[fut.key]
                for i in groups[t]:
                    done += slices[i].stop - slices[i].start
                    if progress is not None:
                        progress(done, n)
                held += tasks[t][1] - tasks[t][0]
            pending += batch
            del batch
            # the results stay on the workers until GATHER_BYTES of them are waiting (the
            # first task's is gathered at once, to learn their size) or the last task is done:
            # a gather while the workers compute costs them CPU (2 workers on 2 cores: the
            # tolerance study 30-40 ms slower with a gather per finished task); an error is
            # raised at once
            if (per is not None and held * per < GATHER_BYTES and done < n
                    and all(f.status != "error" for f in pending)):
                continue
            got = cl.gather(pending, direct=True)
            size = 0
            for fut, parts in zip(pending, got, strict=True):
                t = index[fut.key]
                futures[t] = None  # released on the workers once nothing refers to it
                for i, res in zip(groups[t], parts, strict=True):
                    size += _nbytes(res)
                    if combine is None:
                        joined.add(i, res)
                    else:
                        results[i] = res
            if held:   # (none for an empty set of candidates: one task of an empty chunk)
                per = max(per or 0.0, size / held)
            pending, held = [], 0
            del got, parts
            res = None
            if combine is not None:  # fold the chunks that are next in order
                while folded in results:
                    res = results.pop(folded)
                    acc = res if folded == 0 else combine(acc, res)
                    folded += 1
        return acc if combine is not None else joined.result()
    finally:
        for fut in futures:  # an error or an interrupt: cancel what is still running
            if fut is not None:
                fut.cancel()
        if own:
            cl.close()


@contextmanager
def rich_progress(description: str = "evaluating", *, console: Any = None,
                  transient: bool = False) -> Iterator[Progress]:
    """A Rich progress bar as a ``progress(done, total)`` callback (context manager).

    ``transient=True`` erases the bar when done (keeps a failing command's stderr to its
    one error line).
    """
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

    with Progress("[progress.description]{task.description}", BarColumn(),
                  MofNCompleteColumn(), TimeElapsedColumn(), console=console,
                  transient=transient) as bar:
        task = bar.add_task(description, total=None)

        def update(done: int, total: int) -> None:
            bar.update(task, completed=done, total=total)

        yield update
