"""Peak memory and time of long cycles: ``inverse_dynamics`` in chunks, and the four-bar's full
analysis of 10^7 positions chunk by chunk with its CSV columns streamed.

Cases, each in a fresh interpreter (peak resident memory from ``getrusage``; the interpreter
with NumPy and linkwork imported is the baseline, printed apart):

``kinematics + inverse_dynamics``  the engine on paper 001's four-bar (masses 1, 3, 2 kg,
    gravity) over ``--dyn-n`` positions (10^6), both results held: what the peak rises by per
    position, against the bytes of the two results;
``analyze_chunked``  :func:`linkwork.studies.planar.analyze_chunked` of
    ``examples/fourbar_paper001.toml`` over ``--n`` positions (10^7) of one turn: kinematics,
    dynamics and transmission angles per chunk, every per-position column of
    ``planar_kinematics.csv`` and ``planar_dynamics.csv`` formatted by
    :class:`linkwork.results.CsvRows` (into a byte counter: ``--csv-dir`` writes the files, some
    15 GB at 10^7), the extremes, means and dead centres as running statistics.

Agreement: before the long run, ``analyze_chunked`` at ``--check-n`` positions equals
``analyze`` of the whole cycle held at once (extremes and their positions, dead centres exactly;
means to 1e-12 of the driving torque's scale); after it, the dead centres of the long run equal
those at ``--check-n`` to 1e-10 rad (both located by Brent's method between samples) and every
extreme of the long run is within ``1e-6 + 100 h^2`` (relative) of the one at ``--check-n``, h
the check run's step (a sampled extreme of the same smooth cycle).

Usage::

    .venv/bin/python benchmarks/long_cycle.py            # 10^7 positions: several minutes
    .venv/bin/python benchmarks/long_cycle.py --n 1000000 --dyn-n 100000 --json out.json
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "fourbar_paper001.toml"
GIB = 2**30


def _rss() -> int:
    """Peak resident memory of this process so far [bytes] (Linux reports kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


class _Count:
    """A text sink that only counts what is written to it."""

    def __init__(self) -> None:
        self.chars = 0

    def write(self, s: str) -> int:
        self.chars += len(s)
        return len(s)


def _child_dynamics(n: int) -> dict[str, Any]:
    import numpy as np

    from linkwork.planar import fourbar_mechanism, inverse_dynamics, kinematics

    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0), omega1=10.0)
    phi = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    base = _rss()
    t = time.perf_counter()
    kin = kinematics(mech, phi)
    after_kin = _rss()
    dyn = inverse_dynamics(kin, gravity=(0.0, -9.81))
    dt = time.perf_counter() - t
    peak = _rss()
    held = sum(v.nbytes for v in vars(dyn).values() if isinstance(v, np.ndarray)
               and v.size >= n)
    kin_bytes = sum(v.nbytes for v in vars(kin).values() if isinstance(v, np.ndarray)
                    and v.size >= n)
    return {"n": n, "seconds": dt, "baseline": base, "peak": peak,
            "kinematics_rise_per_position": (after_kin - base) / n,
            "dynamics_rise_per_position": (peak - after_kin) / n,
            "dynamics_result_per_position": held / n,
            "kinematics_result_per_position": kin_bytes / n}


