"""``linkwork analyze`` of a planar file with friction prints the losses per joint, the cycle
efficiency and the self-locking ranges, writes them to planar.json and the friction powers to
planar_dynamics.csv, and plots Q with and without friction; a frictionless file prints none
of it."""

import csv
import json

import numpy as np
import pytest
from _cli_files import EXAMPLES, sine_press_with_friction

from linkwork.cli import main


def test_analyze_prints_losses_and_efficiency(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["analyze", str(sine_press_with_friction(tmp_path)), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    data = json.loads((out / "planar.json").read_text())
    fr = data["friction"]
    assert "friction losses over the cycle" in text
    assert f"cycle efficiency (useful work / driver's work): {fr['efficiency_cycle']:.4f}" in text
    assert "self-locking: none over the range" in text
    for j in ("A", "guide", "slot"):
        assert fr["losses"][j] > 0
    with (out / "planar_dynamics.csv").open() as fh:
        head = next(csv.reader(fh))
    assert {"Pf_A [W]", "Pf_guide [W]", "Pf_slot [W]", "Q_frictionless [N*m]"} <= set(head)
    assert (out / "planar_driving_torque.png").stat().st_size > 0


def test_analyze_names_self_locking_ranges(tmp_path, capsys):
    out = tmp_path / "out"
    path = sine_press_with_friction(tmp_path, '"12 deg"')
    assert main(["analyze", str(path), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    data = json.loads((out / "planar.json").read_text())
    assert data["friction"]["self_locking"]
    assert "self-locking (no finite driving torque moves it) at φ1 = " in text
    assert "cycle efficiency (useful work / driver's work): undefined" in text
    a, b = data["friction"]["self_locking"][0]
    assert f"{np.degrees(a):.1f}..{np.degrees(b):.1f}" in text


@pytest.mark.parametrize("example", ["sine_press_planar.toml", "fourbar_paper001.toml"])
def test_frictionless_files_print_no_friction(tmp_path, capsys, example):
    out = tmp_path / "out"
    path = EXAMPLES / example
    assert main(["analyze", str(path), "--out", str(out)]) == 0
    text = capsys.readouterr().out.split("\nwrote ")[0]  # (the paths name this test)
    assert "friction" not in text and "self-locking" not in text
    assert "friction" not in json.loads((out / "planar.json").read_text())


def test_mean_driving_torque_is_undefined_where_it_self_locks(tmp_path, capsys):
    """With the slot at 12 deg the press self-locks over part of the turn: the driver's work
    over the range, and so the mean driving torque and power, are undefined (printed '-',
    null in planar.json), not the mean of the other positions (-59 N·m for a press doing
    work). Analysed over 160..200 deg only, where every position locks, the command prints
    no warning and exits 0."""
    out = tmp_path / "out"
    path = sine_press_with_friction(tmp_path, '"12 deg"')
    assert main(["analyze", str(path), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    means = json.loads((out / "planar.json").read_text())["means"]
    assert means["Q_mean"] is None and means["power_mean"] is None
    rows = [ln for ln in text.splitlines() if "Q mean (work / range)" in ln
            or "driving power, mean" in ln]
    assert len(rows) == 2 and all(ln.split("│")[2].strip() == "-" for ln in rows), rows
    text = path.read_text().replace('start = "0 deg"', 'start = "160 deg"').replace(
        'stop = "360 deg"', 'stop = "200 deg"').replace("n = 361", "n = 41")
    path.write_text(text)
    assert main(["analyze", str(path), "--out", str(out)]) == 0
    io = capsys.readouterr()
    assert io.err == ""
    assert "self-locking (no finite driving torque moves it) at φ1 = 160.0..200.0 deg" in io.out
