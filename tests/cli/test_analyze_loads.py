"""``linkwork analyze`` of a planar file with force elements and a load diagram (the crank press
example) prints each load's range and work and where its diagram acts, writes their columns to
planar_dynamics.csv and planar.json and draws planar_loads.png; files without them print and
draw none of it."""

import csv
import json
from pathlib import Path

from linkwork.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_analyze_press_prints_and_writes_its_loads(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["analyze", str(EXAMPLES / "crank_press.toml"), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "loads and force elements over the cycle (721 positions" in text
    assert ("drawing: diagram over the slide s of guide from -450.0 to -430.0 mm, acting while "
            "it decreases; outside its range zero") in text
    row = next(line for line in text.splitlines() if "counterbalance" in line)
    assert "spring" in row and "2250" in row and "2750" in row and "350.0..450.0" in row
    row = next(line for line in text.splitlines() if "│ drawing" in line)
    assert "-2920" in row  # the work of one stroke [J], the area under the table
    with (out / "planar_dynamics.csv").open() as fh:
        head = next(csv.reader(fh))
    assert {"F_drawing [N]", "P_drawing [W]", "F_counterbalance [N]", "L_counterbalance [m]",
            "P_counterbalance [W]", "V [J]"} <= set(head)
    data = json.loads((out / "planar.json").read_text())
    assert [e["name"] for e in data["loads"]] == ["drawing", "counterbalance"]
    assert (out / "planar_loads.png").stat().st_size > 0
    record = json.loads((out / "linkwork-run.json").read_text())
    assert "planar_loads.png" in [f["name"] for f in record["runs"]["analyze"]["files"]]


def test_no_loads_no_loads_output(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["analyze", str(EXAMPLES / "fourbar_paper001.toml"), "--out", str(out)]) == 0
    assert "loads and force elements" not in capsys.readouterr().out
    assert not (out / "planar_loads.png").exists()
