"""Candidates evaluated per second by the swash-plate synthesis screening (paper 003).

Contenders, on the same Sobol candidates of scheme 1 (r, l, alpha, a, b) with R = 100 mm:

* ``loop``: a plain per-candidate loop (``linkwork.models.swashplate.characteristics`` on one
  design at a time, exact, default grid) -- the reference;
* ``vectorised``: ``linkwork.synthesis.swashplate.evaluate_candidates`` on chunks of 4096 via
  ``linkwork.sweep.evaluate`` (characteristics + constraint violations, 120-point grid refined
  to machine precision);
* ``screen``: the synthesis screening step (rod/stroke repair, 6 passes, then evaluation);
* ``dask``: ``vectorised`` through an in-process dask.distributed cluster (2 threads), to show
  the overhead of the cluster path on one machine.

Before timing, the vectorised characteristics of the first candidates are compared with the loop
to 1e-10 (H, pressure angles, max |Pi_v|). Usage::

    .venv/bin/python benchmarks/swashplate_synthesis.py [--n 16384] [--loop-n 200] [--no-dask]
"""

from __future__ import annotations

import argparse
import functools
import math
import time

import numpy as np
from scipy.stats import qmc

from linkwork.models import swashplate as sw
from linkwork.sweep import evaluate
from linkwork.synthesis import swashplate as syn


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=16384, help="candidates (vectorised contenders)")
    ap.add_argument("--loop-n", type=int, default=200, help="candidates for the plain loop")
    ap.add_argument("--no-dask", action="store_true")
    args = ap.parse_args(argv)

    req = syn.Request(scheme="1", R=0.1, H=0.06, H_tol=5e-4, delta_f=8 * math.pi / 180,
                      delta_r=8 * math.pi / 180)
    bounds = req.search_bounds()
    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    m = max(1, math.ceil(math.log2(args.n)))
    X = lo + qmc.Sobol(len(bounds), scramble=True, seed=1).random_base2(m)[: args.n] * (hi - lo)

    def loop(Xs: np.ndarray) -> list[sw.Characteristics | None]:
        out: list[sw.Characteristics | None] = []
        for x in Xs:
            R, r, l, al, a, b = (float(v[0]) for v in syn._full_params(req, x[None, :]))
            try:
                out.append(sw.characteristics(R, r, l, al, a, b))
            except ValueError:  # the rod cannot reach: counted as evaluated
                out.append(None)
        return out

    # agreement check
    k = min(50, args.loop_n)
    ref = loop(X[:k])
    vec = syn.evaluate_candidates(X[:k], req)
    for i, c in enumerate(ref):
        if c is None:
            assert np.isnan(vec["H"][i])
            continue
        for key, val in (("H", c.H), ("delta_f", c.delta_f), ("delta_r", c.delta_r),
                         ("Pi_v_max", c.Pi_v_max)):
            assert abs(vec[key][i] - val) <= 1e-10 * max(1.0, abs(val)), (key, i)

    rows = []
    t = time.perf_counter()
    loop(X[: args.loop_n])
    dt = time.perf_counter() - t
    rows.append(("loop (per candidate)", args.loop_n, dt))
    t = time.perf_counter()
    evaluate(functools.partial(syn.evaluate_candidates, req=req), X, chunk_size=4096)
    rows.append(("vectorised, chunks of 4096", len(X), time.perf_counter() - t))
    t = time.perf_counter()
    evaluate(functools.partial(syn._screen, req=req, bounds=bounds), X, chunk_size=4096)
    rows.append(("screen (repair + evaluate)", len(X), time.perf_counter() - t))
    if not args.no_dask:
        from dask.distributed import Client

        with Client(processes=False, dashboard_address=":0", n_workers=1,
                    threads_per_worker=2) as client:
            t = time.perf_counter()
            evaluate(functools.partial(syn.evaluate_candidates, req=req), X, chunk_size=2048,
                     client=client)
            rows.append(("vectorised via dask (in-process, 2 threads)", len(X),
                         time.perf_counter() - t))
    base = rows[0][1] / rows[0][2]
    print(f"swash-plate synthesis screening, scheme 1, numpy {np.__version__}")
    print("| contender | candidates | time [s] | candidates/s | x loop |")
    print("|---|---:|---:|---:|---:|")
    for name, n, dt in rows:
        print(f"| {name} | {n} | {dt:.3f} | {n / dt:,.0f} | {n / dt / base:.1f} |")


if __name__ == "__main__":
    main()
