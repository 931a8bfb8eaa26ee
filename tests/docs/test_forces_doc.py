"""The Python example of ``docs/forces.md`` runs as printed and gives the hand values: the
counterbalance's tension 2.5 kN + 5 N/mm (L - 400 mm) with L = -s the distance from the frame's
anchor to the ram (350 mm at the top, 450 mm at the bottom), the drawing force of its table at
the bottom of the stroke, and the power balance of the loads with the springs' energy."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]


def test_docs_forces_example_runs_and_matches_hand_values():
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "forces.md").read_text(),
                        flags=re.S)
    assert len(blocks) == 1
    ns: dict = {}
    exec(compile(blocks[0], "docs/forces.md", "exec"), ns)
    dyn, phi = ns["dyn"], ns["kin"].phi1
    top, bottom = np.argmin(np.abs(phi - np.pi / 2)), np.argmin(np.abs(phi - 1.5 * np.pi))
    spring = dyn.load("counterbalance")
    assert abs(spring.length[top] - 0.35) < 1e-12 and abs(spring.length[bottom] - 0.45) < 1e-12
    assert abs(spring.value[top] - 2250.0) < 1e-9 and abs(spring.value[bottom] - 2750.0) < 1e-9
    assert abs(dyn.load("drawing").value[bottom] - 100e3) < 1e-6
    # stretched from 350 to 450 mm the spring stores int F dL (F linear in L)
    assert abs(dyn.V[bottom] - dyn.V[top] - (2250 + 2750) / 2 * 0.1) < 1e-9