def _child_chunked(n: int, csv_dir: str | None, chunk: int) -> dict[str, Any]:
    import numpy as np

    from linkwork import io
    from linkwork.results import CsvRows, csv_rows
    from linkwork.studies import planar as sp

    doc = io.load(EXAMPLE)
    phi = np.linspace(0.0, 2 * np.pi, n)
    base = _rss()
    t = time.perf_counter()
    counters: list[_Count] = []
    streams: dict[str, Any] = {}
    opened: list[Any] = []

    def sink(kc: dict[str, Any], dc: dict[str, Any]) -> None:
        if not streams:
            for name, cols in (("planar_kinematics.csv", kc), ("planar_dynamics.csv", dc)):
                header = dict.fromkeys(cols, "")
                if csv_dir is None:
                    counters.append(_Count())
                    streams[name] = CsvRows(counters[-1], header)
                else:
                    cm = csv_rows(Path(csv_dir) / name, header)
                    opened.append(cm)
                    streams[name] = cm.__enter__()
        streams["planar_kinematics.csv"].append(kc)
        streams["planar_dynamics.csv"].append(dc)

    try:
        s = sp.analyze_chunked(doc, positions=phi, chunk=chunk, sink=sink)
    finally:
        for cm in opened:
            cm.__exit__(None, None, None)
    dt = time.perf_counter() - t
    chars = (sum(c.chars for c in counters) if csv_dir is None else
             sum((Path(csv_dir) / f).stat().st_size for f in streams))
    return {"n": n, "seconds": dt, "baseline": base, "peak": _rss(), "csv_bytes": chars,
            "columns": sum(len(r.names) for r in streams.values()),
            "dead_centres": [d.phi1 for d in s.dead_centres],
            "peaks": [[p["name"], p["value"], p["phi1"]] for p in s.peaks],
            "means": s.means}


def _child_check(n: int, chunk: int) -> dict[str, Any]:
    """analyze_chunked at n against analyze of the whole cycle; returns the chunked summary."""
    import numpy as np

    from linkwork import io
    from linkwork.studies import planar as sp

    doc = io.load(EXAMPLE)
    phi = np.linspace(0.0, 2 * np.pi, n)
    s = sp.analyze_chunked(doc, positions=phi, chunk=chunk)
    mech = doc.mechanism()
    from linkwork.planar import inverse_dynamics, kinematics

    kin = kinematics(mech, phi)
    dyn = inverse_dynamics(kin, gravity=doc.analysis.gravity, loads=doc.loads(phi),
                           about=doc.analysis.about)
    from linkwork.planar import dead_centres, transmission_angles

    trans = transmission_angles(kin)
    whole_peaks = sp.cycle_peaks(kin, dyn, trans)
    if s.peaks != whole_peaks:
        raise AssertionError("analyze_chunked: extremes differ from the whole cycle's")
    if s.dead_centres != dead_centres(kin):
        raise AssertionError("analyze_chunked: dead centres differ from the whole cycle's")
    q_scale = max(abs(p["value"]) for p in whole_peaks if p["name"].startswith("Q "))
    q_mean = sp.mean_over_range(phi, dyn.Q)
    if not abs(s.means["Q_mean"] - q_mean) <= 1e-12 * q_scale:
        raise AssertionError("analyze_chunked: Q_mean differs from the whole cycle's")
    return {"n": n, "dead_centres": [d.phi1 for d in s.dead_centres],
            "peaks": [[p["name"], p["value"], p["phi1"]] for p in s.peaks],
            "Q_mean_difference": abs(s.means["Q_mean"] - q_mean) / q_scale}


def _spawn(*args: str) -> dict[str, Any]:
    res = subprocess.run([sys.executable, __file__, "--child", *args], capture_output=True,
                         text=True, cwd=ROOT)
    if res.returncode != 0:
        raise AssertionError(f"child {args} failed: {res.stderr[-2000:]}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def run(n: int = 10_000_000, dyn_n: int = 1_000_000, check_n: int = 100_000,
        chunk: int = 0, csv_dir: str | None = None) -> dict[str, Any]:
    from linkwork.studies.planar import CHUNK_POSITIONS

    chunk = chunk or CHUNK_POSITIONS
    check = _spawn("check", str(check_n), str(chunk))
    dyn = _spawn("dynamics", str(dyn_n))
    long = _spawn("chunked", str(n), str(chunk), csv_dir or "")
    # the long run against the check run (same smooth cycle, finer sampling)
    dc_err = max((abs(a - b) for a, b in zip(long["dead_centres"], check["dead_centres"],
                                                strict=True)), default=0.0)
    if not dc_err <= 1e-10:
        raise AssertionError(f"dead centres at n={n} differ from n={check_n}: {dc_err:.3g}")
    worst = 0.0
    # a sampled extreme is off the true one by about f''/2 h^2: the coarser check run's step
    bound = 1e-6 + 100 * (2 * math.pi / check_n) ** 2
    for (name, v_long, _), (name2, v_check, _) in zip(long["peaks"], check["peaks"],
                                                     strict=True):
        if name != name2:
            raise AssertionError(f"extremes differ in kind: {name} / {name2}")
        rel = abs(v_long - v_check) / max(abs(v_check), 1e-300)
        worst = max(worst, rel)
        if rel > bound:
            raise AssertionError(f"{name}: {v_long} at n={n} against {v_check} at n={check_n}")
    return {"check": check, "dynamics": dyn, "chunked": long, "chunk": chunk,
            "agreement": {f"analyze_chunked vs analyze, n={check_n}: Q_mean":
                          check["Q_mean_difference"],
                          f"dead centres, n={n} vs n={check_n} [rad]": dc_err,
                          f"extremes, n={n} vs n={check_n} (relative)": worst}}


