"""The claims of ``docs/friction.md`` that are numbers, checked against their definitions and
the engine: the working-range example runs as printed and finds paper 000's range (closed
form ``rho1 + rho2 < alpha < 180 deg - (rho1 + rho2)``); the slot coefficient's limit at
30 deg is ``tan(30 deg - atan 0.10)``; the friction circle ``f r`` against the loose journal's
``r sin(atan f)``; the friction example of ``examples/sine_press_planar.toml`` (efficiency,
losses, the 12-deg file's self-locking ranges) as printed."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
from _cli_files import sine_press_with_friction

from linkwork import io
from linkwork.models import sine
from linkwork.studies import planar as planar_study

DOC = (Path(__file__).resolve().parents[2] / "docs" / "friction.md").read_text()


def test_working_range_example_runs_and_finds_paper_000s_range():
    blocks = [b for b in re.findall(r"```python\n(.*?)```", DOC, flags=re.S)
              if "working_range(" in b]
    assert len(blocks) == 1
    ns: dict = {}
    exec(compile(blocks[0], "docs/friction.md", "exec"), ns)
    (a, b), = ns["wr"].intervals
    lo, hi = (float(v) for v in sine.working_range(0.12, 0.10))
    assert abs(a - lo) < 1e-8 and abs(b - hi) < 1e-8  # default tol: 1e-9 of the interval
    assert "[(0.21909..., 2.92249...)]" in blocks[0]
    assert repr(a).startswith("0.21909") and repr(b).startswith("2.92249")


def test_stated_limits_and_percentages():
    m = re.search(r"tan\(30° − arctan 0\.10\) = ([0-9.]+)", DOC)
    assert m and float(m[1]) == round(math.tan(math.radians(30) - math.atan(0.10)), 4)
    m = re.search(r"r sin\(arctan f\)`\s+\(([0-9.]+) % apart at f = 0\.1, ([0-9.]+) % at "
                  r"0\.15\)", DOC)
    assert m
    for pct, f in zip(m.groups(), (0.1, 0.15), strict=True):
        assert float(pct) == round(100 * (f / math.sin(math.atan(f)) - 1), 1)
    rho = math.degrees(math.atan(0.12) + math.atan(0.10))
    assert f"| 0.12, 0.10 | {rho:.9f}° |" in DOC
    assert f"| 0.12, 0.10 (upper) | {180 - rho:.9f}° |" in DOC


def test_sine_press_friction_example_as_printed(tmp_path):
    """cycle efficiency 0.729, losses 14.0 / 12.5 / 35.9 J; at 12 deg self-locking at
    151...206 and 283...357 deg (the file's 1-deg positions)."""
    m = re.search(r"cycle efficiency ([0-9.]+), losses ([0-9.]+) J \(crank bearing\), "
                  r"([0-9.]+) J \(guide\), ([0-9.]+) J \(slot\)", DOC)
    assert m
    dyn = planar_study.analyze(io.load(sine_press_with_friction(tmp_path))).dynamics
    assert f"{dyn.efficiency_cycle:.3f}" == m[1]
    assert [f"{v:.1f}" for v in dyn.friction_losses] == list(m.groups()[1:])
    m = re.search(r"self-locks at\s+φ1 = (\d+)…(\d+)° and (\d+)…(\d+)°", DOC)
    assert m
    dyn = planar_study.analyze(io.load(sine_press_with_friction(tmp_path, '"12 deg"'))).dynamics
    ranges = [round(math.degrees(v)) for r in dyn.self_locking_ranges() for v in r]
    assert ranges == [int(x) for x in m.groups()]
    assert np.all(np.isnan(dyn.Q[dyn.locked]))
