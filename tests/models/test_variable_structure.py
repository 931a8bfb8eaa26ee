"""The variable-structure mechanism (paper 000) as one object, and its duty schedule."""

from __future__ import annotations

import math

import numpy as np
import pytest
from _paper000_geometry import crank_slider_positions, slot_positions
from _paper000_loop_equations import _close, _cs_reference, _sine_reference
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from linkwork.errors import LinkworkError, ParameterError
from linkwork.models import crank_slider, sine
from linkwork.models import crank_slider as cs
from linkwork.models.variable_structure import (
    IDLE,
    WORKING,
    Segment,
    VariableStructureMechanism,
)

A60 = math.radians(60)
W1 = 2 * math.pi * 120 / 60  # 120 rpm


@pytest.fixture
def mech():
    return VariableStructureMechanism(L1=0.05, lambda2=4.0, lambda_e=0.5, alpha=A60,
                                      f_slot=0.1, f_guide=0.1)


def test_state_switch_is_immutable(mech):
    w = mech.switch(WORKING, math.radians(45))
    assert mech.mode == IDLE and mech.alpha == A60
    assert w.mode == WORKING and w.alpha == pytest.approx(math.radians(45))
    assert mech.stroke() == pytest.approx(
        0.05 * (math.sqrt(25 - 0.25) - math.sqrt(9 - 0.25)), rel=1e-14)
    assert w.stroke() == pytest.approx(0.1 / math.sin(math.radians(45)), rel=1e-14)


def test_state_validation(mech):
    with pytest.raises(ParameterError, match="working range"):
        mech.switch(alpha=math.radians(5))
    with pytest.raises(ParameterError, match="mode"):
        mech.switch("sleeping")
    with pytest.raises(ParameterError, match="lambda2"):
        VariableStructureMechanism(0.05, 1.2, 0.5, A60)
    with pytest.raises(ParameterError, match="L1"):
        VariableStructureMechanism(-0.05, 4.0, 0.5, A60)


def test_schedule_5_idle_then_3_working(mech):
    spr = 72
    r = mech.run([("idle", 5), ("working", 3, A60)], W1, samples_per_revolution=spr)
    n_idle, n_work = 5 * spr + 1, 3 * spr + 1
    assert r.t.shape == (n_idle + n_work,)
    # one switch, after 5 revolutions = 2.5 s at 120 rpm
    np.testing.assert_allclose(r.switch_t, [2.5], rtol=1e-14)
    np.testing.assert_array_equal(r.switch_to, [1])
    assert r.switch[n_idle] and r.switch.sum() == 1
    assert r.t[n_idle - 1] == r.t[n_idle]  # the switch instant appears on both sides
    assert r.t[-1] == pytest.approx(4.0)
    # idle samples: slider C of the crank-slider from the independent construction
    for k in range(0, n_idle, 37):
        phi = r.phi1[k]
        assert r.mode[k] == 0
        assert r.s[k] == pytest.approx(crank_slider_positions(phi, 0.05, 4.0, 0.5)["Y_C"],
                                       rel=1e-12)
        assert r.ram_s[k] == 0.0 and r.ram_v[k] == 0.0
    # working samples: the ram, X3 from the independent slot construction
    x0 = slot_positions(0.0, 0.05, A60)["x_P"]
    for k in range(n_idle, r.t.size, 23):
        phi = r.phi1[k]
        assert r.mode[k] == 1
        x3 = x0 - slot_positions(phi, 0.05, A60)["x_P"]
        assert r.s[k] == pytest.approx(x3, abs=1e-14)
        assert r.ram_s[k] == r.s[k]
    # working velocity is d s / d t of the sampled output (central differences)
    tw, sw, vw = r.t[n_idle:], r.s[n_idle:], r.v[n_idle:]
    fd = (sw[2:] - sw[:-2]) / (tw[2:] - tw[:-2])
    np.testing.assert_allclose(vw[1:-1], fd, atol=2e-3 * np.abs(vw).max())
    # the ram's position is continuous at the switch; its velocity jumps by omega1 L1 cot(alpha)
    assert r.ram_s[n_idle - 1] == pytest.approx(r.ram_s[n_idle], abs=1e-16)
    assert r.switch_ram_dv[0] == pytest.approx(W1 * 0.05 / math.tan(A60), rel=1e-12)
    # over 3 working strokes the ram covers 3 double strokes of 2 L1 / sin(alpha)
    assert r.ram_s.max() - r.ram_s.min() == pytest.approx(0.1 / math.sin(A60), rel=1e-3)


