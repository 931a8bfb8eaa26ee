"""Every result family's ``.plot()`` returns one :class:`linkwork.plot.Figure` that draws the
result's own numbers.

For each family: the handle type, the number of data axes its docstring promises, artists on
every axes, and one curve (or bar) compared with the result's arrays (exact: the figure draws the
arrays themselves, scaled by a display unit factor). matplotlib runs headless (Agg); every figure
is closed.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator
from typing import Any

os.environ.setdefault("MPLBACKEND", "Agg")

import numpy as np
import pytest

from linkwork.balancing import compare_balancing, shaking_loads
from linkwork.balancing.mechanism import force_balance
from linkwork.balancing.optimal import optimal_balance, pareto_set
from linkwork.balancing.partial import counterweight_axis_offset
from linkwork.balancing.static import Counterweight
from linkwork.cycles import harmonics
from linkwork.models import crank_slider, sine
from linkwork.models import swashplate as sw
from linkwork.models.fourbar import fourbar as fourbar_closed_form
from linkwork.models.fourbar import fourbar_kinetostatics
from linkwork.models.variable_structure import WORKING, VariableStructureMechanism
from linkwork.planar.dynamics import inverse_dynamics
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import fourbar_mechanism
from linkwork.plot import Figure, pyplot
from linkwork.redundancy import (
    Tolerance,
    body_wrenches,
    geometry,
    spatial_model,
    spatial_reactions,
    tolerance_study,
)
from linkwork.results import Result
from linkwork.synthesis import swashplate as syn

PHI = np.linspace(0.0, 2 * np.pi, 72, endpoint=False)
PAPER = dict(masses=(1.0, 3.0, 2.0), inertias=(1.0 * 0.1**2 / 12, 0.0225, 0.00567),
             coms=(0.05, 0.15, 0.1), omega1=10.0)


@pytest.fixture(autouse=True)
def _close_figures() -> Iterator[None]:
    yield
    pyplot().close("all")


@pytest.fixture(scope="module")
def mech() -> Any:
    return fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER)


def _check(fig: Any, n_axes: int) -> Figure:
    """The one handle type, ``n_axes`` data axes on one figure, something drawn on each, and
    what a designer prints (:func:`_printable`)."""
    assert isinstance(fig, Figure)
    assert len(fig) == len(fig.axes) == n_axes
    for ax in fig.axes:
        assert ax.figure is fig.figure
        assert ax.lines or ax.patches or ax.collections
    _printable(fig)
    return fig


def _title(fig: Any) -> str:
    sup = fig.figure.get_suptitle()
    return sup or " / ".join(ax.get_title() for ax in fig.axes if ax.get_title())


def _printable(fig: Figure) -> None:
    """A title (the figure's or every axes'); angle axes over a turn ticked at multiples of 30
    deg (90 over wider ranges) and limited to the range drawn; a grid; legends of more than 3
    entries outside the axes (their boxes do not meet once drawn)."""
    assert _title(fig), "figure without a title"
    if not fig.figure.get_suptitle():
        assert all(ax.get_title() for ax in fig.axes), "an axes without a title"
    fig.figure.canvas.draw()
    renderer = fig.figure.canvas.get_renderer()
    for ax in fig.axes:
        label = ax.get_xlabel() or next((a.get_xlabel() for a in fig.axes if a.get_xlabel() and
                                         a.get_shared_x_axes().joined(a, ax)), "")
        lo, hi = ax.get_xlim()
        if "[deg]" in label and "angle" in label and hi - lo >= 300:
            ticks = [t for t in ax.get_xticks() if lo - 1e-9 <= t <= hi + 1e-9]
            step = 30.0 if hi - lo <= 400 else 90.0
            assert all(abs(t / step - round(t / step)) < 1e-9 for t in ticks), (label, ticks)
            drawn = np.concatenate([np.asarray(ln.get_xdata(), float) for ln in ax.lines
                                    if np.size(ln.get_xdata()) > 2])
            assert lo == pytest.approx(drawn.min(), abs=1e-9)
            assert drawn.max() <= hi + 1e-9 and hi - drawn.max() <= 10.0
        assert any(g.get_visible() for g in ax.get_xgridlines() + ax.get_ygridlines()), \
            "no grid"
        leg = ax.get_legend()
        if leg is not None and len(leg.get_texts()) > 3:
            box, frame = leg.get_window_extent(renderer), ax.get_window_extent(renderer)
            assert not box.overlaps(frame), f"legend of {len(leg.get_texts())} entries inside"


# --- closed forms ----------------------------------------------------------------------------

def test_fourbar_result_and_forces() -> None:
    theta = np.linspace(0.0, 2 * np.pi, 91)
    r = fourbar_closed_form(theta, 0.1, 0.3, 0.2, 0.3, 10.0, coupler_point=(0.15, 0.05))
    fig = _check(r.plot(), 1)
    np.testing.assert_array_equal(fig.get_lines()[-1].get_ydata(), r.yP)
    f = fourbar_kinetostatics(theta, 0.1, 0.3, 0.2, 0.3, 10.0, mass=(1.0, 3.0, 2.0))
    fig = _check(f.plot(), 2)
    np.testing.assert_array_equal(fig[1].get_lines()[0].get_ydata(), f.Q)


def test_crank_slider_inclined_slot_and_schedule() -> None:
    cs = crank_slider.offset_crank_slider(PHI, 0.05, 4.0, 0.5, 12.0)
    fig = _check(cs.plot(), 3)
    np.testing.assert_allclose(fig[0].lines[0].get_ydata(), cs.Y_C * 1e3, rtol=1e-15)
    sn = sine.inclined_slot(PHI, 0.05, math.radians(60), 12.0)
    fig = _check(sn.plot(), 3)
    np.testing.assert_allclose(fig[2].lines[0].get_ydata(), sn.a3, rtol=1e-15)
    vs = VariableStructureMechanism(L1=0.05, lambda2=4.0, lambda_e=0.5, alpha=math.radians(60),
                                    f_slot=0.1, f_guide=0.1)
    sched = vs.run([("idle", 1), (WORKING, 1, math.radians(60))], 12.0,
                   samples_per_revolution=36)
    fig = _check(sched.plot(), 3)
    assert any(np.array_equal(ln.get_xdata(), sched.t) for ln in fig[0].lines)


def test_swashplate_kinematics_characteristics_forces() -> None:
    d = sw.scheme_1(0.1, 0.09, 0.2, math.radians(20), 0.02, -0.01)
    res = sw.analyze(d, n=91)
    fig = _check(res.plot(), 3)
    np.testing.assert_allclose(fig[0].lines[0].get_ydata(), res.s * 1e3, rtol=1e-15)
    c = res.characteristics
    fig = _check(c.plot(), 1)
    assert fig.artists["bars"][0].get_height() == pytest.approx(float(c.H) * 1e3, rel=1e-15)
    f = sw.drive_forces(sw.scheme_4a(0.1, 0.2, math.radians(15)), 1000.0, u=4, n=73)
    fig = _check(f.plot(), 2)
    np.testing.assert_allclose(fig[1].lines[1].get_ydata(), f.M_total, rtol=1e-15)


def test_synthesis_and_feasible_region() -> None:
    d = sw.scheme_4a(0.1, 0.2, math.radians(15))
    req = syn.Request(scheme="4a", R=0.1, H=float(d.stroke()), H_tol=1e-3,
                      delta_f=math.radians(2), delta_r=math.radians(2))
    reg = syn.feasible_region(req, d, "alpha", "l", n=12)
    fig = _check(reg.plot(best=d), 1)
    star = next(ln for ln in fig.get_lines() if ln.get_marker() == "*")
    assert star.get_xdata()[0] == pytest.approx(15.0, abs=1e-12)
    res = syn.synthesize(req, n_candidates=256, n_refine=1)
    fig = _check(res.plot(n=8), 1)
    star = next(ln for ln in fig.get_lines() if ln.get_marker() == "*")
    rel = res.best.relative()
    free = list(req.free)
    scale = 180 / math.pi if free[0] == "alpha" else 1.0
    assert star.get_xdata()[0] == pytest.approx(rel[free[0]] * scale, rel=1e-12)


# --- planar engine ---------------------------------------------------------------------------

def test_kinematics_point_motion_dynamics(mech: Any) -> None:
    k = kinematics(mech, PHI)
    fig = _check(k.plot(), 3)
    i = k.bodies.index("rocker")
    line = next(ln for ln in fig[1].lines if ln.get_label() == "rocker")
    np.testing.assert_array_equal(line.get_ydata(), k.omega[i])
    pm = k.point("coupler", "B")
    fig = _check(pm.plot(), 3)
    np.testing.assert_array_equal(fig[2].lines[1].get_ydata(), pm.ay)
    dyn = inverse_dynamics(k)
    fig = _check(dyn.plot(), 2)
    np.testing.assert_allclose(fig.artists["torque"]["line"].get_ydata(), dyn.Q, rtol=1e-15)
    # the mean line is the work per cycle over the range (trapezoid over the driver positions)
    mean = fig[0].lines[1].get_ydata()[0]
    assert mean == pytest.approx(np.trapezoid(dyn.Q, PHI) / (PHI[-1] - PHI[0]), rel=1e-12)


# --- balancing ---------------------------------------------------------------------------------

def test_shaking_loads_and_force_balance(mech: Any) -> None:
    sl = shaking_loads(kinematics(mech, PHI))
    fig = _check(sl.plot(), 2)
    np.testing.assert_array_equal(fig[1].lines[0].get_ydata(), sl.moment)
    fb = force_balance(mech, n=72)
    fig = _check(fb.plot(), 1)
    heights = [b.get_height() for b in fig.artists["bars"]]
    assert heights == [fb.force_rms_before, fb.force_rms_after]


def test_counterweight_and_axis_offset() -> None:
    cw = Counterweight("crank", 0.2, math.pi, radius=0.05)
    fig = _check(cw.plot(), 1)
    x, y = fig.get_lines()[0].get_data()
    assert x[1] == pytest.approx(-0.2, rel=1e-15) and abs(y[1]) < 1e-15
    moment = 3.0 * np.sin(PHI) + np.cos(2 * PHI)
    ao = counterweight_axis_offset(PHI, moment, 0.2, 10.0)
    fig = _check(ao.plot(), 1)
    np.testing.assert_array_equal(fig[0].lines[1].get_ydata(), ao.residual)


def test_comparison_harmonics(mech: Any) -> None:
    comp = compare_balancing(mech, n=72)
    fig = _check(comp.plot(), 1)
    bars = fig.artists["bars"]["ΔM1 static"]
    np.testing.assert_array_equal([b.get_height() for b in bars], comp.dM1)
    fig = _check(comp.cycle.plot(), 3)
    np.testing.assert_array_equal(fig[2].lines[1].get_ydata(), comp.cycle.Q1)
    h = harmonics(PHI, 2.0 + 3.0 * np.cos(2 * PHI), 4)
    fig = _check(h.plot(), 1)
    assert [b.get_height() for b in fig.artists["bars"]] == pytest.approx([0, 3, 0, 0],
                                                                          abs=1e-12)


def test_optimal_balance_and_pareto(mech: Any) -> None:
    ob = optimal_balance(mech, (1, 0, 0), n=36, starts=1)
    fig = _check(ob.plot(), 1)
    assert fig.artists["bars"][0].get_height() == ob.force_rms
    ps = pareto_set(mech, np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]), n=36, starts=1)
    fig = _check(ps.plot(), 1)
    np.testing.assert_array_equal(fig.artists["pareto"].get_offsets()[:, 0],
                                  ps.force_rms[~ps.dominated])


# --- redundancy --------------------------------------------------------------------------------

def test_spatial_reactions_and_tolerance_study(mech: Any) -> None:
    joints = [j.name for j in mech.joints]
    r = spatial_reactions(mech, PHI, gravity=(0, -9.81), default={"e": 0.03, "z": 0.01})
    fig = _check(r.plot(), 4)
    np.testing.assert_array_equal(fig[3].lines[0].get_ydata(), r.Q)
    k = kinematics(mech, PHI)
    model = spatial_model(mech, default={"e": 0.03, "z": 0.01})
    w = body_wrenches(mech, k, gravity=(0, -9.81))
    st = tolerance_study(model, geometry(mech, k), w, [Tolerance(joints[2], "a", "tx", 1e-4)],
                         30)
    fig = _check(st.plot(bins=5), len(st.joints))
    assert int(fig.artists["histograms"][st.joints[0]]["hist"][0].sum()) == 30


def test_every_result_class_overrides_plot() -> None:
    """No result family is left with the base class's NotImplementedError."""
    def subclasses(c: type) -> set[type]:
        out = set(c.__subclasses__())
        return out.union(*(subclasses(s) for s in out)) if out else out
    missing = [c.__qualname__ for c in subclasses(Result) if c.plot is Result.plot]
    assert missing == []


