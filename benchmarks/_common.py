"""What every benchmark here shares: interleaved sampling, min/median/max, ratios per round,
the machine's load, the agreement check of outputs, and the formatting of times.

Sampling: each round takes one sample of every contender of a case in turn (each sample
looping long enough to take ``min_time``), so that a burst of load from other processes on the
shared machine hits all of them alike. A contender's time is reported as min / median / max
over the rounds; a ratio of two contenders as min / median / max of the ratios of their
samples taken in the same round (paired), which is the spread a target must be judged against.
"""

from __future__ import annotations

import functools
import itertools
import os
import statistics
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass
class Spread:
    """Samples of one quantity (seconds per call, or a ratio): min, median, max."""

    samples: list[float] = field(default_factory=list)

    @property
    def min(self) -> float:
        return min(self.samples)

    @property
    def median(self) -> float:
        return statistics.median(self.samples)

    @property
    def max(self) -> float:
        return max(self.samples)

    def as_dict(self) -> dict[str, Any]:
        return {"min": self.min, "median": self.median, "max": self.max,
                "samples": list(self.samples)}


def time_rounds(fns: Sequence[Callable[[], Any]], repeat: int, min_time: float = 0.02,
                first: Sequence[float] | None = None, long_repeat: int | None = None,
                long_call: float = 1.0) -> list[Spread]:
    """Seconds per call of each function, sampled round-robin: ``repeat`` rounds, one sample of
    every function per round (functions whose call takes over ``long_call`` s only in the first
    ``long_repeat`` rounds). ``first``: the time of a call already made (sets the calls per
    sample); otherwise one untimed call is made for it (a warm-up)."""
    numbers, singles = [], []
    for i, fn in enumerate(fns):
        if first is None:
            t0 = time.perf_counter()
            fn()
            single = time.perf_counter() - t0
        else:
            single = first[i]
        singles.append(single)
        numbers.append(max(1, int(min_time / max(single, 1e-7))))
    rounds = [min(repeat, long_repeat) if long_repeat is not None and t > long_call else repeat
              for t in singles]
    out = [Spread() for _ in fns]
    for k in range(repeat):
        for i, fn in enumerate(fns):
            if k >= rounds[i]:
                continue
            t0 = time.perf_counter()
            for _ in range(numbers[i]):
                fn()
            out[i].samples.append((time.perf_counter() - t0) / numbers[i])
    return out


def ratio(a: Spread, b: Spread) -> Spread:
    """``a / b`` per round (the samples taken in the same round), over the rounds both have."""
    k = min(len(a.samples), len(b.samples))
    return Spread([x / y for x, y in zip(a.samples[:k], b.samples[:k], strict=True)])


def verdict(r: Spread, target: float, better: str = "below") -> str:
    """How a ratio stands against a target, judged against its spread: ``met`` (every round),
    ``met by the median only`` (the median, not every round), ``missed``."""
    def ok(x: float) -> bool:
        return x <= target if better == "below" else x >= target

    if ok(r.max if better == "below" else r.min):
        return "met"
    if ok(r.median):
        return "met by the median only"
    return "missed"


def load() -> float:
    """The 1-minute load average (the machine is shared: report it with every run)."""
    return os.getloadavg()[0]


def header(extra: str = "") -> str:
    """One line: versions, CPUs and the load average now."""
    return (f"numpy {np.__version__}, python {sys.version.split()[0]}, {os.cpu_count()} CPUs, "
            f"load average {load():.2f}{'; ' + extra if extra else ''}")


def finish(result: dict[str, Any], text: str, what: str, load0: float, t0: float,
           json_path: str | None = None) -> None:
    """Print the run's header (versions, ``what``, the load average before and now, the run's
    time) and ``text``; write ``result`` with the load averages to ``json_path`` if given."""
    import json

    print(header(f"{what}; load average {load0:.2f} before; run "
                 f"{time.perf_counter() - t0:.0f} s"))
    print(text)
    if json_path:
        with open(json_path, "w") as fh:
            json.dump({**result, "load_average": [load0, load()]}, fh, indent=1)


