"""The ``[sketch]`` table of a planar file: the mechanism as drawn (world coordinates).

Reference: ``examples/fourbar_paper001.toml`` (paper 001's four-bar in body frames) and the same
four-bar written as its drawing at phi1 = 0 (points computed here by circle intersection, printed
to 17 digits); ``linkwork.studies.planar.analyze`` of both must give the same columns, every
number to 1e-9 of the largest value of its unit. Broken drawings give one line naming the key,
exit 2.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from linkwork import io
from linkwork.cli import main
from linkwork.errors import FileFormatError
from linkwork.studies import planar as study

ROOT = Path(__file__).resolve().parents[2]


def _paper001_drawing() -> str:
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    A = np.array([a, 0.0])
    C = np.array([d, 0.0])
    dd = np.hypot(*(C - A))
    x = (b * b - c * c + dd * dd) / (2 * dd)
    h = math.sqrt(b * b - x * x)
    e = (C - A) / dd
    B = A + x * e + h * np.array([-e[1], e[0]])  # branch +1: left of A -> C
    u = (B - A) / b
    P = A + 0.15 * u + 0.1 * np.array([-u[1], u[0]])
    mid = (A + B) / 2

    def xy(p):
        return f"[{float(p[0])!r}, {float(p[1])!r}]"

    return f"""type = "planar"
name = "Four-bar of paper 001, drawn"

[sketch]
points = {{ O = [0, 0], C = [0.3, 0], A = {xy(A)}, B = {xy(B)}, P = {xy(P)} }}
ground = ["O", "C"]
links = {{ crank = ["O", "A"], coupler = ["A", "B", "P"], rocker = ["C", "B"] }}

[sketch.masses]
crank = {{ mass = "1 kg", inertia = "0.000833 kg*m^2" }}
coupler = {{ mass = "3 kg", com = {xy(mid)}, inertia = "0.0225 kg*m^2" }}
rocker = {{ mass = "2 kg", inertia = "0.00567 kg*m^2" }}

[driver]
joint = "O"
omega1 = "10 rad/s"

[analysis]
n = 361
about = [0, 0]
"""


def test_drawn_paper001_fourbar_analyses_as_the_example(tmp_path):
    """Every column of the analysis (kinematics of every named point, reactions, Q, shaking)
    of the drawn four-bar equals the example's."""
    f = tmp_path / "drawn.toml"
    f.write_text(_paper001_drawing())
    drawn = study.analyze(io.load(f))
    ref = study.analyze(io.load(ROOT / "examples" / "fourbar_paper001.toml"))
    c1, c2 = drawn.columns(), ref.columns()
    assert set(c1) == set(c2)
    scales: dict[str, float] = {}  # per unit: the largest magnitude of any column
    for v, unit in c2.values():
        scales[unit] = max(scales.get(unit, 0.0), float(np.max(np.abs(v))))
    for k, (v, unit) in c2.items():
        scale = scales[unit]
        assert c1[k][1] == unit
        assert np.max(np.abs(c1[k][0] - v)) <= 1e-9 * scale, k
    assert drawn.structure.formula() == ref.structure.formula()


@pytest.mark.parametrize(("change", "key", "words"), [
    (("links = {", 'links = { stub = ["A"], '), "sketch.links.stub", "at least two points"),
    (('joint = "O"', 'joint = "A"'), "sketch.drivers", "not a frame pivot"),
    (("points = { O = [0, 0],", "points = { X = [1, 1], O = [0, 0],"), "sketch.points.X",
     "on no link"),
    (('ground = ["O", "C"]', 'ground = ["O"]'), "sketch", "the drawing is invalid: .*mobility"),
    (('joint = "O"\nomega1 = "10 rad/s"', 'joint = "O"\ntype = "linear"'), "driver.type",
     "must be crank"),
    (("[sketch]", '[frame]\npoints = {}\n[sketch]'), "frame", r"leave out \[frame\]"),
])
def test_bad_drawings_in_files(tmp_path, change, key, words):
    """Errors of a drawing name the file's key (``sketch.links.stub``)."""
    f = tmp_path / "bad.toml"
    f.write_text(_paper001_drawing().replace(*change))
    with pytest.raises(FileFormatError, match=words) as err:
        io.load(f)
    assert err.value.key.startswith(key)


def test_file_without_frame_or_sketch_names_both_ways(tmp_path):
    f = tmp_path / "none.toml"
    f.write_text('type = "planar"\n[driver]\njoint = "O"\n')
    with pytest.raises(FileFormatError, match=r"frame: missing required key \(or describe"):
        io.load(f)


def test_cli_refuses_a_toggle_drawing_in_one_line(tmp_path, capsys):
    """A four-bar drawn with coupler and rocker collinear: one line on stderr, exit 2."""
    text = """type = "planar"
[sketch]
points = { O = [0, 0], A = [0, 0.1], B = [0.2, 0.05], C = [0.4, 0] }
ground = ["O", "C"]
links = { crank = ["O", "A"], coupler = ["A", "B"], rocker = ["C", "B"] }
[driver]
joint = "O"
"""
    f = tmp_path / "toggle.toml"
    f.write_text(text)
    code = main(["analyze", str(f), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and "toggle of joint 'B'" in err
    assert not (tmp_path / "out" / "planar.json").exists()
