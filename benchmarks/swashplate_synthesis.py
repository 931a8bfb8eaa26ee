"""Candidates screened per second by the swash-plate synthesis (paper 003), in-process and on
local dask clusters of worker processes.

Contenders, on the same scrambled Sobol candidates of scheme 1 (r, l, alpha, a, b), R = 100 mm:

``loop (per candidate)``    ``linkwork.models.swashplate.characteristics`` on one design at a
                            time (exact, 720-angle grid) on ``--loop-n`` candidates: the
                            reference of the characteristics (information: another algorithm
                            per design);
``vectorised``              ``linkwork.synthesis.swashplate.evaluate_candidates`` through
                            ``linkwork.sweep.evaluate`` in chunks of 4096 (characteristics and
                            constraint violations, 120-angle grid refined to machine precision);
``screen``                  the screening step of ``synthesize`` (rod and stroke repair, 6
                            passes, then evaluation) in chunks of 4096, in-process;
``screen, dask ...``        the same chunks on ``LocalCluster(processes=True)`` with
                            ``--workers`` worker processes (1 thread each, dask's default worker
                            settings): what ``linkwork swashplate synthesize --scheduler``
                            gives; one cluster alive at a time, sampled round-robin with the
                            in-process screening and with ``w plain processes`` (equal shares
                            of the candidates on spawned processes, no Dask: the machine's
                            bound for an executor of processes at that moment).

Agreement, before timing: the vectorised characteristics (H, both pressure angles, max |Pi_v|)
of all ``--loop-n`` loop candidates equal the loop's to 1e-10 (of max(1, |value|)); every
cluster's and the plain processes' screening equals the in-process screening exactly (every key,
every candidate, NaN where NaN). Timing: ``--repeat`` rounds, one sample of every contender per
round; min / median / max; the speed-up of an executor is the in-process screening time over
its own, per round.

Usage::

    .venv/bin/python benchmarks/swashplate_synthesis.py [--n 16384] [--loop-n 300]
        [--workers 1 2] [--repeat 5] [--no-dask] [--markdown] [--json out.json]
"""

from __future__ import annotations

import argparse
import functools
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from scipy.stats import qmc

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import (
    PlainProcesses,
    Spread,
    cluster_lines,
    cluster_rounds,
    finish,
    fmt_spread,
    load,
    time_rounds,
)

from linkwork.models import swashplate as sw
from linkwork.sweep import evaluate
from linkwork.synthesis import swashplate as syn

CHUNK = 4096


def problem(n: int) -> tuple[syn.Request, list[tuple[float, float]], np.ndarray]:
    """The request (scheme 1, R 100 mm, H 60 mm +- 0.5 mm, pressure angles <= 8 deg), its
    search bounds and ``n`` Sobol candidates in them."""
    req = syn.Request(scheme="1", R=0.1, H=0.06, H_tol=5e-4, delta_f=8 * math.pi / 180,
                      delta_r=8 * math.pi / 180)
    bounds = req.search_bounds()
    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    m = max(1, math.ceil(math.log2(n)))
    X = lo + qmc.Sobol(len(bounds), scramble=True, seed=1).random_base2(m)[:n] * (hi - lo)
    return req, bounds, X


def loop(req: syn.Request, Xs: np.ndarray) -> list[sw.Characteristics | None]:
    """The characteristics one design at a time (None: the rod cannot reach)."""
    out: list[sw.Characteristics | None] = []
    for x in Xs:
        R, r, l, al, a, b = (float(v[0]) for v in syn._full_params(req, x[None, :]))
        try:
            out.append(sw.characteristics(R, r, l, al, a, b))
        except ValueError:  # the rod cannot reach: counted as evaluated
            out.append(None)
    return out


def check_loop(ref: list[sw.Characteristics | None], vec: dict[str, np.ndarray]) -> float:
    """Vectorised characteristics against the loop's; the largest difference."""
    worst = 0.0
    for i, c in enumerate(ref):
        if c is None:
            if not np.isnan(vec["H"][i]):
                raise AssertionError(f"candidate {i}: the loop finds no reach, vectorised does")
            continue
        for key, val in (("H", c.H), ("delta_f", c.delta_f), ("delta_r", c.delta_r),
                         ("Pi_v_max", c.Pi_v_max)):
            err = abs(vec[key][i] - val) / max(1.0, abs(val))
            worst = max(worst, err)
            if not err <= 1e-10:
                raise AssertionError(f"candidate {i}: vectorised {key} disagrees with the loop: "
                                     f"{err:.3g} > 1e-10")
    return worst


