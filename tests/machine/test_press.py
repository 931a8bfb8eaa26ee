"""Paper 000's press with the real motor and flywheel (linkwork.machine.press, .transient).

Reference: the reduced equation written in this test from the closed forms of paper 000
(:mod:`linkwork.models.crank_slider`, :mod:`linkwork.models.sine`: velocity and acceleration
analogues, a code path of its own, not the engine's), the torque balance through the gear (both
power directions) written again here, integrated over the crank angle by DOP853 (rtol 1e-12)
piece by piece between the press force's jumps, with the momentum kept at every switch (crank
and rotors common; the engaged links from rest). The duty schedule's speed at the start of every
revolution, its lowest speed, the speed drop per working stroke and the revolution times agree
to 1e-6 relative (about 1e-9 at 360 positions a revolution).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from linkwork.errors import ParameterError, StallError
from linkwork.machine import Gear, InductionMotor
from linkwork.machine.press import press_schedule, working_phase
from linkwork.machine.transient import run_schedule
from linkwork.models.crank_slider import offset_crank_slider
from linkwork.models.sine import inclined_slot
from linkwork.models.variable_structure import VariableStructureMechanism

RPM = math.pi / 30
G = 9.81
PRESS = VariableStructureMechanism(L1=0.05, lambda2=4.0, lambda_e=0.5, alpha=np.radians(60),
                                   f_slot=0.12, f_guide=0.10)
MASSES = dict(crank_mass=6.0, crank_inertia=0.02, crank_com=0.01, rod_mass=3.0,
              slider_mass=4.0, ram_mass=25.0, press_force=8e3, working_stroke=0.02)
SCHEDULE = [("idle", 3), ("working", 2, np.radians(60)), ("idle", 2),
            ("working", 2, np.radians(45))]
MOTOR = InductionMotor(1500.0, 1500 * RPM, 1410 * RPM, 2.6, inertia=0.004)
GEAR = Gear(1410 / 120, 0.95, 0.001)
FLYWHEEL = 1.5


def _reference_mode(mode, alpha=None):
    """J, dJ, M(phi) of a structure from paper 000's closed forms (scalars)."""
    L1, m = PRESS.L1, MASSES
    mt = m["crank_mass"]
    jc = m["crank_inertia"] + mt * m["crank_com"] ** 2
    if mode == "idle":
        L2 = PRESS.lambda2 * L1
        j_rod = m["rod_mass"] * L2**2 / 12

        def f(phi):
            k = offset_crank_slider(phi, L1, PRESS.lambda2, PRESS.lambda_e, 1.0, 0.0)
            vB = L1 * np.array([-math.sin(phi), math.cos(phi)])
            aB = -L1 * np.array([math.cos(phi), math.sin(phi)])
            vS = 0.5 * (vB + np.array([0.0, float(k.V_qC)]))
            aS = 0.5 * (aB + np.array([0.0, float(k.a_qC)]))
            u21, eq2 = float(k.U21), float(k.eps_q2)
            J = jc + m["rod_mass"] * vS @ vS + j_rod * u21**2 + m["slider_mass"] * float(
                k.V_qC) ** 2
            dJ = 2 * (m["rod_mass"] * vS @ aS + j_rod * u21 * eq2
                      + m["slider_mass"] * float(k.V_qC * k.a_qC))
            Mg = G * math.sin(phi) * (mt * m["crank_com"] + m["rod_mass"] * L1 / 2)
            return J, dJ, Mg
        return f, []
    start, end = working_phase(L1, alpha, m["working_stroke"])

    def f(phi):
        k = inclined_slot(phi, L1, alpha, 1.0, 0.0)
        u31, aq3 = float(k.U31), float(k.a_q3)
        J = jc + m["ram_mass"] * u31**2
        dJ = 2 * m["ram_mass"] * u31 * aq3
        M = G * (mt * m["crank_com"] * math.sin(phi) + m["ram_mass"] * u31)
        if (phi - start) % (2 * math.pi) <= end - start:
            M -= m["press_force"] * u31
        return J, dJ, M
    return f, [start, end]