def fmt_time(s: float) -> str:
    if s < 1e-3:
        return f"{s * 1e6:.1f} us"
    if s < 1.0:
        return f"{s * 1e3:.2f} ms"
    return f"{s:.2f} s"


def fmt_spread(sp: Spread, unit: str = "time") -> str:
    """``min / median / max`` of times or of ratios."""
    if unit == "time":
        return f"{fmt_time(sp.min)} / {fmt_time(sp.median)} / {fmt_time(sp.max)}"
    return f"{sp.min:.2f} / {sp.median:.2f} / {sp.max:.2f}"


def max_rel_diff(got: Sequence[Any], want: Sequence[Any], angles: Sequence[int] = (),
                 groups: Sequence[Sequence[int]] = ()) -> float:
    """The largest difference of corresponding arrays, each relative to the largest value of
    its reference, or of its group's references (``groups``: indices of outputs that share a
    scale, e.g. the x and y of a vector); angles at the indices ``angles`` compared modulo
    2 pi. NaN on both sides counts as equal, on one side only as a disagreement (inf)."""
    g_all = [np.asarray(g, dtype=float) for g in got]
    w_all = [np.asarray(w, dtype=float) for w in want]
    if len(g_all) != len(w_all):
        return float("inf")

    def top(w: np.ndarray) -> float:
        return float(np.nanmax(np.abs(w))) if np.any(np.isfinite(w)) else 0.0

    scale = [top(w) for w in w_all]
    for grp in groups:
        s = max(scale[i] for i in grp)
        for i in grp:
            scale[i] = s
    worst = 0.0
    for i, (g, w) in enumerate(zip(g_all, w_all, strict=True)):
        if g.shape != w.shape:
            g, w = np.broadcast_arrays(g, w)
        if np.any(np.isnan(g) != np.isnan(w)):
            return float("inf")
        d = g - w
        if i in angles:
            d = (d + np.pi) % (2 * np.pi) - np.pi
        err = float(np.nanmax(np.abs(d))) if d.size else 0.0
        worst = max(worst, err / scale[i] if scale[i] > 0 else err)
    return worst


