"""Plots of planar-engine results draw what they are given."""

from __future__ import annotations

import math
from pathlib import Path

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
