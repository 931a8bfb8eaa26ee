"""The default table positions are the same for every command on every driver type: the
multiples of 30 deg inside a crank's [analysis] range, 12 positions over a linear driver's
(``studies.planar.default_table_positions``); ``linkwork reactions`` on a linear-driver file
works by default (it read the crank angles 0, 30, ... as millimetres of slide before).

Reference: the positions written out by hand for each file's range (tolerance: the tables'
one decimal)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from _cli_files import run_cli

ROOT = Path(__file__).resolve().parents[2]


def _analyze_positions(text: str) -> list[float]:
    """The first column of the first table that ``linkwork analyze`` prints."""
    rows, started = [], False
    for line in text.splitlines():
        if line.startswith("┃") and ("φ1" in line or "s1" in line):
            started = True
        elif started and line.startswith("│"):
            rows.append(float(line.split("│")[1]))
        elif started and line.startswith("└"):
            break
    return rows


def _reactions_positions(text: str) -> list[float]:
    return [float(x) for x in re.findall(r"reactions at (?:φ1|s1) = ([-0-9.e+]+) (?:deg|mm)",
                                         text)]


@pytest.mark.parametrize(("file", "expected"), [
    # a linear driver from 270 to 430 mm: 12 positions, both ends included
    ("tests/data/slider_driven_crank.toml", np.linspace(270.0, 430.0, 12)),
    # a crank over 0..359 deg: 0, 30, ..., 330
    ("examples/loom_fourbar_spatial.toml", np.arange(0.0, 331.0, 30.0)),
])
def test_analyze_and_reactions_table_the_same_positions(file, expected, tmp_path, capsys):
    code, text, err = run_cli(["analyze", str(ROOT / file), "--out", str(tmp_path / "a")],
                              capsys)
    assert code == 0, err
    np.testing.assert_allclose(_analyze_positions(text), expected, atol=0.051)
    code, text, err = run_cli(["reactions", str(ROOT / file), "--out", str(tmp_path / "r"),
                               "--no-plots"], capsys)
    assert code == 0, err
    np.testing.assert_allclose(_reactions_positions(text), expected, atol=0.051)