# --- what a designer prints ----------------------------------------------------------------

NAMES = ("Пресс КГШП φ", "压力机 (press)", "Four-bar ÆØÅ ß")


@pytest.mark.parametrize("name", NAMES)
def test_names_in_any_script_titled_without_missing_glyphs(mech: Any, name: str) -> None:
    """A name in Cyrillic (with φ) is shown as written; letters the font lacks (CJK under
    DejaVu Sans) become "?" instead of the 'Glyph ... missing' warning (an error here)."""
    k = kinematics(mech, PHI)
    dyn = inverse_dynamics(k)
    for fig in (k.plot(name=name), dyn.plot(name=name),
                shaking_loads(k).plot(name=name)):
        fig.figure.canvas.draw()  # glyphs are looked up when drawing: warnings are errors
        title = _title(fig)
        if name.startswith("压"):
            assert "??? (press)" in title
        else:
            assert name in title


def test_coincident_curves_get_their_own_style(mech: Any) -> None:
    """The coupler is a two-force member in space: |fz| at A and B are one curve; each must
    stay visible (another dash pattern and markers)."""
    r = spatial_reactions(mech, PHI, gravity=(0, -9.81), default={"e": 0.03, "z": 0.01})
    fig = r.plot()
    lines = {ln.get_label(): ln for ln in fig[0].lines}
    a, b = lines["A"], lines["B"]
    np.testing.assert_allclose(a.get_ydata(), b.get_ydata(), rtol=1e-9, atol=1e-9)
    assert (a.get_linestyle(), a.get_marker()) != (b.get_linestyle(), b.get_marker())
    assert b.get_marker() not in ("None", "", None)


