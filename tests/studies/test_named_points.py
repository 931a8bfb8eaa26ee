"""Every named point of every moving body in the planar study's columns (planar_kinematics.csv,
planar.json): ``<body>.<point>.x/y/vx/vy/ax/ay``; the coupler point P of paper 001 against the
closed-form four-bar."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from _cli_files import run_cli

from linkwork import io
from linkwork.models.fourbar import fourbar
from linkwork.studies import planar as study_planar

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FIELDS = ("x", "y", "vx", "vy", "ax", "ay")
UNITS = {"x": "m", "y": "m", "vx": "m/s", "vy": "m/s", "ax": "m/s^2", "ay": "m/s^2"}


def _close(got: np.ndarray, want: np.ndarray) -> None:
    scale = float(np.max(np.abs(want)))
    assert np.max(np.abs(np.asarray(got) - want)) <= 1e-9 * max(scale, 1e-300)


@pytest.mark.parametrize("example", ["fourbar_paper001.toml", "loom_sixbar.toml",
                                     "sine_press_planar.toml"])
def test_every_named_point_equals_kinematics_point(example):
    study = study_planar.analyze(io.load(EXAMPLES / example))
    kin, cols = study.kinematics, study.kinematics_columns()
    names = [(b.name, pt) for b in study.mechanism.bodies for pt in b.points]
    assert names  # every example names points
    for body, pt in names:
        pm = kin.point(body, pt)
        for f in FIELDS:
            values, unit = cols[f"{body}.{pt}.{f}"]
            assert unit == UNITS[f]
            np.testing.assert_array_equal(values, getattr(pm, f))
    json_cols = study.to_dict()["columns"]
    assert {f"{b}.{p}.{f}" for b, p in names for f in FIELDS} <= set(json_cols)


def test_paper001_coupler_point_p_against_the_closed_form():
    doc = io.load(EXAMPLES / "fourbar_paper001.toml")
    study = study_planar.analyze(doc)
    phi = study.positions
    # paper 001: crank 100 mm, coupler 300 mm, rocker 200 mm, frame 300 mm, omega 10 1/s;
    # P at (150 mm, 100 mm) in the coupler frame (origin A, x axis A -> B); branch B = +1
    res = fourbar(phi, 0.1, 0.3, 0.2, 0.3, omega1=10.0, eps1=0.0, branch=+1)
    want = res.point("coupler", 0.15, 0.10)
    cols = study.columns()
    for f, w in zip(FIELDS, want, strict=True):
        _close(cols[f"coupler.P.{f}"][0], np.broadcast_to(w, phi.shape))


def test_csv_and_json_carry_the_coupler_curve(tmp_path, capsys):
    out = tmp_path / "out"
    code, _, err = run_cli(["analyze", str(EXAMPLES / "fourbar_paper001.toml"), "--out",
                            str(out)], capsys)
    assert code == 0, err
    with (out / "planar_kinematics.csv").open() as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    study = study_planar.analyze(io.load(EXAMPLES / "fourbar_paper001.toml"))
    p = study.kinematics.point("coupler", "P")
    for f in FIELDS:
        k = head.index(f"coupler.P.{f} [{UNITS[f]}]")
        np.testing.assert_array_equal(data[:, k], getattr(p, f))  # repr(float) round-trips
    doc = json.loads((out / "planar.json").read_text())
    assert doc["units"]["coupler.P.ax"] == "m/s^2"
    np.testing.assert_array_equal(doc["columns"]["coupler.P.x"], p.x)
