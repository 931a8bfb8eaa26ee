"""Keep benchmarks/forces.py from rotting: run it tiny (n = 50), no timing assertions; its flat
NumPy forces must agree with the engine's, and a wrong one must be caught."""

from __future__ import annotations

import pytest
from _benchmarks import load_benchmark


@pytest.fixture(scope="module")
def bench():
    return load_benchmark("forces")


def test_forces_benchmark_runs(bench):
    rows = bench.run(sizes=(50,), repeat=1)
    assert [r["contender"] for r in rows] == ["no loads", "point force", "elements",
                                              "elements, flat NumPy"]
    assert "| 50 | elements |" in bench.table(rows)


def test_forces_benchmark_check_catches_a_disagreement(bench, monkeypatch):
    kin, elements = bench.press(50)
    flat = bench.flat

    def wrong(k):
        out = flat(k)
        out[0] = (out[0][0], out[0][1] * 1.001)  # the spring pulls along y
        return out

    monkeypatch.setattr(bench, "flat", wrong)
    with pytest.raises(SystemExit, match=r"spring\.0"):
        bench.check(kin, elements)
