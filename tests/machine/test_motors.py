"""Motor characteristics (linkwork.machine.motors).

Kloss's formula from catalogue data: the characteristic passes through the rated point
(torque P_r/omega_r at the rated speed) and peaks at the breakdown torque lambda M_r at the
breakdown slip s_k, which lies beyond the rated slip (stable branch); the slope is checked
against a central difference (1e-7 relative), ``speed_at`` inverts the stable branch. A worked
catalogue case by hand: 5.5 kW, 1500/1445 rpm, lambda = 2.7 gives s_r = 0.036667,
s_k = s_r (2.7 + sqrt(2.7^2 - 1)) = 0.191959, M_r = 36.347 N m, M_k = 98.137 N m.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from linkwork.errors import InfeasibleError, ParameterError
from linkwork.machine import ConstantSpeed, ConstantTorque, DCMotor, Gear, InductionMotor

RPM = math.pi / 30


def test_kloss_worked_catalogue_case():
    m = InductionMotor(5500.0, 1500 * RPM, 1445 * RPM, 2.7)
    assert m.rated_slip == pytest.approx(55 / 1500, rel=1e-14)
    assert m.breakdown_slip == pytest.approx(0.0366667 * (2.7 + math.sqrt(2.7**2 - 1)),
                                             rel=1e-6)
    assert m.rated_torque == pytest.approx(5500 / (1445 * RPM), rel=1e-14)
    assert m.breakdown_torque == pytest.approx(98.137, rel=1e-4)
    assert m.torque(1445 * RPM) == pytest.approx(m.rated_torque, rel=1e-12)
    assert m.torque(m.breakdown_speed) == pytest.approx(m.breakdown_torque, rel=1e-12)
    assert m.torque(1500 * RPM) == 0.0
    assert m.starting_torque == pytest.approx(m.torque(0.0), rel=1e-12)


@given(st.floats(1e2, 1e6), st.floats(0.005, 0.1), st.floats(1.2, 3.5),
       st.floats(0.0, 1.2))
def test_kloss_stable_branch_and_slope(power, slip, lam, where):
    ws = 157.07963
    m = InductionMotor(power, ws, ws * (1 - slip), lam)
    assert m.breakdown_slip > m.rated_slip
    w = ws * (1 - where * m.breakdown_slip)  # from synchronous down to past breakdown
    h = 1e-6 * ws
    fd = (m.torque(w + h) - m.torque(w - h)) / (2 * h)
    assert m.slope(w) == pytest.approx(fd, rel=1e-6, abs=1e-9 * m.breakdown_torque / ws)
    if where < 1:
        assert m.slope(w) < 0  # stable: torque falls as the speed rises
        assert m.speed_at(float(m.torque(w))) == pytest.approx(w, rel=1e-12)
    else:
        assert m.slope(w) >= -1e-9 * m.breakdown_torque / ws


def test_dc_motor_from_rated_data():
    m = DCMotor.from_rated(2000.0, 1000 * RPM, 1200 * RPM, inertia=0.01)
    mr = 2000.0 / (1000 * RPM)
    assert m.rated_torque == pytest.approx(mr)
    assert m.torque(1000 * RPM) == pytest.approx(mr, rel=1e-13)
    assert m.torque(1200 * RPM) == pytest.approx(0.0, abs=1e-12)
    assert m.stall_torque == pytest.approx(mr * 1200 / 200)
    assert m.speed_at(mr) == pytest.approx(1000 * RPM)
    assert np.all(m.slope(np.array([0.0, 50.0])) == -m.stall_torque / m.no_load_speed)
    with pytest.raises(InfeasibleError):
        m.speed_at(1.01 * m.stall_torque)


@pytest.mark.parametrize(("make", "match"), [
    (lambda: InductionMotor(5500, 157, 160, 2.5), "rated_speed.*synchronous_speed"),
    (lambda: InductionMotor(5500, 157, 150, 1.0), "breakdown_ratio"),
    (lambda: InductionMotor(-1, 157, 150, 2.5), "rated_power"),
    (lambda: DCMotor(0.0, 100.0), "stall_torque"),
    (lambda: DCMotor(10.0, 100.0, inertia=-1.0), "inertia"),
    (lambda: DCMotor.from_rated(100, 200, 150), "rated_speed"),
    (lambda: ConstantSpeed(0.0), "speed"),
    (lambda: ConstantTorque(float("nan")), "mean_speed"),
    (lambda: Gear(0.0), "gear.ratio"),
    (lambda: Gear(10.0, 1.2), "gear.efficiency"),
    (lambda: Gear(10.0, 0.9, -1.0), "gear.inertia"),
])
def test_bad_motor_data_is_named(make, match):
    with pytest.raises(ParameterError, match=match):
        make()