def test_schedule_alternating_and_alpha_changes(mech):
    sched = [Segment("working", 1, math.radians(45)), Segment("idle", 2),
             Segment("working", 2, math.radians(120))]
    r = mech.run(sched, W1, samples_per_revolution=36)
    np.testing.assert_array_equal(r.switch_to, [0, 1])
    np.testing.assert_allclose(r.switch_t, [0.5, 1.5])
    np.testing.assert_allclose(r.switch_ram_dv, [-W1 * 0.05 / math.tan(math.radians(45)),
                                                 W1 * 0.05 / math.tan(math.radians(120))])
    assert set(np.round(np.degrees(r.alpha[r.mode == 1]))) == {45.0, 120.0}
    d = r.to_dict()
    assert [s["to"] for s in d["switches"]] == ["idle", "working"]


@pytest.mark.parametrize("bad,match", [
    ([("idle", 0)], "revolutions"), ([("idle", 1.5)], "revolutions"), ([], "schedule"),
    ([("coast", 2)], "mode"), ([("working", 2, math.radians(179))], "working range"),
])
def test_bad_schedules(mech, bad, match):
    with pytest.raises(ParameterError, match=match):
        mech.run(bad, W1)


def test_bad_speed(mech):
    with pytest.raises(ParameterError, match="omega1"):
        mech.run([("idle", 1)], -1.0)


def test_output_link_labels(mech):
    assert mech.output(0.3).link == "slider C: Y_C"
    assert mech.switch(WORKING).output(0.3).link == "ram: X3"


def test_plot_schedule_marks_switches(mech):
    from linkwork.plot import pyplot
    from linkwork.plot.sine import plot_cycle, plot_schedule

    r = mech.run([("idle", 2), ("working", 1, A60), ("idle", 1)], W1, samples_per_revolution=36)
    ax = plot_schedule(r)
    assert len(ax) == 3
    xs = {round(float(line.get_xdata()[0]), 12) for line in ax[0].lines
          if len(line.get_xdata()) == 2 and line.get_xdata()[0] == line.get_xdata()[1]}
    assert xs == {round(t, 12) for t in r.switch_t}
    idle = mech.kinematics(np.linspace(0, 2 * np.pi, 37), W1)
    work = mech.switch(WORKING).kinematics(np.linspace(0, 2 * np.pi, 37), W1)
    ax2 = plot_cycle(idle, work)
    np.testing.assert_allclose(ax2[0].lines[0].get_ydata(), idle.Y_C * 1e3)
    np.testing.assert_allclose(ax2[2].lines[1].get_ydata(), work.a3)
    pyplot().close("all")


