"""``linkwork dynamics``: the study of a [drive] table through the command line, its files and
its failure policy (one line on stderr, exit code 2) for a motor too weak, a delta no flywheel
reaches, a file without a [drive] table."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from _cli_files import run_cli, sine_press_with_friction

from linkwork import io
from linkwork.studies import dynamics as study

EXAMPLES = Path(__file__).parents[2] / "examples"


def _file(tmp_path, drive, base="fourbar_paper001.toml"):
    p = tmp_path / "m.toml"
    p.write_text((EXAMPLES / base).read_text() + "\n" + drive)
    return p


MOTOR = """
[[drive.motor]]
name = "small"
type = "induction"
rated_power = "250 W"
synchronous_speed = "1500 rpm"
rated_speed = "1400 rpm"
breakdown_ratio = 2.4
inertia = "0.0005 kg*m^2"
"""


@pytest.mark.slow
def test_knuckle_press_example_sizes_its_flywheel_and_checks_three_motors(tmp_path, capsys):
    code, out, err = run_cli(["dynamics", str(EXAMPLES / "loom_sixbar.toml"), "--out",
                              str(tmp_path)], capsys)
    assert code == 0, err
    assert "exact (periodic solve)" in out and "Wittenbauer" in out
    assert "1.5 kW induction: OK: RMS torque" in out
    data = json.loads((tmp_path / "dynamics.json").read_text())
    assert data["sizing"]["delta_reached"] == pytest.approx(0.10, rel=1e-8)
    assert data["flywheel"] == pytest.approx(data["sizing"]["flywheel"])
    first = data["motors"][0]["steady"]
    assert first["delta"] == pytest.approx(0.10, rel=1e-8)
    for name in ("dynamics_motor1.csv", "dynamics_motor3.csv", "dynamics_startup.csv",
                 "dynamics_speed.png", "dynamics_torque.png", "dynamics_energy_mass.png",
                 "dynamics_startup.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    head = (tmp_path / "dynamics_motor1.csv").read_text().splitlines()[0]
    assert head.startswith("phi1 [rad],t [s],omega [rad/s],eps [rad/s^2]")


@pytest.mark.slow
def test_sine_press_duty_schedule_through_the_command(tmp_path, capsys):
    code, out, err = run_cli(["dynamics", str(EXAMPLES / "sine_press.toml"), "--out",
                              str(tmp_path)], capsys)
    assert code == 0, err
    assert "schedule with 1.5 kW induction" in out
    assert "switch at t = " in out and "to working 60 deg" in out
    assert "0.55 kW induction: overheats" in out
    data = json.loads((tmp_path / "dynamics.json").read_text())
    revs = data["schedule"]["revolutions"]
    assert len(revs["drop"]) == 12                   # 5 + 3 + 2 + 2 revolutions
    assert min(revs["drop"][5:8]) > 0.05             # every working stroke costs speed
    assert [s["to"] for s in data["schedule"]["switches"]] == [
        "working 60 deg", "idle", "working 45 deg"]
    assert (tmp_path / "dynamics_schedule.png").stat().st_size > 0


def test_study_of_a_planar_file_with_a_load_schedule(tmp_path):
    doc = io.load(_file(tmp_path, """
[[load]]
type = "torque"
body = "crank"
mz = "-1.5 N*m"
phi_range = ["30 deg", "150 deg"]

[drive]
flywheel = "0.05 kg*m^2"
start_up = false
[drive.gear]
ratio = 14
[[drive.schedule]]
revolutions = 2
load = 0
[[drive.schedule]]
revolutions = 2
""" + MOTOR))
    s = study.run(doc)
    assert s.kind == "planar" and s.flywheel == 0.05
    assert s.choices[0].steady is not None and s.choices[0].start is None
    assert list(s.schedule.modes) == ["loads x 0", "loads x 1"]
    np.testing.assert_allclose(study.breaks_of(doc), np.radians([30.0, 150.0]))
    w = s.schedule.rev_work_loads
    assert w[0] == 0.0 and w[2] == pytest.approx(1.5 * 2 * np.pi / 3, rel=1e-9)
    d = s.to_dict()
    assert d["motors"][0]["verdict"].startswith("OK")
    assert len(d["motors"][0]["steady"]["columns"]["omega"]) == len(s.steady.phi1)


@pytest.mark.parametrize(("drive", "words"), [
    ("[[load]]\ntype = \"torque\"\nbody = \"crank\"\nmz = \"-30 N*m\"\n[drive]\nstart_up = false\n"
     "[drive.gear]\nratio = 5\n" + MOTOR,
     r"mean load torque 30 N·m \(6 N·m at the motor through the gear i = 5, "
     r"efficiency 1\) exceeds the motor's breakdown torque 4.093 N·m"),
    ("[drive]\ndelta = 1e-9\n[drive.gear]\nratio = 14\n" + MOTOR,
     r"delta 1e-09 cannot be sized: it is below 1e-06"),
    ("[drive]\ndelta = 0.0001\nmax_flywheel = \"0.01 kg*m^2\"\n[drive.gear]\nratio = 14\n" + MOTOR,
     r"delta 0.0001 cannot be reached with a flywheel up to 0.01 kg·m² \(max_flywheel\): it "
     r"leaves delta = "),
    ("", r"m.toml: drive: missing: linkwork dynamics needs a \[drive\] table"),
])
def test_failures_are_one_line_and_exit_2(tmp_path, capsys, drive, words):
    code, _out, err = run_cli(["dynamics", str(_file(tmp_path, drive)), "--out",
                              str(tmp_path / "o")], capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkwork: error: ")
    assert re.search(words, lines[0]), lines[0]


def test_a_file_whose_friction_self_locks_it_is_one_line(tmp_path, capsys):
    """The sine press with its slot at 12 deg self-locks over part of the turn with the file's
    friction (docs/friction.md): the machine's motion is undefined there; one line names the
    file, the joints' coefficients and the ranges in order over the turn (it said 'mechanism =
    with friction is invalid: self-locks at phi1 = 151 deg (264 positions)', no file)."""
    path = sine_press_with_friction(tmp_path, '"12 deg"')
    path.write_text(path.read_text() + '\n[drive]\nflywheel = "2 kg*m^2"\npositions = 360\n'
                    "start_up = false\n" + MOTOR)
    code, _, err = run_cli(["dynamics", str(path), "--out", str(tmp_path / "out")], capsys)
    assert code == 2 and err.count("\n") == 1, err
    assert f"{path}: joint friction: 0.05 (A), 0.1 (guide), 0.12 (slot) is invalid: makes the " \
        "mechanism self-lock at phi1 in [" in err
    found = [float(x) for r in re.findall(r"\[([0-9.]+), ([0-9.]+) deg\]", err) for x in r]
    assert found and found == sorted(found) and 0 <= found[0] and found[-1] < 360, err
    assert "the machine's motion needs the driving torque at every position" in err
