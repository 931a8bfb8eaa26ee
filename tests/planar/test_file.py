"""The ``planar`` TOML file and ``linkwork analyze`` on the planar examples."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from linkwork import files
from linkwork.cli import main
from linkwork.errors import FileFormatError
from linkwork.planar import fourbar, inverse_dynamics, kinematics

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_paper001_file_equals_builder():
    """The example file describes the paper-001 four-bar: same motion and torque as fourbar()."""
    doc = files.load(EXAMPLES / "fourbar_paper001.toml")
    mech = doc.mechanism()
    phi = doc.positions()
    assert phi.shape == (361,) and phi[-1] == pytest.approx(2 * np.pi)
    k1 = kinematics(mech, phi)
    ref = fourbar(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0),
                  inertias=(0.000833, 0.0225, 0.00567), omega1=10.0)
    k2 = kinematics(ref, phi)
    np.testing.assert_allclose(k1.omega, k2.omega, atol=1e-12)
    np.testing.assert_allclose(inverse_dynamics(k1).Q, inverse_dynamics(k2).Q, atol=1e-10)
    assert k1.omega1[0] == 10.0


def test_units_and_load_window(tmp_path):
    text = (EXAMPLES / "sine_press_planar.toml").read_text()
    doc = files.load(EXAMPLES / "sine_press_planar.toml")
    assert doc.driver.omega1 == pytest.approx(4 * np.pi)  # 120 rpm
    phi = np.radians([90.0, 100.0, 120.0, 150.0, 151.0])
    (load,) = doc.loads(phi)
    np.testing.assert_allclose(load.fx, [0.0, 8000.0, 8000.0, 8000.0, 0.0])
    assert "8 kN" in text


def test_unknown_key_and_bad_structure(tmp_path):
    src = (EXAMPLES / "fourbar_paper001.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(src.replace('mass = "1 kg"', 'mass = "1 kg"\ncolour = "red"'))
    with pytest.raises(FileFormatError, match=r"body\.0\.colour: unknown key"):
        files.load(bad)
    bad.write_text(src.replace('length = "100 mm"', 'length = "100 s"'))
    with pytest.raises(FileFormatError, match="length"):
        files.load(bad)
    # drop the rocker's frame joint: under-driven
    cut = src.replace('[[joint]]\nname = "C"\ntype = "revolute"\na = "frame"\nb = "rocker"\n', "")
    assert cut != src
    bad.write_text(cut)
    with pytest.raises(FileFormatError, match="under-driven"):
        files.load(bad)


@pytest.mark.parametrize("name", ["fourbar_paper001.toml", "loom_sixbar.toml",
                                  "sine_press_planar.toml"])
def test_cli_analyze_examples(name, tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "250")  # wide enough for every column header
    rc = main(["analyze", str(EXAMPLES / name), "--out", str(tmp_path), "--angles", "0,90,200"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "mobility W = 1" in out and "Q [N" in out and "|R" in out
    with (tmp_path / "planar_dynamics.csv").open() as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    assert header[0] == "phi1 [rad]" and any(h.startswith("Q [") for h in header)
    data = json.loads((tmp_path / "planar.json").read_text())
    assert data["mobility"] == 1 and data["reaction_sign"].startswith("force exerted by")
    for png in ("planar_skeleton.png", "planar_driving_torque.png", "planar_reactions.png",
                "planar_shaking.png"):
        assert (tmp_path / png).stat().st_size > 1000
    # the CSV's torque column is the engine's
    doc = files.load(EXAMPLES / name)
    k = kinematics(doc.mechanism(), doc.positions())
    d = inverse_dynamics(k, gravity=doc.analysis.gravity, loads=doc.loads(doc.positions()),
                         about=doc.analysis.about)
    qcol = header.index(next(h for h in header if h.startswith("Q [")))
    np.testing.assert_allclose([float(r[qcol]) for r in rows[1:]], d.Q, rtol=1e-12, atol=1e-9)


def test_cli_cannot_assemble_one_line(tmp_path, capsys):
    src = (EXAMPLES / "fourbar_paper001.toml").read_text()
    f = tmp_path / "nb.toml"
    f.write_text(src.replace('length = "100 mm"', 'length = "250 mm"'))
    assert main(["analyze", str(f), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cannot assemble at phi1 in [" in err


def test_sine_press_example_matches_paper000_closed_form():
    """The engine-built sine press of the example file = inclined_slot(L1 = 50 mm, 60 deg)."""
    from linkwork.models.sine import inclined_slot

    doc = files.load(EXAMPLES / "sine_press_planar.toml")
    phi = doc.positions()
    k = kinematics(doc.mechanism(), phi)
    cf = inclined_slot(phi, 0.05, np.radians(60.0), omega1=doc.driver.omega1)
    S = k.point("ram", "S")
    np.testing.assert_allclose(0.05 - S.x, cf.X3, atol=1e-12)
    np.testing.assert_allclose(-S.ax, cf.a3, atol=1e-9 * np.max(np.abs(cf.a3)))


def test_linear_driver_file_and_cli(tmp_path, capsys, monkeypatch):
    """A crank-slider driven by its slider (linear actuator): file, table, torque sign."""
    monkeypatch.setenv("COLUMNS", "250")
    f = tmp_path / "lin.toml"
    f.write_text("""
type = "planar"
name = "slider-driven crank"
[frame]
points = { O = [0, 0], G = [0, 0] }
[[body]]
name = "crank"
start = "O"
end = "A"
length = "100 mm"
mass = 1
[[body]]
name = "rod"
start = "A"
end = "B"
length = "350 mm"
mass = 2
[[body]]
name = "slider"
points = { B = [0, 0] }
mass = 3
[[joint]]
name = "O"
type = "revolute"
a = "frame"
b = "crank"
[[joint]]
name = "A"
type = "revolute"
a = "crank"
b = "rod"
[[joint]]
name = "B"
type = "revolute"
a = "rod"
b = "slider"
[[joint]]
name = "G"
type = "prismatic"
a = "frame"
b = "slider"
through = "G"
point = "B"
[driver]
type = "linear"
joint = "G"
v1 = "0.5 m/s"
[analysis]
start = "270 mm"
stop = "430 mm"
n = 41
branches = { A = 1 }
[[load]]
type = "torque"
body = "crank"
mz = "-3 N*m"
""")
    doc = files.load(f)
    k = kinematics(doc.mechanism(), doc.positions())
    d = inverse_dynamics(k, loads=doc.loads(doc.positions()))
    # statics-dominated check by power: Q v1 = dT/dt + 3 omega_crank
    dT = np.zeros(k.n)
    for b in doc.mechanism().bodies:
        i = doc.mechanism().index[b.name]
        c = k.point(b.name, "com")
        dT += b.mass * (c.vx * c.ax + c.vy * c.ay) + b.inertia * k.omega[i] * k.eps[i]
    np.testing.assert_allclose(d.Q * 0.5, dT + 3.0 * k.omega[1], atol=1e-9)
    assert main(["analyze", str(f), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "s1 [mm]" in out and "Q [N]" in out
