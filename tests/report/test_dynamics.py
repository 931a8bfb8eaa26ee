"""The machine-dynamics part of the report (linkwork.report.dynamics): what it shows is the
study's (linkwork.studies.dynamics, run here directly), and the page's drawing carries each
motor's real motion for real-time playback.

References: the study itself (the shown numbers must be its own: 4 significant digits as
printed, arrays to 1e-12); the time of the real motion as the integral dt = dphi/omega of the
study's crank speed (trapezoid over its 1-degree nodes: within 6e-6 of the period on these
examples, so the frames' times are compared to 2e-5 of the period); Wittenbauer's two tangents
meet at J = -J_F (J_F = (b_max - b_min)/(k_max - k_min)).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from linkwork import io, report
from linkwork.plot.numbers import fmt
from linkwork.studies import dynamics as study_dynamics

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
RPM = 30 / math.pi


@pytest.fixture(scope="module")
def loom():
    path = EXAMPLES / "loom_sixbar.toml"
    doc = io.load(path)
    return report.build(doc, path=path), study_dynamics.run(doc)


def _section(page, key="dynamics"):
    return next(s for s in page.sections if s.key == key)


def _diagram(section, start):
    return next(d for d in section.diagrams if d.title.startswith(start))


def test_the_section_shows_the_studys_motors_verdicts_and_flywheel(loom):
    page, study = loom
    sec = _section(page)
    assert not sec.error
    assert [t for _, t in sec.verdicts] == [f"{c.motor.name}: {c.verdict}"
                                            for c in study.choices]
    assert [ok for ok, _ in sec.verdicts] == [c.ok for c in study.choices]
    motors = sec.tables[0]
    for row, c in zip(motors.rows, study.choices, strict=True):
        assert row[0] == c.motor.name
        assert float(row[1]) == pytest.approx(c.steady.omega_mean * RPM, rel=5e-4)
        assert float(row[2]) == pytest.approx(c.steady.delta, rel=5e-3)
        assert float(row[5]) == pytest.approx(c.torque_peak, rel=5e-4)
    assert motors.positions == [c.phi_torque_peak for c in study.choices]  # a row shows it
    sizing = sec.tables[1]
    s = study.sizing
    assert [r[1] for r in sizing.rows] == [fmt(s.flywheel), fmt(s.energy_method),
                                           fmt(s.wittenbauer_flywheel)]
    assert float(sizing.rows[0][1]) == pytest.approx(41.8, abs=0.05)   # docs/machine.md


def test_speed_and_torque_diagrams_are_the_steady_states(loom):
    page, study = loom
    sec = _section(page)
    speed = _diagram(sec, "crank speed ω over the turn")
    torque = _diagram(sec, "motor torque at its shaft")
    for k, c in enumerate(study.choices):
        ss = c.steady
        np.testing.assert_allclose(speed.series[k][1][:-1], ss.omega * RPM, rtol=1e-12)
        assert speed.series[k][1][-1] == speed.series[k][1][0]          # closed over the turn
        np.testing.assert_allclose(torque.series[k][1][:-1], ss.torque, rtol=1e-12)
        assert speed.lines[k].y[0] == pytest.approx(ss.omega_mean * RPM, rel=1e-12)
        assert speed.lines[k].colour == k                               # its motor's colour
    np.testing.assert_allclose(speed.positions[:-1], study.choices[0].steady.phi1)
    limits = {ln.name: ln.y[0] for ln in torque.lines}
    first = study.choices[0]
    assert limits[f"{first.motor.name}: breakdown torque {fmt(first.limit)} N·m"] == first.limit


def test_energy_mass_diagram_and_its_tangents_meet_at_the_flywheel(loom):
    page, study = loom
    w = study.sizing.wittenbauer
    em = _diagram(_section(page), "energy-mass diagram (Wittenbauer)")
    np.testing.assert_allclose(em.x[:-1], w["J"], rtol=1e-12)
    scale = np.max(np.abs(w["dE"])) / np.max(np.abs(em.series[0][1]))  # J or kJ shown
    np.testing.assert_allclose(em.series[0][1][:-1] * scale, w["dE"], rtol=1e-12)
    fw = study.sizing.wittenbauer_flywheel
    a, b = em.lines
    assert a.x[0] == b.x[0] == -fw
    assert a.y[0] == pytest.approx(b.y[0], rel=1e-9)                    # they meet at -J_F
    assert em.points[0][1][0] == -fw and em.points[0][2][0] == pytest.approx(a.y[0])
    magnified = _diagram(_section(page), "energy-mass diagram: the curve")
    assert magnified.lines[0].x[0] > np.min(w["J"]) - 0.2 * np.ptp(w["J"])


def test_the_drawing_runs_at_each_motors_real_speed(loom):
    page, study = loom
    scene = page.scene
    assert len(scene.timings) == len(study.choices)
    for tm, c in zip(scene.timings, study.choices, strict=True):
        ss = c.steady
        assert c.motor.name in tm.label and tm.span == ss.period
        phi = np.append(ss.phi1, ss.phi1[0] + 2 * np.pi)
        inv = 1 / np.append(ss.omega, ss.omega[0])
        t_ref = np.concatenate([[0.0], np.cumsum(np.diff(phi) * 0.5 * (inv[1:] + inv[:-1]))])
        rel = np.mod(scene.positions - phi[0], 2 * np.pi)
        expected = np.interp(rel, phi - phi[0], t_ref)
        expected = np.mod(expected - expected[0], ss.period)
        frames = scene.frames(720)
        assert np.max(np.abs(tm.t[frames] - expected[frames])) < 2e-5 * ss.period
        assert np.all(np.diff(tm.t[frames]) > 0)
        on_node = np.isclose(rel[:, None], phi[None, :-1] - phi[0], atol=1e-12, rtol=0)
        i, j = np.nonzero(on_node)
        assert i.size > 300
        np.testing.assert_allclose(tm.speed[i], ss.omega[j], rtol=1e-12)


def test_sine_press_schedule_marks_its_switches():
    path = EXAMPLES / "sine_press.toml"
    doc = io.load(path)
    page = report.build(doc, path=path)
    study = study_dynamics.run(doc)
    sec = _section(page)
    run = study.schedule
    sched = _diagram(sec, "duty schedule with")
    np.testing.assert_allclose(sched.series[0][1], run.omega * RPM, rtol=1e-12)
    assert [m for m in sched.marks] == [(float(t), run.modes[int(k)]) for t, k in
                                        zip(run.switch_t, run.switch_to, strict=True)]
    assert [k for k in ("sine_press", "dynamics")] == [s.key for s in page.sections]
    assert any(t.caption.startswith("press masses") for t in page.inputs)
    assert len(page.scene.timings) == sum(c.steady is not None for c in study.choices)


def test_a_motor_that_cannot_drive_the_machine_is_said_in_its_section(tmp_path):
    """The four-bar with a motor too weak for its mean load: the kinematics and dynamics are
    reported, the machine dynamics section says why it is missing, nothing is timed."""
    text = (EXAMPLES / "fourbar_paper001.toml").read_text() + """
[[load]]
type = "torque"
body = "crank"
mz = "-30 N*m"
[drive]
start_up = false
[drive.gear]
ratio = 5
[[drive.motor]]
name = "small DC"
type = "dc"
stall_torque = "2 N*m"
no_load_speed = "3000 rpm"
"""
    path = tmp_path / "weak.toml"
    path.write_text(text)
    page = report.build(io.load(path), path=path)
    assert not _section(page, "planar").error
    assert "exceeds the motor's stall torque 2 N·m" in _section(page).error
    assert page.scene.timings == ()


def test_no_drive_no_dynamics_section():
    page = report.build(io.load(EXAMPLES / "fourbar_paper001.toml"))
    assert "dynamics" not in [s.key for s in page.sections]
    assert page.scene.timings == ()