def report(result: dict[str, Any], markdown: bool = False) -> str:
    d, c = result["dynamics"], result["chunked"]
    mib = 2**20
    rows = [
        ("kinematics + inverse_dynamics", f"{d['n']:.0e}", f"{d['seconds']:.1f} s",
         f"{d['peak'] / mib:.0f} MiB", f"{d['baseline'] / mib:.0f} MiB",
         f"kinematics +{d['kinematics_rise_per_position']:.0f} B/position (result "
         f"{d['kinematics_result_per_position']:.0f}); inverse_dynamics "
         f"+{d['dynamics_rise_per_position']:.0f} B/position (result "
         f"{d['dynamics_result_per_position']:.0f})"),
        ("analyze_chunked + CSV formatting", f"{c['n']:.0e}", f"{c['seconds']:.0f} s",
         f"{c['peak'] / mib:.0f} MiB ({c['peak'] / GIB:.2f} GiB)",
         f"{c['baseline'] / mib:.0f} MiB",
         f"chunks of {result['chunk']}; {c['columns']} columns, {c['csv_bytes'] / 1e9:.1f} GB "
         f"of CSV text"),
    ]
    lines = []
    if markdown:
        lines += ["| case | positions | time | peak resident | baseline | notes |",
                  "|---|---:|---:|---:|---:|---|"]
        lines += ["| " + " | ".join(r) + " |" for r in rows]
    else:
        lines += ["  ".join(r) for r in rows]
    target = "met" if c["peak"] < 2 * GIB else "missed"
    lines += ["", f"target (issue 20 item 4): 10^7 positions of the four-bar's full analysis "
              f"under 2 GiB peak: {c['peak'] / GIB:.2f} GiB at n = {c['n']} ({target})", "",
              "agreement:"]
    lines += [f"  {k}: {v:.2g}" for k, v in result["agreement"].items()]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000_000, help="positions of the long run")
    ap.add_argument("--dyn-n", type=int, default=1_000_000,
                    help="positions of kinematics + inverse_dynamics")
    ap.add_argument("--check-n", type=int, default=100_000,
                    help="positions of the check against the whole cycle")
    ap.add_argument("--chunk", type=int, default=0, help="positions per chunk (default the "
                    "library's)")
    ap.add_argument("--csv-dir", help="write the CSV files there (default: count the text)")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--json", help="also write the results to this JSON file")
    ap.add_argument("--child", nargs="+", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        kind, *rest = args.child
        if kind == "dynamics":
            out = _child_dynamics(int(rest[0]))
        elif kind == "chunked":
            out = _child_chunked(int(rest[0]), rest[2] or None if len(rest) > 2 else None,
                                 int(rest[1]))
        else:
            out = _child_check(int(rest[0]), int(rest[1]))
        print(json.dumps(out))
        return 0
    t0, load0 = time.perf_counter(), os.getloadavg()[0]
    result = run(args.n, args.dyn_n, args.check_n, args.chunk, args.csv_dir)
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from _common import finish

    finish(result, report(result, markdown=args.markdown), "long cycles", load0, t0, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())