class PlainProcesses:
    """``w`` plain worker processes (``multiprocessing``, spawned, no Dask), started and warmed
    up once, with the environment a Dask nanny gives its workers
    (``distributed.nanny.pre-spawn-environ``: one BLAS thread, dask's malloc setting). A study
    runs on them as ``w`` equal consecutive shares of its candidates, one per process, each
    evaluated there in-process in the same chunks: no scheduler, no per-task cost, only the
    shares and their results cross between processes. Each process runs its share as a Dask
    worker runs a task (``linkwork.sweep._on_worker``: the chunks on aligned arrays inside
    ``sweep.roomy_heap``). What an executor of ``w`` processes can do on this machine at this
    moment at best: the bound a Dask cluster of ``w`` workers is judged against."""

    def __init__(self, w: int) -> None:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        try:
            import dask

            env = {k: str(v) for k, v in
                   (dask.config.get("distributed.nanny.pre-spawn-environ") or {}).items()}
        except ImportError:
            env = {}
        saved = {k: os.environ.get(k) for k in env}
        os.environ.update(env)   # inherited by the processes spawned now
        try:
            self.w = int(w)
            self.executor = ProcessPoolExecutor(self.w,
                                                mp_context=multiprocessing.get_context("spawn"))
            list(self.executor.map(time.sleep, [0.3] * self.w))   # w tasks at once: w spawned
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v
        started = len(self.executor._processes or {})
        if started != self.w:
            raise RuntimeError(f"{self.w} plain processes asked, {started} started")

    def evaluate(self, func: Callable[..., Any], candidates: Any, chunk_size: int) -> Any:
        """``func`` over ``candidates`` (an array, or a dict of arrays) in ``w`` shares, one per
        process; the results joined in order."""
        from linkwork.sweep import _join, _length, _on_worker, _take, chunk_slices

        cuts = [_length(candidates) * i // self.w for i in range(self.w + 1)]
        shares = [_take(candidates, slice(a, b)) for a, b in itertools.pairwise(cuts)]
        bounds = [[(c.start, c.stop) for c in chunk_slices(b - a, chunk_size)]
                  for a, b in itertools.pairwise(cuts)]
        # (functions of this module cannot travel: the tests load it under another name)
        parts = self.executor.map(_on_worker, [func] * self.w, shares, bounds, [{}] * self.w)
        return _join([r for part in parts for r in part])

    def close(self) -> None:
        self.executor.shutdown()


def cluster_rounds(workers: Sequence[int], inproc: Callable[[], Any],
                   on_cluster: Callable[[Any], Any], on_plain: Callable[[PlainProcesses], Any],
                   same: Callable[[Any, Any, str], None], repeat: int
                   ) -> list[dict[str, Any]]:
    """A study in-process, on a local Dask cluster of worker processes and on as many plain
    processes (:class:`PlainProcesses`), for each entry ``w`` of ``workers`` in turn, with
    only that cluster (``LocalCluster(n_workers=w, threads_per_worker=1, processes=True)``,
    dask's default worker settings: what a ``--scheduler`` address gives on one machine) and
    its plain processes alive: an idle cluster's processes took 3-6.5 % of a core each on this
    machine, CPU the measured one would lose. The three are sampled round-robin, ``repeat``
    rounds (``inproc()``, ``on_cluster(client)``, ``on_plain(processes)``); their results are
    checked first, ``same(got, in_process, label)``. Returns one row per ``w``: the samples
    of each and the CPU split (:func:`cpu_split`) in-process and on the cluster."""
    import logging

    from dask.distributed import Client, LocalCluster

    logging.getLogger("distributed").setLevel(logging.ERROR)
    rows = []
    for w in workers:
        label = f"process cluster, {w} worker{'s' if w > 1 else ''}"
        plain_label = f"{w} plain process{'es' if w > 1 else ''}"
        cluster = LocalCluster(n_workers=w, threads_per_worker=1, processes=True,
                               dashboard_address=":0", silence_logs=logging.ERROR)
        client = Client(cluster)
        plain = PlainProcesses(w)
        try:
            fns: list[Callable[[], Any]] = [inproc, functools.partial(on_cluster, client),
                                            functools.partial(on_plain, plain)]
            firsts, results = [], []
            for fn in fns:                      # warm-up, agreement, calibration
                t0 = time.perf_counter()
                results.append(fn())
                firsts.append(time.perf_counter() - t0)
            same(results[1], results[0], label)
            same(results[2], results[0], plain_label)
            del results
            times = time_rounds(fns, repeat, first=firsts)
            cpu = {"in-process": cpu_split(inproc), label: cpu_split(fns[1], client)}
        finally:
            plain.close()
            client.close()
            cluster.close()
        rows.append({"workers": w, "cluster": label, "plain": plain_label,
                     "times": {"in-process": times[0].samples, "cluster": times[1].samples,
                               "plain": times[2].samples}, "cpu": cpu})
    return rows


def cluster_lines(rows: Sequence[dict[str, Any]], what: str, target: float = 1.6,
                  markdown: bool = False) -> list[str]:
    """The table of :func:`cluster_rounds`: each executor's time, its speed-up over
    in-process per round, and the cluster's share of the plain processes' speed-up (Dask's own
    cost); the target judged against the spread for 2 workers (issue 20)."""
    out = ["", f"{what} on local process clusters, one cluster alive at a time (speed-ups: "
           "in-process time / time, per round):"]
    cells = ["executor", "workers", "min / median / max", "speed-up min / median / max",
             "cluster / plain processes"]
    if markdown:
        out += ["| " + " | ".join(cells) + " |", "|---|---:|---:|---:|---:|"]
    for r in rows:
        t = {k: Spread(list(v)) for k, v in r["times"].items()}
        share = ratio(t["plain"], t["cluster"])
        for key, name in (("in-process", "in-process"), ("cluster", r["cluster"]),
                          ("plain", r["plain"])):
            sp = ratio(t["in-process"], t[key])
            line = [name, str(r["workers"]), fmt_spread(t[key]),
                    "1" if key == "in-process" else fmt_spread(sp, "ratio"),
                    fmt_spread(share, "ratio") if key == "cluster" else ""]
            if markdown:
                out.append("| " + " | ".join(line) + " |")
            else:
                out.append(f"  {line[0]:32s} {line[1]:>2s} {line[2]:>30s} {line[3]:>20s} "
                           f"{line[4]:>20s}")
        if r["workers"] == 2:
            sp = ratio(t["in-process"], t["cluster"])
            bound = ratio(t["in-process"], t["plain"])
            out.append(f"  target: 2 workers >= {target:g}x in-process (issue 20): "
                       f"{verdict(sp, target, 'above')} (median {sp.median:.2f}); 2 plain "
                       f"processes, the machine's bound this run: {bound.median:.2f} "
                       f"({verdict(bound, target, 'above')})")
    for r in rows:
        out += cpu_lines(r["cpu"])
    return out


def _process_cpu() -> float:
    """CPU seconds (user + system) of this process so far (run on a worker by the client)."""
    t = os.times()
    return t.user + t.system


def cpu_split(fn: Callable[[], Any], client: Any = None, repeat: int = 3) -> dict[str, Any]:
    """CPU seconds that one call of ``fn`` costs, median of ``repeat`` calls: in this process
    (``client``), and with a dask ``client`` on its scheduler (``scheduler``; None when the
    scheduler runs in this process, as a ``LocalCluster``'s does: it is then counted in
    ``client`` once) and on each of its workers (``workers``: sorted, the busiest last). Unlike
    wall time this does not depend on other load of the machine: the busiest process bounds
    the wall time the call would take on free cores."""
    own = client is not None and client.run_on_scheduler(os.getpid) == os.getpid()
    runs: list[dict[str, Any]] = []
    for _ in range(repeat):
        w0 = client.run(_process_cpu) if client is not None else {}
        s0 = client.run_on_scheduler(_process_cpu) if client is not None and not own else 0.0
        c0 = _process_cpu()
        fn()
        c1 = _process_cpu()
        w1 = client.run(_process_cpu) if client is not None else {}
        s1 = client.run_on_scheduler(_process_cpu) if client is not None and not own else 0.0
        runs.append({"client": c1 - c0, "scheduler": s1 - s0,
                     "workers": sorted(w1[k] - w0[k] for k in w0)})
    out: dict[str, Any] = {"client": statistics.median(r["client"] for r in runs)}
    if client is not None:
        out["scheduler"] = None if own else statistics.median(r["scheduler"] for r in runs)
        n = len(runs[0]["workers"])
        out["workers"] = [statistics.median(r["workers"][i] for r in runs) for i in range(n)]
    return out


def cpu_lines(cpu: dict[str, dict[str, Any]]) -> list[str]:
    """The CPU seconds of :func:`cpu_split` per executor, and the speed-up the busiest process
    allows on free cores (in-process CPU / busiest process's CPU: a bound, not a measurement)."""
    if not cpu:
        return []
    base = cpu["in-process"]["client"]
    cores = os.cpu_count() or 1
    out = ["", "CPU seconds per call (median of 3; load-independent): in-process "
           f"{base:.2f} s"]
    for label, c in cpu.items():
        if label == "in-process":
            continue
        sched = c.get("scheduler")
        busiest = max([c["client"], *c["workers"]])
        total = c["client"] + (sched or 0.0) + sum(c["workers"])
        # os.times counts in clock ticks (10 ms): a tiny call may read 0 s in every process
        bound = (f"{base / busiest:.2f} (the speed-up on free cores at most)" if busiest > 0
                 else "undefined (below the CPU clock's 10 ms resolution)")
        # all processes on this machine's cores: at least total / cores of wall time
        here = (f"; in-process / (all / {cores} cores) = {base * cores / total:.2f} (the "
                "speed-up on this machine at most)" if total > 0 else "")
        who = (f"client and scheduler (one process) {c['client']:.2f} s" if sched is None
               else f"client {c['client']:.2f} s, scheduler {sched:.2f} s")
        out.append(f"  {label}: {who}, workers " + ", ".join(f"{w:.2f}" for w in c["workers"])
                   + f" s (all {total:.2f} s); in-process / busiest process = {bound}{here}")
    return out