@settings(max_examples=25, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(segs=st.lists(st.tuples(st.sampled_from(["idle", "working"]), st.integers(1, 3),
                               st.floats(20, 160)), min_size=1, max_size=5),
       rpm=st.floats(10, 600))
def test_property_schedule_timing_and_ram_continuity(mech, segs, rpm):
    w1 = rpm * math.pi / 30
    sched = [(m, n, math.radians(a) if m == "working" else None) for m, n, a in segs]
    r = mech.run(sched, w1, samples_per_revolution=24)
    turns = np.cumsum([n for _, n, _ in sched])[:-1]
    np.testing.assert_allclose(r.switch_t, turns * 2 * np.pi / w1, rtol=1e-12)
    idx = np.flatnonzero(r.switch)
    assert idx.size == len(sched) - 1
    # the ram's position is continuous through every switch (parked at X3 = 0); round-off
    # tolerances scale with the crank length L1 (position) and L1 omega1 (velocity): atol=1e-15 m
    # failed once with -1.35e-15 m; 1e-13 L1 = 5e-15 m here
    L1 = mech.L1
    np.testing.assert_allclose(r.ram_s[idx], r.ram_s[idx - 1], atol=1e-13 * L1)
    np.testing.assert_allclose(r.switch_ram_dv, r.ram_v[idx] - r.ram_v[idx - 1],
                               atol=1e-13 * L1 * w1)
    assert np.all(r.ram_v[r.mode == 0] == 0.0)
    assert np.all(np.diff(r.t) >= 0)


def test_duty_schedule_against_references():
    """Reference: the loop equations solved by Newton with complex-step rates
    (tests/_paper000_loop_equations.py). Tolerance: rel=1e-12, _close (RTOL = 1e-6 relative,
    floor 1e-9 of the scale)."""
    L1, lam2, lame, w1 = 0.05, 4.0, 0.5, 4 * np.pi
    m = VariableStructureMechanism(L1, lam2, lame, math.radians(60), f_slot=0.12, f_guide=0.1)
    res = m.run([("idle", 5), ("working", 3, math.radians(60))], w1, samples_per_revolution=72)
    T = 2 * np.pi / w1
    assert res.switch_t == pytest.approx([5 * T], rel=1e-12)
    assert list(res.switch_to) == [1]
    assert res.t[-1] == pytest.approx(8 * T, rel=1e-12)
    assert res.switch.sum() == 1
    # sample values at a few instants against the loop-equation references
    for k in (7, 100, 300, 359, 361 + 10, 361 + 130, len(res.t) - 5):
        p = float(res.phi1[k])
        if res.mode[k] == 0:
            ref = _cs_reference(L1, lam2, lame, w1, 0.0, 1, p)
            _close(res.s[k], ref["Y_C"], L1, "s idle")
            _close(res.v[k], ref["V_C"], L1 * w1, "v idle")
            _close(res.a[k], ref["a_C"], L1 * w1 * w1, "a idle")
            assert res.ram_s[k] == 0 and res.ram_v[k] == 0
        else:
            ref = _sine_reference(L1, math.radians(60), w1, 0.0, p)
            for a_, b_ in ((res.s[k], "X3"), (res.ram_s[k], "X3")):
                _close(a_, ref[b_], L1, b_)
            _close(res.v[k], ref["V3"], L1 * w1, "V3")
            _close(res.a[k], ref["a3"], L1 * w1 * w1, "a3")
    # ram velocity jump at engagement: V3(phi1 = 0) = omega1 L1 cot(alpha)
    assert res.switch_ram_dv[0] == pytest.approx(w1 * L1 / math.tan(math.radians(60)),
                                                 rel=1e-12)


@pytest.mark.parametrize("call,words", [
    (lambda: cs.offset_crank_slider(np.linspace(0, 6, 50), 0.05, 1.2, 0.5), ["lambda2", "1.5"]),
    (lambda: cs.offset_crank_slider(0.3, -0.05, 4.0, 0.5), ["L1", "-0.05"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, -4.0, 0.5), ["lambda2", "-4"]),
    (lambda: cs.offset_crank_slider(np.nan, 0.05, 4.0, 0.5), ["phi1", "nan"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, np.nan, 0.5), ["lambda2", "nan"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, 4.0, np.inf), ["lambda_e", "inf"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, 4.0, 0.5, omega1=np.nan), ["omega1", "nan"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, 4.0, 0.5, branch=0), ["branch", "0"]),
    (lambda: cs.stroke(0.05, 1.4, 0.5), ["lambda2", "1.4", "1.5"]),
    (lambda: cs.dead_centres(1.4, 0.5), ["lambda2", "1.4", "1.5"]),
    (lambda: cs.max_pressure_angle(1.4, 0.5), ["lambda2", "1.4", "1.5"]),
    (lambda: sine.inclined_slot(0.3, 0.05, 0.0), ["alpha", "0"]),
    (lambda: sine.inclined_slot(0.3, 0.05, np.pi), ["alpha", "180"]),
    (lambda: sine.inclined_slot(0.3, 0.05, np.nan), ["alpha", "nan"]),
    (lambda: sine.inclined_slot(0.3, 0.0, 1.0), ["L1", "0"]),
    (lambda: sine.stroke(-1.0, 1.0), ["L1", "-1"]),
    (lambda: sine.alpha_for_stroke(0.05, 0.09), ["H", "0.09", "0.1"]),
    (lambda: sine.alpha_for_stroke(0.05, np.nan), ["H", "nan"]),
    (lambda: sine.alpha_for_stroke(0.05, -0.2), ["H", "-0.2"]),
    (lambda: sine.working_range(-0.1, 0.1), ["f_slot", "-0.1"]),
    (lambda: sine.working_range(np.nan, 0.1), ["f_slot", "nan"]),
    (lambda: sine.working_range(1.5, 1.0), ["f_slot", "1.5"]),
    (lambda: sine.check_alpha(math.radians(5), 0.12, 0.1), ["alpha", "5", "12.55", "167.4"]),
    (lambda: VariableStructureMechanism(0.05, 1.2, 0.5, 1.0), ["lambda2", "1.2", "1.5"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, math.radians(5), f_slot=0.12,
                                        f_guide=0.1), ["alpha", "5"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0).run([("idle", 0)], 1.0),
     ["revolutions", "0"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0).run([("boring", 1)], 1.0),
     ["mode", "boring"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0).run([("idle", 1)], np.nan),
     ["omega1", "nan"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0).run([("idle", 1)], -3.0),
     ["omega1", "-3"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0, f_slot=0.12, f_guide=0.1).run(
        [("working", 1, math.radians(5))], 1.0), ["alpha", "5"]),
])
def test_impossible_parameters_give_clear_errors(call, words):
    with pytest.raises(LinkworkError) as ei:
        call()
    msg = str(ei.value).lower()
    for w in words:
        assert w.lower() in msg, (w, msg)
    assert isinstance(ei.value, ValueError)


def test_branch_array_is_named():
    from linkwork.models.variable_structure import VariableStructureMechanism
    with pytest.raises(ParameterError, match="branch"):
        crank_slider.offset_crank_slider(0.3, 0.05, 4.0, 0.5, branch=np.array([1, -1]))
    with pytest.raises(ParameterError, match="branch"):
        crank_slider.dead_centres(4.0, 0.5, branch=np.array([1, -1]))
    with pytest.raises(ParameterError, match="branch"):
        VariableStructureMechanism(0.05, 4.0, 0.5, 1.0, branch=np.array([1, -1]))
    # a scalar branch still works, as a numpy integer too
    res = crank_slider.offset_crank_slider(0.3, 0.05, 4.0, 0.5, branch=np.int64(-1))
    assert float(res.Y_C) < 0


@pytest.mark.parametrize("schedule,spr,needle", [
    ([("idle", 1)], 10.5, "samples_per_revolution"),
    ([("idle", 1)], "360", "samples_per_revolution"),
    ([("idle",)], 36, "schedule entry"),
    (["idle"], 36, "schedule entry"),
    ([("working", 1, 1.0, 2)], 36, "schedule entry"),
])
def test_run_malformed_schedule_is_named(schedule, spr, needle):
    from linkwork.models.variable_structure import VariableStructureMechanism
    mech = VariableStructureMechanism(0.05, 4.0, 0.5, 1.0)
    with pytest.raises(ParameterError, match=needle):  # were TypeErrors from Python internals
        mech.run(schedule, 10.0, samples_per_revolution=spr)