def check_same(got: dict[str, np.ndarray], want: dict[str, np.ndarray], label: str) -> None:
    """Exactly the same screening (every key, every candidate; NaN where NaN)."""
    if set(got) != set(want):
        raise AssertionError(f"{label}: other keys than in-process")
    for k, v in want.items():
        if not np.array_equal(np.asarray(got[k]), np.asarray(v), equal_nan=True):
            raise AssertionError(f"{label}: {k} differs from the in-process screening")


def run(n: int = 16384, loop_n: int = 300, repeat: int = 5, workers: tuple[int, ...] = (1, 2),
        long_repeat: int = 5) -> dict[str, Any]:
    req, bounds, X = problem(n)
    vec_fn = functools.partial(syn.evaluate_candidates, req=req)
    screen_fn = functools.partial(syn._screen, req=req, bounds=bounds)
    names = ["loop (per candidate)", "vectorised, chunks of 4096",
             "screen (repair + evaluate), in-process"]
    counts = [loop_n, n, n]
    fns: list[Any] = [lambda: loop(req, X[:loop_n]),
                      lambda: evaluate(vec_fn, X, chunk_size=CHUNK),
                      lambda: evaluate(screen_fn, X, chunk_size=CHUNK)]
    firsts, results = [], []
    for fn in fns:                          # warm-up, agreement, calibration
        t0 = time.perf_counter()
        results.append(fn())
        firsts.append(time.perf_counter() - t0)
    agreement = {"vectorised vs loop": check_loop(
        results[0], syn.evaluate_candidates(X[:loop_n], req))}
    del results
    times = time_rounds(fns, repeat, first=firsts, long_repeat=long_repeat)
    rows = [{"contender": name, "candidates": k, "times": sp.samples}
            for name, k, sp in zip(names, counts, times, strict=True)]

    def same(got: Any, want: Any, label: str) -> None:
        check_same(got, want, label)
        agreement[f"screen, {label} vs in-process"] = 0.0

    def on_plain(procs: PlainProcesses) -> Any:
        return procs.evaluate(screen_fn, X, CHUNK)

    def on_cluster(client: Any) -> Any:
        return evaluate(screen_fn, X, chunk_size=CHUNK, client=client)

    clusters = (cluster_rounds(workers, fns[2], on_cluster, on_plain, same, repeat)
                if workers else [])
    return {"rows": rows, "agreement": agreement, "n": n, "dask": clusters}


def table(result: dict[str, Any], markdown: bool = False) -> str:
    rows = result["rows"]
    base = rows[0]["candidates"] / Spread(rows[0]["times"]).median
    lines = []
    if markdown:
        lines += ["| contender | candidates | min / median / max | candidates/s (median) | "
                  "x loop |", "|---|---:|---:|---:|---:|"]
    else:
        lines.append(f"{'contender':46s} {'candidates':>10s} {'min / median / max':>28s} "
                     f"{'candidates/s':>12s} {'x loop':>7s}")
    for r in rows:
        sp = Spread(r["times"])
        rate = r["candidates"] / sp.median
        if markdown:
            lines.append(f"| {r['contender']} | {r['candidates']} | {fmt_spread(sp)} | "
                         f"{rate:,.0f} | {rate / base:.1f} |")
        else:
            lines.append(f"{r['contender']:46s} {r['candidates']:10d} {fmt_spread(sp):>28s} "
                         f"{rate:12,.0f} {rate / base:7.1f}")
    if result.get("dask"):
        lines += cluster_lines(result["dask"], f"the screening of {result['n']} candidates",
                               markdown=markdown)
    lines += ["", "agreement (checked before timing):"]
    lines += [f"  {k}: {v:.2g}" for k, v in result["agreement"].items()]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--n", type=int, default=16384, help="candidates (vectorised contenders)")
    ap.add_argument("--loop-n", type=int, default=300, help="candidates of the plain loop")
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2],
                    help="worker processes of each local dask cluster")
    ap.add_argument("--no-dask", action="store_true")
    ap.add_argument("--repeat", type=int, default=5, help="rounds")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--json", help="also write the rows to this JSON file")
    args = ap.parse_args(argv)
    t0, load0 = time.perf_counter(), load()
    result = run(args.n, args.loop_n, args.repeat, () if args.no_dask else tuple(args.workers))
    finish(result, table(result, markdown=args.markdown),
           f"swash-plate screening, scheme 1; {args.repeat} rounds", load0, t0, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())
