"""The self-contained HTML pieces (linkwork.plot.html): what the viewer receives is the
drawing's geometry to within its quantum, diagrams map to frames both ways, user text is
escaped, and nothing refers to the network.

References: the scene's own shapes (built from the engine, tested in test_scene.py); the
quantum is 1e-5 of the drawing's extent, so a decoded coordinate is within half of it.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from linkwork import io
from linkwork.plot import html as ph
from linkwork.plot import scene as sc
from linkwork.studies import planar as study_planar

ROOT = Path(__file__).resolve().parents[2]


def _scene() -> sc.Scene:
    doc = io.load(ROOT / "examples" / "fourbar_paper001.toml")
    return sc.planar_scene(study_planar.analyze(doc).kinematics, centres=True)


def _data(html: str, prefix: str = "lw") -> dict:
    m = re.search(rf'<script type="application/json" id="{prefix}-data">(.*?)</script>', html,
                  re.S)
    assert m is not None
    return json.loads(m.group(1))


def test_scene_data_decodes_to_the_drawn_geometry_within_the_quantum():
    scene = _scene()
    data = ph.scene_data(scene)
    q = data["q"]
    x0, y0, x1, y1 = scene.bounds()
    assert q <= 1e-5 * max(x1 - x0, y1 - y0) * 1e3   # [mm]
    frames = data["frames"]
    for entry in data["shapes"]:
        i = int(entry["id"].rsplit("-s", 1)[1])
        shape = scene.shapes[i]
        d = np.array([np.nan if v is None else v for v in entry["d"]], dtype=float)
        xy = d.reshape(len(frames), entry["k"], 2) * q                   # mm, y down
        ref = np.moveaxis(shape.xy[:, :, frames], -1, 0) * 1e3
        ref[..., 1] *= -1
        both = np.isfinite(ref)
        assert np.array_equal(np.isfinite(xy), both)
        assert np.max(np.abs(xy[both] - ref[both])) <= 0.5 * q * (1 + 1e-9)


def test_diagram_maps_frames_to_samples_across_the_end_of_a_turn():
    scene = _scene()                                   # frames 0..359 deg, periodic
    pos = np.radians(np.arange(0.3, 360.0, 10.0))      # a coarser diagram, 0.3..350.3 deg
    d = ph.Diagram("t", np.degrees(pos), [("y", np.sin(pos))], "φ1 [deg]", "y", positions=pos)
    _, data = ph.diagram_svg(d, scene, ident="c0")
    f2s = np.array(data["f2s"])
    frames_deg = np.degrees(scene.positions[scene.frames(ph.MAX_FRAMES)])
    expect = np.floor((frames_deg - 0.3) / 10.0 + 0.5).astype(int) % 36  # 356 -> 0.3 (wrap)
    assert np.array_equal(f2s, expect)
    s2f = np.array(data["s2f"])
    np.testing.assert_allclose(frames_deg[s2f], np.round(np.degrees(pos)), atol=1e-9)


def test_diagram_outside_the_scenes_range_has_no_cursor():
    scene = _scene()
    pos = np.radians(np.linspace(400.0, 500.0, 11))    # no frame near (not periodic: linear)
    lin = sc.Scene("s", scene.positions, "s1", "m", scene.valid, scene.shapes)
    d = ph.Diagram("t", pos, [("y", pos)], "x", "y", positions=pos)
    _, data = ph.diagram_svg(d, lin, ident="c0")
    assert max(data["f2s"]) == -1


def test_user_text_is_escaped_and_the_page_refers_to_no_network():
    scene = _scene()
    evil = '</script><script>alert("x")</script> & <b>'
    page = ph.Page(title=evil, subtitle=evil, scene=scene,
                   sections=[ph.Section(evil, "k", intro=[evil],
                                        tables=[ph.Table(evil, [evil], [[evil]])])],
                   source=evil, notes=[(evil, evil)], warnings=[evil])
    html = ph.page_html(page)
    assert 'alert("x")' not in html.replace('alert(&quot;x&quot;)', "")
    assert html.count("<script") == 2            # the data and the viewer, nothing injected
    for url in re.findall(r'(?:src|href)\s*=\s*"([^"#][^"]*)"', html):
        raise AssertionError(f"external reference {url}")
    assert "http://" not in html.replace('xmlns="http://www.w3.org/2000/svg"', "")
    assert "https://" not in html


def test_view_html_fragments_have_their_own_ids():
    scene = _scene()
    a, b = ph.view_html(scene), ph.view_html(scene)
    ida = re.search(r'class="lw-root lw-view" id="([^"]+)"', a)
    idb = re.search(r'class="lw-root lw-view" id="([^"]+)"', b)
    assert ida and idb and ida.group(1) != idb.group(1)
    assert _data(a, ida.group(1))["scene"]["n"] == 360


def test_ticks_of_angles_and_of_plain_numbers():
    assert ph._ticks(0.0, 360.0, angle=True) == [0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0,
                                                 315.0, 360.0]
    t = ph._ticks(-3.7, 12.2)
    assert t[0] >= -3.7 and t[-1] <= 12.2 and len(t) <= 9
    steps = np.diff(t)
    assert np.allclose(steps, steps[0])
    mantissa = steps[0] / 10.0 ** math.floor(math.log10(steps[0]))
    assert any(math.isclose(mantissa, m) for m in (1.0, 2.0, 2.5, 5.0))


def test_tick_labels_tell_every_tick_apart():
    """Ticks 0.025 apart are written with three decimals (0.175, not 0.18 beside 0.2)."""
    t = ph._ticks(0.07, 0.235)
    labels = [ph._tick_text(v, t) for v in t]
    assert len(set(labels)) == len(labels)
    assert [float(x) for x in labels] == pytest.approx(t, abs=1e-12)
