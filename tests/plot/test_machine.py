"""Figures of machine dynamics (linkwork.plot.machine): what each draws, from small runs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork import io
from linkwork.machine import DCMotor, Mode, flywheel_for, run_schedule, steady_state
from linkwork.plot import Figure, pyplot
from linkwork.plot.machine import plot_speed, plot_torque

G = (0.0, -9.81)


@pytest.fixture(scope="module")
def fourbar():
    return io.load("examples/fourbar_paper001.toml").mechanism()


def test_steady_state_figure_speed_and_torque(fourbar):
    ss = steady_state(fourbar, DCMotor(20.0, 12.0, inertia=0.01, name="DC"), gravity=G)
    fig = ss.plot()
    assert isinstance(fig, Figure) and len(fig) == 2
    line = fig[0].get_lines()[0]
    assert line.get_label().startswith("DC: mean ") and "δ = " in line.get_label()
    x, y = line.get_data()
    assert x[0] == 0.0 and x[-1] == pytest.approx(360.0)            # closed over the turn
    np.testing.assert_allclose(y[:-1], ss.omega * 30 / math.pi)
    limits = [ln for ln in fig[1].get_lines() if "limit" in str(ln.get_label())]
    assert limits and limits[0].get_ydata()[0] == pytest.approx(20.0)
    fig.close()


def test_several_motors_on_one_axes(fourbar):
    runs = [steady_state(fourbar, DCMotor(s, 12.0, inertia=0.01, name=f"{s:g} N m"),
                         gravity=G, dynamics=False) for s in (15.0, 30.0)]
    plt = pyplot()
    fig, ax = plt.subplots()
    drawn = plot_speed(runs, ax=ax)
    assert len(drawn["lines"]) == 2
    drawn = plot_torque(runs, ax=ax)
    assert len(drawn["lines"]) == 2
    plt.close(fig)


def test_energy_mass_diagram_with_magnified_inset():
    doc = io.load("examples/loom_sixbar.toml")
    d = doc.drive
    fs = flywheel_for(doc.mechanism(), d.motors()[0], 0.1, gear=d.build_gear(),
                      loads=doc.loads, gravity=doc.analysis.gravity,
                      breaks=np.radians([145.0, 184.7]))
    fig = fs.plot()
    ax = fig[0]
    assert len(ax.child_axes) == 1                      # the curve is a sliver: an inset
    assert "energy-mass diagram" in ax.get_title()
    fig.close()


def test_transient_figure_marks_the_switches(fourbar):
    modes = [Mode("a", fourbar, (), G), Mode("b", fourbar, (), (0.0, -19.62))]
    run = run_schedule(modes, [("a", 1), ("b", 1), ("a", 1)], DCMotor(20.0, 12.0, inertia=0.01),
                       flywheel=0.05)
    fig = run.plot()
    marks = [ln for ln in fig[0].get_lines() if ln.get_linestyle() == "--"]
    assert len(marks) == 2
    assert [t.get_text() for t in fig[0].texts] == ["b", "a"]
    fig.close()