def test_angle_axis_steps() -> None:
    """Ticks at 30 deg up to a turn, 90 deg to three turns; limits at the range; a cycle
    sampled without its end is shown to 360."""
    from linkwork.plot import angle_axis

    plt = pyplot()
    for data, step, lim in ((np.arange(0.0, 360.0, 1.0), 30.0, (0.0, 360.0)),
                            (np.linspace(0.0, 360.0, 361), 30.0, (0.0, 360.0)),
                            (np.linspace(0.0, 720.0, 50), 90.0, (0.0, 720.0)),
                            (np.linspace(-180.0, 180.0, 73), 30.0, (-180.0, 180.0)),
                            (np.linspace(20.0, 200.0, 50), 30.0, (20.0, 200.0))):
        _, ax = plt.subplots()
        ax.plot(data, np.sin(data))
        angle_axis(ax, data)
        assert ax.get_xlim() == pytest.approx(lim)
        ticks = [t for t in ax.get_xticks() if lim[0] <= t <= lim[1]]
        assert all(abs(t / step - round(t / step)) < 1e-9 for t in ticks)
        assert len(ticks) >= 4


def test_a_very_long_mechanism_name_is_cut_in_titles():
    """A 100 000-character name (issue 19: ~100 s per figure in savefig) shows its first
    TITLE_NAME_MAX - 1 characters and an ellipsis; short names are shown whole."""
    from linkwork.plot._base import TITLE_NAME_MAX, titled

    long = "Пресс " + "x" * 100_000
    title = titled(long, "Dynamics", "driving torque")
    assert title == long[:TITLE_NAME_MAX - 1] + "…: driving torque"
    assert titled("Four-bar of paper 001", "Dynamics", "Q") == "Four-bar of paper 001: Q"
    assert titled(None, "Dynamics", "Q") == "Dynamics: Q"