def _eps(f, phi, w):
    J, dJ, M = f(phi)
    i, eta = GEAR.ratio, GEAR.efficiency
    jin = MOTOR.inertia + GEAR.inertia
    a = float(MOTOR.torque(i * w))
    c = 0.5 * dJ * w * w - M
    eps = (i * eta * a - c) / (i * eta * jin * i + J + FLYWHEEL)  # the motor drives
    if a - jin * i * eps < 0:                                        # the crank drives back
        eps = (i / eta * a - c) / (i / eta * jin * i + J + FLYWHEEL)
    return eps


def _reference_run(w0, segments):
    jr = (MOTOR.inertia + GEAR.inertia) * GEAR.ratio**2 + FLYWHEEL
    jc = MASSES["crank_inertia"] + MASSES["crank_mass"] * MASSES["crank_com"] ** 2
    w, t = w0, 0.0
    revs = []
    for mode, count, alpha in segments:
        f, breaks = _reference_mode(mode, alpha)
        if revs:  # a switch at phi = 0: generalised momentum of crank and rotors kept
            w = w * (jc + jr) / (f(0.0)[0] + jr)
        for _ in range(count):
            cuts = sorted({0.0, 2 * math.pi, *(b % (2 * math.pi) for b in breaks)})
            w_start, w_min, t_start = w, w, t
            for a, b in itertools.pairwise(cuts):
                sol = solve_ivp(lambda p, y, f=f: [_eps(f, p, y[0]) / y[0], 1 / y[0]], (a, b),
                                [w, t], method="DOP853", rtol=1e-12, atol=1e-14,
                                dense_output=True)
                dense = sol.sol(np.linspace(a, b, 400))[0]
                w_min = min(w_min, float(np.min(dense)))
                w, t = float(sol.y[0, -1]), float(sol.y[1, -1])
            revs.append((w_start, w_min, t_start, t - t_start))
    return np.array(revs)


@pytest.mark.slow
def test_duty_schedule_speed_drop_per_stroke_against_closed_form_integration():
    modes, segs = press_schedule(PRESS, SCHEDULE, **MASSES)
    w0 = 127.6 * RPM
    run = run_schedule(modes, segs, MOTOR, gear=GEAR, flywheel=FLYWHEEL, start=w0, n=360)
    ref = _reference_run(w0, [("idle", 3, None), ("working", 2, np.radians(60)),
                              ("idle", 2, None), ("working", 2, np.radians(45))])
    np.testing.assert_allclose(run.rev_omega_start, ref[:, 0], rtol=1e-6)
    np.testing.assert_allclose(run.rev_omega_min, ref[:, 1], rtol=1e-6)
    np.testing.assert_allclose(run.rev_t, ref[:, 2], rtol=1e-6, atol=1e-9)
    drop = (ref[:, 0] - ref[:, 1]) / ref[:, 0]
    np.testing.assert_allclose(run.rev_drop, drop, rtol=0, atol=1e-6)
    working = run.rev_mode != 0
    assert np.all(run.rev_drop[working] > 0.05)          # each stroke costs visible speed
    np.testing.assert_allclose(run.rev_work_loads[working], 8e3 * 0.02, rtol=1e-9)
    # the switches: instants, speeds before and after, the engagement's energy
    assert run.switch_names == ["working 60 deg", "idle", "working 45 deg"]
    assert np.all(run.switch_energy_loss > 0)
    assert np.all(run.switch_omega_after < run.switch_omega_before)


def test_press_modes_check_their_inputs():
    with pytest.raises(ParameterError, match="working_stroke"):
        press_schedule(PRESS, SCHEDULE, **{**MASSES, "working_stroke": 0.5})
    with pytest.raises(ParameterError, match="ram_mass"):
        press_schedule(PRESS, SCHEDULE, **{**MASSES, "ram_mass": -1.0})
    with pytest.raises(ParameterError, match="alpha"):
        press_schedule(PRESS, [("working", 1, np.radians(5))], **MASSES)


def test_a_weak_motor_stalls_on_the_working_stroke_with_a_clear_error():
    modes, segs = press_schedule(PRESS, SCHEDULE, **{**MASSES, "press_force": 60e3})
    with pytest.raises(StallError, match=r"the crank stops at phi1 = [\d.]+ deg, t = [\d.]+ s "
                       r"\(in mode 'working 60 deg'\)"):
        run_schedule(modes, segs, MOTOR, gear=GEAR, flywheel=0.0, start=127 * RPM)
