"""Transients (linkwork.machine.transient): start-up from rest, loads changing over time.

Reference: tests/_machine_lagrange.py's multibody model integrated in time (y = (phi, omega),
DOP853 at rtol 1e-11) from the same initial state, compared at the run's instants. The start
from rest, where the speed grows as the square root of the angle, is marched on a grid refined
geometrically towards the start: omega(t) agrees to about 4e-7 of the mean speed (tolerance
1e-5); a load changing smoothly over time to about 7e-9 (tolerance 1e-6).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _machine_lagrange import Multibody, run_in_time

from linkwork import io
from linkwork.errors import DriveError, ParameterError, StallError
from linkwork.machine import ConstantSpeed, DCMotor
from linkwork.machine.transient import Mode, run_schedule, start_up
from linkwork.planar import BodyTorque, PointForce

G = (0.0, -9.81)
MOTOR = DCMotor(20.0, 12.0, inertia=0.01)
FLYWHEEL = 0.02


def _fy(p):
    return -40.0 * np.exp(-((np.mod(p - np.radians(200) + np.pi, 2 * np.pi) - np.pi) / 0.5)
                          ** 2) - 5.0


def _case():
    mech = io.load("examples/fourbar_paper001.toml").mechanism()
    mb = Multibody(mech, lambda p, w: float(MOTOR.torque(w)), rotors=MOTOR.inertia + FLYWHEEL,
                   gravity=G, loads=lambda p: [("force", "coupler", (0.15, 0.1), 0.0,
                                                float(_fy(p)))])
    return mech, (lambda p: [PointForce("coupler", "P", 0.0, _fy(p))]), mb


@pytest.mark.slow
def test_start_up_from_rest_against_lagrange_in_time():
    mech, loads, mb = _case()
    su = start_up(mech, MOTOR, loads=loads, gravity=G, flywheel=FLYWHEEL, n=360)
    run = su.run
    ref = run_in_time(mb, 0.0, float(run.t[-1]))(run.t)
    wm = su.steady.omega_mean
    assert np.max(np.abs(ref[1] - run.omega)) <= 1e-5 * wm
    assert np.max(np.abs(ref[0] - run.phi1)) <= 1e-5
    # after t_steady the reference stays within the band of the steady state
    late = run.t >= su.t_steady
    w_ss = np.interp(np.mod(run.phi1[late], 2 * np.pi), su.steady.phi1, su.steady.omega,
                     period=2 * np.pi)
    assert np.max(np.abs(ref[1][late] - w_ss)) <= su.band * wm * (1 + 1e-3)
    assert su.torque_peak == pytest.approx(MOTOR.stall_torque)   # a DC motor: at standstill
    assert 0 < su.t_steady < run.t[-1] and su.t_mean_speed > 0
    assert run.omega[0] == 0.0


@pytest.mark.slow
def test_load_changing_over_time_against_lagrange_in_time():
    mech, loads, mb = _case()

    def factor(t):
        return 1.0 + 2.0 / (1.0 + math.exp(-(t - 1.0) / 0.1))   # the load triples near 1 s

    run = run_schedule([Mode("m", mech, loads, G)], [("m", 6)], MOTOR, flywheel=FLYWHEEL,
                       start="steady", load_factor=factor)
    ref = run_in_time(mb, 0.0, float(run.t[-1]), omega0=float(run.omega[0]),
                      factor=factor)(run.t)
    assert np.max(np.abs(ref[1] - run.omega)) <= 1e-6 * float(np.mean(run.omega))
    # the tripled load changes the mean speed in the sense of its work (here it drives: the
    # force on the coupler point does negative work on the mechanism's side over a cycle)
    sign = np.sign(run.rev_work_loads[0])
    assert sign * (run.rev_omega_mean[-1] - run.rev_omega_mean[0]) < 0
    assert run.rev_work_loads[-1] == pytest.approx(3 * run.rev_work_loads[0], rel=1e-3)


def test_a_motor_that_cannot_start_the_machine():
    mech, _, _ = _case()
    load = lambda p: [BodyTorque("crank", -(5.0 + 30.0 * np.cos(p)))]  # noqa: E731
    with pytest.raises(StallError, match=r"cannot start the machine at phi1 = 0\.0 deg: its "
                       r"starting torque 20 N·m gives 20 N·m at the crank, below the load "
                       r"torque 35 N·m there"):
        start_up(mech, MOTOR, loads=load, flywheel=2.0)


def test_transients_refuse_what_they_cannot_do():
    mech, loads, _ = _case()
    with pytest.raises(DriveError, match="holds the speed"):
        start_up(mech, ConstantSpeed(10.0), loads=loads)
    with pytest.raises(ParameterError, match="band"):
        start_up(mech, MOTOR, loads=loads, band=0.0)
    with pytest.raises(ParameterError, match=r"schedule\[0\]"):
        run_schedule([Mode("m", mech, loads)], [("x", 2)], MOTOR)
    with pytest.raises(ParameterError, match="positions in all"):
        run_schedule([Mode("m", mech, loads)], [("m", 10**6)], MOTOR)


def test_run_exports_its_switches_and_revolutions():
    mech, loads, _ = _case()
    modes = [Mode("light", mech, (), G), Mode("loaded", mech, loads, G)]
    run = run_schedule(modes, [("light", 2), ("loaded", 3), ("light", 3)], MOTOR,
                       flywheel=FLYWHEEL)
    d = run.to_dict()
    assert [s["to"] for s in d["switches"]] == ["loaded", "light"]
    assert len(d["revolutions"]["omega_mean"]) == 8
    # the same mechanism on both sides of a switch: nothing engaged, no energy lost
    np.testing.assert_allclose(run.switch_omega_after, run.switch_omega_before, rtol=1e-13)
    np.testing.assert_allclose(run.switch_energy_loss, 0.0, atol=1e-12)
    rec = run.recovery(band=0.01)
    assert rec[1]["to"] == "light" and rec[1]["revolutions"] is not None
    assert np.count_nonzero(run.switch) == 2
    assert run.t.size == run.omega.size == run.mode.size
