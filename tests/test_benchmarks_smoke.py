"""Keep benchmarks/kinematics.py from rotting: run it tiny (n=100), no timing assertions."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

PATH = Path(__file__).resolve().parents[1] / "benchmarks" / "kinematics.py"


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("linkwork_bench_kinematics", PATH)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def test_benchmark_runs_and_all_contenders_agree(bench):
    use_pl = bench.have_pylinkage()
    rows = bench.run(sizes=(100,), repeat=1, pylinkage=use_pl, no_numba=False)
    names = {(r["mechanism"], r["contender"]) for r in rows}
    for mech in ("four-bar", "crank-slider"):
        for who in ("plain NumPy", "closed form", "engine", "engine + reactions"):
            assert (mech, who) in names
        assert ((mech, "pylinkage (numba)") in names) == use_pl
    text = bench.table(rows)
    assert "closed form / plain NumPy" in text


def test_benchmark_check_catches_a_disagreement(bench):
    cons = bench.fourbar_contenders(50, with_engine=False)
    ref = cons[0].output(cons[0].run())
    bad = list(ref)
    bad[3] = bad[3] * (1 + 1e-6)
    with pytest.raises(AssertionError, match="closed form disagrees"):
        bench.check([c for c in cons if c.name == "closed form"], tuple(bad), "four-bar")


def test_benchmark_plain_numpy_fourbar_is_the_open_branch(bench):
    from linkwork.models.fourbar import fourbar

    t = np.linspace(0, 2 * np.pi, 37)
    plain = bench.numpy_fourbar(t, 0.1, 0.3, 0.2, 0.3, 10.0)
    r = fourbar(t, 0.1, 0.3, 0.2, 0.3, 10.0, branch=+1)
    np.testing.assert_allclose(np.angle(np.exp(1j * (plain[0] - r.theta3))), 0, atol=1e-12)
    np.testing.assert_allclose(plain[2], r.omega3, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(plain[4], r.alpha3, rtol=1e-9, atol=1e-9)
