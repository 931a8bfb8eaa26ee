"""Every study and result family shows itself: ``_repr_html_`` (a notebook's display: a compact
table and, for a mechanism's motion, the animated drawing) and ``.plot()`` (a Figure).

The drawing's content is checked against the engine in tests/plot/test_scene.py and in a real
browser in tests/report/test_browser.py; here: that each family gives one, with the right
number of frames, and that the summary's numbers are the result's.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from linkwork import io
from linkwork.models import crank_slider, sine
from linkwork.plot import Figure, pyplot
from linkwork.results import Result
from linkwork.studies import balance, reactions, sine_press, swashplate
from linkwork.studies import planar as study_planar

ROOT = Path(__file__).resolve().parents[2]
EX = ROOT / "examples"


def _view(html: str) -> dict:
    prefix = re.search(r'class="lw-root lw-view" id="([^"]+)"', html).group(1)
    m = re.search(rf'<script type="application/json" id="{prefix}-data">(.*?)</script>', html,
                  re.S)
    return json.loads(m.group(1))


def _studies():
    fourbar = io.load(EX / "fourbar_paper001.toml")
    spatial = io.load(EX / "loom_fourbar_spatial.toml")
    return {
        "planar": (study_planar.analyze(fourbar), 360),
        "balance": (balance.run(io.load(ROOT / "tests" / "data" / "balance_fourbar.toml")),
                    None),
        "reactions": (reactions.run(spatial), 360),
        "sine_press": (sine_press.analyze(io.load(EX / "sine_press.toml")), 360),
        "swashplate": (swashplate.analyze(io.load(EX / "swashplate_4a.toml")), 360),
    }


@pytest.fixture(scope="module")
def studies():
    return _studies()


@pytest.mark.parametrize("kind", ["planar", "balance", "reactions", "sine_press", "swashplate"])
def test_every_study_displays_itself_and_plots(studies, kind):
    study, frames = studies[kind]
    html = study._repr_html_()
    data = _view(html)
    if frames is None:
        assert data["scene"] is None
    else:
        assert data["scene"]["n"] == frames
    assert "<table" in html
    fig = study.plot()
    try:
        assert isinstance(fig, Figure) and len(fig) >= 1
    finally:
        pyplot().close(fig.figure)


def test_planar_study_summary_is_its_peaks(studies):
    study, _ = studies["planar"]
    html = study._repr_html_()
    for pk in study.peaks:
        assert f"<td>{pk['name']}</td>" in html


def _results(studies) -> list[Result]:
    st = studies["planar"][0]
    phi = np.radians(np.arange(0.0, 361.0))
    return [st.kinematics, st.dynamics, st.kinematics.point("coupler", "P"),
            crank_slider.offset_crank_slider(phi, 0.05, 4.0, 0.5, 10.0),
            sine.inclined_slot(phi, 0.05, np.radians(60.0), 10.0),
            studies["swashplate"][0].cycle, studies["reactions"][0].reactions,
            studies["balance"][0].comparison, studies["balance"][0].comparison.cycle]


def test_results_display_a_table_and_motion_results_their_mechanism(studies):
    animated = {"Kinematics", "Dynamics", "CrankSliderResult", "InclinedSlotResult",
                "KinematicsResult"}
    for res in _results(studies):
        html = res._repr_html_()
        data = _view(html)
        assert (data["scene"] is not None) == (type(res).__name__ in animated), type(res)
        assert "<table" in html


def test_result_table_shows_the_ranges_of_the_arrays(studies):
    res = crank_slider.offset_crank_slider(np.radians(np.arange(0.0, 360.0)), 0.05, 4.0, 0.5,
                                           10.0)
    html = res._repr_html_()
    row = re.search(r"<td>Y_C</td><td>([^<]+)</td><td>m</td>", html)
    lo, hi = (float(v) for v in row.group(1).split(" .. "))
    assert lo == pytest.approx(res.Y_C.min(), rel=1e-3)
    assert hi == pytest.approx(res.Y_C.max(), rel=1e-3)


def test_several_designs_display_without_a_drawing():
    phi = np.radians(np.arange(0.0, 360.0, 10.0))
    res = crank_slider.offset_crank_slider(phi, np.array([[0.05], [0.06]]), 4.0, 0.5, 10.0)
    assert _view(res._repr_html_())["scene"] is None
