"""The ``[drive]`` and ``[press]`` tables (linkwork.io.drive): motors built from file data with
units, the keys of each motor type, and one error naming the file and key for what is wrong."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from linkwork import io
from linkwork.errors import FileFormatError
from linkwork.machine import ConstantSpeed, DCMotor, InductionMotor

EXAMPLES = Path(__file__).parents[2] / "examples"
RPM = math.pi / 30


def _with_drive(tmp_path, drive: str) -> Path:
    text = (EXAMPLES / "fourbar_paper001.toml").read_text() + "\n" + drive
    p = tmp_path / "f.toml"
    p.write_text(text)
    return p


def test_motors_gear_and_flywheel_from_a_file(tmp_path):
    doc = io.load(_with_drive(tmp_path, """
[drive]
flywheel = "0.4 kg*m^2"
[drive.gear]
ratio = 14
efficiency = 0.9
inertia = "1e-4 kg*m^2"
[[drive.motor]]
type = "induction"
rated_power = "0.25 kW"
synchronous_speed = "1500 rpm"
rated_speed = "1400 rpm"
breakdown_ratio = 2.4
inertia = "5 kg*cm^2"
[[drive.motor]]
type = "dc"
rated_power = "200 W"
rated_speed = "1400 rpm"
no_load_speed = "1600 rpm"
[[drive.motor]]
type = "constant_speed"
speed = "100 rpm"
"""))
    m = doc.drive.motors()
    assert isinstance(m[0], InductionMotor) and m[0].rated_power == pytest.approx(250.0)
    assert m[0].rated_speed == pytest.approx(1400 * RPM) and m[0].inertia == pytest.approx(5e-4)
    assert isinstance(m[1], DCMotor) and m[1].rated_torque == pytest.approx(200 / (1400 * RPM))
    assert isinstance(m[2], ConstantSpeed) and m[2].speed == pytest.approx(100 * RPM)
    assert [x.name for x in m] == ["motor 1", "motor 2", "motor 3"]
    g = doc.drive.build_gear()
    assert (g.ratio, g.efficiency, g.inertia) == (14.0, 0.9, 1e-4)
    assert doc.drive.flywheel == pytest.approx(0.4)
    assert doc.mechanism() is not None   # the rest of the file as before


@pytest.mark.parametrize(("drive", "key", "words"), [
    ('[drive]\n[[drive.motor]]\ntype = "induction"\nrated_power = "1 kW"\n',
     "drive.motor.0", "needs 'synchronous_speed'"),
    ('[drive]\n[[drive.motor]]\ntype = "dc"\nstall_torque = 5\nno_load_speed = 100\n'
     'speed = "10 rpm"\n', "drive.motor.0", "'speed' is not a key of a dc motor"),
    ('[drive]\nflywheel = 1\ndelta = 0.1\n[[drive.motor]]\ntype = "constant_speed"\n'
     'speed = 10\n', "drive", "a flywheel or a delta"),
    ('[drive]\ndelta = 0\n[[drive.motor]]\ntype = "dc"\nstall_torque = 5\n'
     'no_load_speed = 100\n', "drive.delta", "0 is invalid: must be > 0"),
    ('[drive]\n[[drive.motor]]\ntype = "induction"\nrated_power = "1 kW"\n'
     'synchronous_speed = "1500 rpm"\nrated_speed = "1400 rpm"\nbreakdown_ratio = 0.8\n',
     "drive.motor.0.breakdown_ratio", "0.8 is invalid: must be > 1"),
    ('[drive]\n[[drive.motor]]\ntype = "dc"\nstall_torque = "5 kg"\nno_load_speed = 100\n',
     "drive.motor.0.stall_torque", "torque"),
    ('[drive]\n[drive.gear]\nefficiency = 1.5\n[[drive.motor]]\ntype = "dc"\n'
     'stall_torque = 5\nno_load_speed = 100\n', "drive.gear.efficiency", "1"),
])
def test_bad_drive_tables_name_file_and_key(tmp_path, drive, key, words):
    with pytest.raises(FileFormatError) as err:
        io.load(_with_drive(tmp_path, drive))
    msg = str(err.value)
    assert f"f.toml: {key}" in msg and words in msg, msg


def test_press_table_of_the_sine_press_example():
    doc = io.load(EXAMPLES / "sine_press.toml")
    masses = doc.press.masses()
    assert masses["press_force"] == pytest.approx(8e3)
    assert masses["working_stroke"] == pytest.approx(0.02)
    assert masses["gravity"] == pytest.approx((-9.81, 0.0))
    assert [m.name for m in doc.drive.motors()] == ["1.5 kW induction", "0.55 kW induction"]
