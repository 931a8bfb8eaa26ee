"""Plots of planar-engine results draw what they are given."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from linkwork.planar import kinematics

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_skeleton_draws_each_point_path_once():
    """The skeleton plot of paper 001's four-bar listed 'path coupler.B' and 'path rocker.B',
    one curve drawn twice (B is the joint of both); the knuckle press drew K twice."""
    from linkwork import files
    from linkwork.cli._planar import _distinct_paths
    from linkwork.planar import kinematics

    for example, expected in (("fourbar_paper001.toml", [("crank", "A"), ("coupler", "B")]),
                              ("loom_sixbar.toml", [("crank", "A"), ("rod", "K"),
                                                    ("lower", "R")])):
        doc = files.load(EXAMPLES / example)
        mech = doc.mechanism()
        cands = [(b.name, pt) for b in mech.bodies for pt in list(b.points)[1:2]]
        assert len(cands) > len(expected)
        assert _distinct_paths(kinematics(mech, doc.positions()), cands) == expected


def test_skeleton_plot_draws_guides_and_slots():
    """A press designer reading the skeleton of the sine press must see the ram's guide and
    the inclined slot (only joint points were drawn: the slot was invisible)."""
    from linkwork.files import load
    from linkwork.plot.planar import plot_skeleton
    doc = load(_example("sine_press_planar.toml"))
    kin = kinematics(doc.mechanism(), doc.positions())
    out = plot_skeleton(kin, [0, 30])
    labels = sorted(ln.get_label() for ln in out["guides"])
    assert labels == ["guide", "slot"]
    slot = next(ln for ln in out["guides"] if ln.get_label() == "slot")
    x, y = slot.get_data()
    assert math.degrees(math.atan2(y[1] - y[0], x[1] - x[0])) == pytest.approx(60.0)
    import matplotlib.pyplot as plt
    plt.close("all")


def _example(name):
    from pathlib import Path
    return Path(__file__).resolve().parents[2] / "examples" / name



def test_skeleton_draws_the_path_of_every_named_point():
    """One path per named point that moves, each once (a joint's point named on both of its
    bodies is one path; pivots in the frame have none): paper 001's four-bar with its coupler
    point P, whose coupler curve must be in the plot, and the knuckle press."""
    import matplotlib.pyplot as plt

    from linkwork.files import load
    from linkwork.plot.planar import plot_skeleton

    drawn = {}
    for example, expected in (
            ("fourbar_paper001.toml", ["crank.A", "coupler.B", "coupler.P"]),
            ("loom_sixbar.toml", ["crank.A", "rod.K", "lower.R"])):
        doc = load(EXAMPLES / example)
        kin = kinematics(doc.mechanism(), doc.positions())
        out = plot_skeleton(kin, [0, 90], name=doc.name)
        assert [ln.get_label() for ln in out["paths"]] == [f"path {p}" for p in expected]
        styles = {(ln.get_color(), str(ln.get_linestyle())) for ln in out["paths"]}
        assert len(styles) == len(expected)  # told apart
        assert out["ax"].get_title().startswith(doc.name)
        for ln in out["paths"]:  # the path drawn is the point's over the whole cycle
            body, pt = ln.get_label().removeprefix("path ").split(".")
            pm = kin.point(body, pt)
            np.testing.assert_array_equal(ln.get_xdata(), pm.x * 1e3)
            np.testing.assert_array_equal(ln.get_ydata(), pm.y * 1e3)
            drawn[ln.get_label()] = ln
    # the coupler curve of P is a closed curve of some size, not a line or a dot
    x, y = drawn["path coupler.P"].get_data()
    assert np.ptp(x) > 50.0 and np.ptp(y) > 50.0
    plt.close("all")


def test_cli_figures_titled_legend_outside_any_script(tmp_path, monkeypatch):
    """The four figures of `linkwork analyze` on the knuckle press renamed in Cyrillic: the name
    in every title, angle ticks at multiples of 30 deg over 0..360, the reactions' legend (7
    joints) outside the axes, no missing-glyph warning when drawn (warnings are errors)."""
    import matplotlib.pyplot as plt

    import linkwork.plot
    from linkwork.cli._planar import _plots
    from linkwork.files import load
    from linkwork.studies import planar as study_planar

    name = "Пресс КГШП φ"
    text = (EXAMPLES / "loom_sixbar.toml").read_text(encoding="utf-8")
    text = text.replace('name = "Knuckle-joint press drive (six-bar)"', f'name = "{name}"')
    src = tmp_path / "press.toml"
    src.write_text(text, encoding="utf-8")
    study = study_planar.analyze(load(src))
    made = []

    def keep(fig, path, dpi=120):
        fig.canvas.draw()
        made.append(fig)
        return path

    monkeypatch.setattr(linkwork.plot, "save", keep)
    _plots(study, tmp_path)
    assert len(made) == 4
    for fig in made:
        titles = [fig.get_suptitle()] + [a.get_title() for a in fig.axes]
        assert any(name in t for t in titles)
        for ax in fig.axes:
            assert any(g.get_visible() for g in ax.get_xgridlines())
    for fig in made[1:]:
        ax = fig.axes[-1]
        assert ax.get_xlim() == pytest.approx((0.0, 360.0))
        ticks = [t for t in ax.get_xticks() if 0 <= t <= 360]
        assert ticks == pytest.approx(np.arange(0.0, 361.0, 30.0))
    reactions = made[2].axes[0]
    leg = reactions.get_legend()
    assert len(leg.get_texts()) == 7
    r = made[2].canvas.get_renderer()
    assert not leg.get_window_extent(r).overlaps(reactions.get_window_extent(r))
    plt.close("all")


def test_loads_plot_draws_each_load_in_its_unit():
    """plot_loads: the forces (a spring's tension, a slide force) on one axes in kN when large,
    a couple on a second; every curve is the load's value; no load to draw is refused."""
    from linkwork.errors import ParameterError
    from linkwork.planar import (
        BodyTorque,
        LoadDiagram,
        SlideForce,
        Spring,
        crank_slider_mechanism,
        inverse_dynamics,
    )
    from linkwork.plot.planar import plot_loads

    mech = crank_slider_mechanism(0.05, 0.2, masses=(1.0, 1.0, 1.0))
    kin = kinematics(mech, np.radians(np.arange(0.0, 360.0, 5.0)))
    dyn = inverse_dynamics(kin, loads=[
        Spring("frame", (0.0, 0.2), "slider", "B", stiffness=1e5, free_length=0.2),
        SlideForce("G", 2e4, name="press"),
        BodyTorque("crank", LoadDiagram([0.0, math.pi], [1.0, 2.0]))])
    out = plot_loads(dyn, name="test")
    top, bottom = out["axes"]
    assert top.get_ylabel() == "force [kN]" and bottom.get_ylabel() == "couple [N·m]"
    spring, press, couple = out["lines"]
    np.testing.assert_allclose(spring.get_ydata(), dyn.loads[0].value / 1e3)
    np.testing.assert_allclose(press.get_ydata(), 20.0)
    np.testing.assert_allclose(couple.get_ydata(), dyn.loads[2].value)
    assert press.get_label() == "press (slide)"
    with pytest.raises(ParameterError, match=r"^names = \['x'\] .*no load to draw"):
        plot_loads(dyn, ["x"])
