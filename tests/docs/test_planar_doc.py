"""The Python and TOML examples of ``docs/planar.md`` run as printed and match hand computations."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from _planar_references import _crank_rod_slider_energy, _fourbar_paper001_torque, _fourbar_torque

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _crank_slider_torque(phi: np.ndarray) -> np.ndarray:
    """crank_slider(0.05, 0.2, 0.025, masses=(1, 2, 3), omega1=12.566) written out: guide along
    +x through (0, 25 mm), B = (r cos + sqrt(l^2 - (e - r sin)^2), e); thin rods; no loads.
    Q = dT/d phi1 at constant omega1."""
    r, l, e, w = 0.05, 0.2, 0.025, 12.566

    def energy(p: np.ndarray) -> np.ndarray:
        def coords(p: np.ndarray) -> np.ndarray:
            A = np.stack([r * np.cos(p), r * np.sin(p)])
            B = np.stack([A[0] + np.sqrt(l * l - (e - A[1]) ** 2), np.full_like(p, e)])
            th = np.arctan2(B[1] - A[1], B[0] - A[0])
            return np.stack([*(A / 2), p, *((A + B) / 2), th, B[0]])

        h = 1e-6
        return _crank_rod_slider_energy((coords(p + h) - coords(p - h)) / (2 * h) * w, r, l)

    h = 1e-4
    return (energy(phi + h) - energy(phi - h)) / (2 * h)


def test_docs_planar_examples_run_and_match_hand_computations(monkeypatch):
    """docs/planar.md showed how to build the four-bar in Python but not how the same
    mechanism loads from its TOML file in Python, nor the crank-slider shortcut in use. Its
    Python blocks must run as printed, and their torques match the power balance written out
    here: the engine-built four-bar with gravity and loads, the fourbar() and crank_slider()
    shortcuts, and paper 001's four-bar loaded from examples/fourbar_paper001.toml."""
    import re

    from linkwork.planar import inverse_dynamics, kinematics

    root = EXAMPLES.parent
    blocks = re.findall(r"```python\n(.*?)```", (root / "docs" / "planar.md").read_text(),
                        flags=re.S)
    assert len(blocks) >= 2
    monkeypatch.chdir(root)
    ns: dict = {}
    for block in blocks:
        exec(compile(block, "docs/planar.md", "exec"), ns)
    deg = np.radians(np.arange(0, 360))
    thin = (1.0 * 0.1**2 / 12, 3.0 * 0.3**2 / 12, 2.0 * 0.2**2 / 12)
    Q = _fourbar_torque(deg, thin, gy=-9.81, fy_B=-20.0, mz_rocker=1.5)
    np.testing.assert_allclose(ns["dyn"].Q, Q, atol=1e-5 * np.abs(Q).max())
    Q = _fourbar_torque(deg, thin)
    got = inverse_dynamics(kinematics(ns["fb"], deg)).Q
    np.testing.assert_allclose(got, Q, atol=1e-5 * np.abs(Q).max())
    Q = _crank_slider_torque(deg)
    np.testing.assert_allclose(ns["dyn_cs"].Q, Q, atol=1e-5 * np.abs(Q).max())
    np.testing.assert_allclose(ns["phi1"], np.radians(np.linspace(0.0, 360.0, 361)))
    Q = _fourbar_paper001_torque(ns["phi1"])
    np.testing.assert_allclose(ns["dyn_f"].Q, Q, atol=1e-5)
