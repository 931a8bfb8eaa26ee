"""Keep benchmarks/machine.py from rotting: one case at 64 positions, no timing assertions;
both contenders must reach the reference (the periodic solve at 256 positions)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

PATH = Path(__file__).resolve().parents[2] / "benchmarks" / "machine.py"


def test_machine_benchmark_runs_and_both_contenders_agree():
    spec = importlib.util.spec_from_file_location("linkwork_bench_machine", PATH)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    rows = mod.run(n=64, repeat=1, names=["no flywheel"])
    assert len(rows) == 1
    r = rows[0]
    assert r["periodic_error"] < 1e-4 and r["ivp_error"] < 1e-4   # fourth order at 64 positions
    assert r["ivp_revolutions"] >= 2 and r["ivp_rhs"] > 0
    assert "speed-up" in mod.table(rows, markdown=True)
