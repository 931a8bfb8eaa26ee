"""Motor selection (linkwork.machine.selection): figures and verdict lines.

The factor an overloaded motor needs is checked against its own definition: the motor scaled
by it (x 1.002) runs the machine on its stable branch, scaled by it / 1.002 it does not. The
figures are those of the steady state (peak over the limit, RMS over the rated torque).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork import io
from linkwork.errors import ParameterError
from linkwork.machine import DCMotor, Gear, InductionMotor, machine
from linkwork.machine.selection import _runs, scaled, select_motors

RPM = math.pi / 30


def _press():
    doc = io.load("examples/loom_sixbar.toml")
    return dict(mech=doc.mechanism(), loads=doc.loads, gravity=doc.analysis.gravity,
                breaks=np.radians([145.0, 184.7]), gear=Gear(36.0, 0.95, 0.002))


MOTORS = [InductionMotor(4000.0, 1500 * RPM, 1440 * RPM, 2.8, inertia=0.012, name="4 kW"),
          InductionMotor(1100.0, 1500 * RPM, 1420 * RPM, 2.3, inertia=0.003, name="1.1 kW"),
          InductionMotor(250.0, 1500 * RPM, 1380 * RPM, 2.2, inertia=0.001, name="0.25 kW"),
          DCMotor.from_rated(1500.0, 1500 * RPM, 1700 * RPM, inertia=0.004, name="DC")]


def test_verdicts_with_a_flywheel():
    p = _press()
    choices = select_motors(p.pop("mech"), MOTORS, flywheel=30.0, **p)
    big, _, small, dc = choices
    assert big.ok and big.verdict.startswith("OK: RMS torque")
    assert big.peak_ratio == pytest.approx(big.torque_peak / MOTORS[0].breakdown_torque)
    assert big.rms_ratio == pytest.approx(big.torque_rms / MOTORS[0].rated_torque)
    assert "start-up" in big.verdict and big.start is not None
    assert not small.ok and small.verdict.startswith("overheats: RMS torque")
    assert small.rms_ratio > 1
    assert dc.ok and "stall torque" in dc.verdict
    d = big.to_dict()
    assert d["ok"] and d["start"]["t_steady"] > 0


def test_overloaded_motor_needs_the_factor_it_names():
    p = _press()
    mech = p.pop("mech")
    choice = select_motors(mech, [MOTORS[1]], flywheel=0.0, start=False, **p)[0]
    assert not choice.ok
    assert choice.verdict.startswith("overloaded at ")
    assert "x the breakdown torque" in choice.verdict
    k = choice.needs
    m = machine(mech, MOTORS[1], **p)
    assert _runs(m.with_motor(scaled(MOTORS[1], k * 1.002))) is not None
    assert _runs(m.with_motor(scaled(MOTORS[1], k / 1.002))) is None
    deg = float(choice.verdict.split(" at ")[1].split(" deg")[0])
    assert 140 <= deg <= 190                    # where the coining force acts


def test_scaled_motors_and_bad_input():
    s = scaled(MOTORS[0], 2.0)
    assert s.breakdown_torque == pytest.approx(2 * MOTORS[0].breakdown_torque)
    assert s.breakdown_speed == pytest.approx(MOTORS[0].breakdown_speed)
    assert scaled(MOTORS[3], 3.0).stall_torque == pytest.approx(3 * MOTORS[3].stall_torque)
    with pytest.raises(ParameterError, match="motors"):
        select_motors(_press()["mech"], [])
