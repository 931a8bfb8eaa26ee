"""The reports in a real browser: headless Chromium (Debian's package, /usr/bin/chromium)
driven by Playwright, offline.

For the report of every bundled example (and of a mechanism that assembles over part of its
cycle): no console error or warning and no page error, no request but the file itself (the
context is offline and every other request is recorded), the animation advances (the frame and
the drawn pose change while it plays), the drawn pose read from the DOM at several frames equals
the engine's positions (within the drawing's quantum, 1e-5 of its extent), the slider and the
diagram cursor agree both ways (the slider moved by the keyboard puts the cursor on the
diagram's sample of that frame; a mouse click on a diagram moves the slider to the frame of the
clicked sample), and a screenshot of each report is written to ``test-output/screenshots/``
for review.

Without Chromium (a machine where ``.ci/run`` could not install it) the tests skip and say why.
"""

from __future__ import annotations

import json
import math
import os
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from linkwork import io, report
from linkwork.report.base import Options
from linkwork.studies import planar as study_planar
from linkwork.studies import sine_press, swashplate

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))
PARTIAL = ROOT / "tests" / "data" / "partial" / "fourbar_partial.toml"
SCREENSHOTS = ROOT / "test-output" / "screenshots"
CHROMIUM = os.environ.get("LINKWORK_CHROMIUM", "/usr/bin/chromium")
#: The flags Debian's Chromium needs here (without the background-networking ones it makes
#: refused connections); Playwright adds --headless and a fresh --user-data-dir.
FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def _skip_reason() -> str | None:
    if os.environ.get("LINKWORK_BROWSER_SKIP"):
        return os.environ["LINKWORK_BROWSER_SKIP"]
    if not (Path(CHROMIUM).is_file() or shutil.which(CHROMIUM)):
        return (f"headless Chromium not found at {CHROMIUM} (Debian: apt-get install chromium; "
                ".ci/run installs it)")
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "playwright is not installed (pip install -e '.[test]')"
    return None


pytestmark = pytest.mark.skipif(_skip_reason() is not None, reason=str(_skip_reason()))


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=CHROMIUM, args=FLAGS, headless=True)
        yield b
        b.close()


@pytest.fixture(scope="module")
def pages(tmp_path_factory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("reports")
    made = {}
    for path in [*EXAMPLES, PARTIAL]:
        opts = Options(centres=path.stem == "fourbar_paper001", file=str(path))
        page = report.build(io.load(path), path=path, options=opts)
        made[path.stem] = report.write(page, out / f"{path.stem}.html")
    return made


class Opened:
    """A report open in a fresh offline browser context, with what it logged and asked for."""

    def __init__(self, browser: Any, html: Path) -> None:
        self.context = browser.new_context(offline=True, viewport={"width": 1400, "height": 900})
        self.page = self.context.new_page()
        self.messages: list[tuple[str, str]] = []
        self.requests: list[str] = []
        self.page.on("console", lambda m: self.messages.append((m.type, m.text)))
        self.page.on("pageerror", lambda e: self.messages.append(("pageerror", str(e))))
        self.page.on("request", lambda r: self.requests.append(r.url))
        self.url = html.resolve().as_uri()
        self.page.goto(self.url)
        self.data = json.loads(self.page.text_content("#lw-data"))

    def api(self, call: str) -> Any:
        return self.page.evaluate(f"document.getElementById('lw').linkwork.{call}")

    def circle(self, name: str) -> tuple[float, float]:
        """Centre of the drawn circle called ``name``, in the drawing's mm (y up)."""
        loc = self.page.locator(f'circle[data-name="{name}"]').first
        return float(loc.get_attribute("cx")), -float(loc.get_attribute("cy"))

    def close(self) -> None:
        self.context.close()


@pytest.fixture
def opened(browser, pages, request):
    o = Opened(browser, pages[request.param])
    yield o
    o.close()


def _frames_to_check(o: Opened) -> list[int]:
    valid = np.flatnonzero(np.array(o.data["scene"]["valid"]) == 1)
    return [int(valid[int(k)]) for k in np.linspace(0, valid.size - 1, 5)]


def _engine_points(stem: str) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The engine's (or closed form's) positions of named drawn circles [mm, (2, n)] and the
    positions of the frames [SI], computed here from the studies, not from the report."""
    path = PARTIAL if stem == "fourbar_partial" else ROOT / "examples" / f"{stem}.toml"
    doc = io.load(path)
    if isinstance(doc, io.PlanarFile):
        st = study_planar.analyze(doc, on_failure="nan")
        kin, mech = st.kinematics, st.mechanism
        pts = {}
        for j in mech.joints:
            if j.code == "P":
                continue
            qa, pb, _ = mech.joint_geometry(j)
            pm = kin.point(j.b, pb) if j.b != mech.frame.name else kin.point(j.a, qa)
            pts[f"joint {j.name}"] = np.stack([pm.x, pm.y]) * 1e3
        return pts, np.asarray(kin.phi1)
    if isinstance(doc, io.SinePressFile):
        c = sine_press.analyze(doc).idle_cycle
        return {"idle joint B": np.stack([c.X_B, c.Y_B]) * 1e3,
                "idle joint C": np.stack(np.broadcast_arrays(c.X_C, c.Y_C)) * 1e3}, c.phi1
    st = swashplate.analyze(doc)
    R = st.design.R
    return {"side joint A": np.stack([-R * np.cos(st.cycle.phi), st.cycle.s]) * 1e3}, \
        st.cycle.phi


STEMS = [p.stem for p in EXAMPLES]


@pytest.mark.parametrize("opened", STEMS, indirect=True)
def test_report_loads_offline_without_errors_or_requests(opened):
    opened.page.wait_for_timeout(300)
    assert [m for m in opened.messages if m[0] in ("error", "warning", "pageerror")] == []
    assert opened.requests == [opened.url]      # the file itself, nothing from the network


@pytest.mark.parametrize("opened", STEMS, indirect=True)
def test_animation_advances_and_draws_the_engine_positions(opened):
    o = opened
    first_frame = o.api("frame()")
    moving = o.data["scene"]["shapes"][0]["id"]
    sel = f"[id^='{moving}']"
    before = o.page.locator(sel).first.evaluate("e => e.outerHTML")
    o.page.wait_for_function(f"document.getElementById('lw').linkwork.frame() != {first_frame}",
                             timeout=5000)
    o.page.wait_for_timeout(150)
    assert o.api("playing()")
    assert o.page.locator(sel).first.evaluate("e => e.outerHTML") != before  # the pose moved
    stem = Path(o.url).stem
    engine, positions = _engine_points(stem)
    frames = o.data["scene"]["frames"]
    q = o.data["scene"]["q"]
    for k in _frames_to_check(o):
        o.api(f"show({k})")
        assert o.api("frame()") == k and not o.api("playing()")
        i = frames[k]                                    # the cycle's position of frame k
        unit_f = 180 / math.pi if o.data["scene"]["unit"] == "deg" else 1e3
        assert o.data["scene"]["pos"][k] == pytest.approx(positions[i] * unit_f, abs=1e-5)
        for name, xy in engine.items():
            drawn = o.circle(name)
            assert drawn == pytest.approx((xy[0, i], xy[1, i]), abs=0.51 * q + 1e-6), \
                f"{name} at frame {k}"


@pytest.mark.parametrize("opened", STEMS, indirect=True)
def test_slider_and_diagram_cursor_agree_both_ways(opened):
    o = opened
    o.api("pause()")
    chart = next(c for c in o.data["charts"] if c["linked"] and not c["parametric"])
    o.api(f"show({_frames_to_check(o)[1]})")
    slider = o.page.locator("#lw-slider")
    slider.focus()
    for _ in range(3):
        o.page.keyboard.press("ArrowRight")             # a person moving the slider
    k = int(slider.input_value())
    assert o.api("frame()") == k
    s = chart["f2s"][k]
    cursor = o.page.locator(f"#{chart['id']}-cursor")
    assert float(cursor.get_attribute("x1")) == pytest.approx(chart["px"][s], abs=0.05)
    # a click on the diagram at a sample's abscissa shows that sample's frame
    target = len(chart["px"]) // 3
    box = o.page.locator(f"#{chart['id']}").bounding_box()
    vb = o.page.locator(f"#{chart['id']}").evaluate(
        "e => [e.viewBox.baseVal.width, e.viewBox.baseVal.height]")
    x = box["x"] + chart["px"][target] / vb[0] * box["width"]
    y = box["y"] + 0.5 * (chart["box"][2] + chart["box"][3]) / vb[1] * box["height"]
    o.page.mouse.click(x, y)
    k2 = int(slider.input_value())
    assert o.api("frame()") == k2
    # the frame of the clicked sample, or of a neighbour within the click's screen pixel (the
    # browser rounds mouse positions; a 721-point curve has samples closer than a pixel)
    pixel = vb[0] / box["width"]                        # chart units per screen pixel
    near = [chart["s2f"][i] for i, px in enumerate(chart["px"])
            if px is not None and abs(px - chart["px"][target]) <= pixel]
    assert k2 in near
    cursor_x = float(cursor.get_attribute("x1"))
    assert abs(cursor_x - chart["px"][target]) <= pixel  # the cursor stands where clicked


@pytest.mark.parametrize("opened", [*STEMS, "fourbar_partial"], indirect=True)
def test_screenshot_of_each_report(opened):
    o = opened
    o.api("show(Math.floor(document.getElementById('lw').linkwork.n / 8))")
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    shot = SCREENSHOTS / f"{Path(o.url).stem}.png"
    o.page.screenshot(path=str(shot))
    assert shot.stat().st_size > 10_000


@pytest.mark.parametrize("opened", ["fourbar_partial"], indirect=True)
def test_unassembled_positions_are_skipped_and_said(opened):
    o = opened
    valid = o.data["scene"]["valid"]
    seen = set()
    for _ in range(40):
        o.page.wait_for_timeout(40)
        seen.add(o.api("frame()"))
    assert len(seen) > 5 and all(valid[k] == 1 for k in seen)
    bad = valid.index(0)
    o.api(f"show({bad})")
    assert "not assembled" in o.page.text_content("#lw-state")
    assert "lw-off" in o.page.get_attribute("#lw-scene", "class")
    warn = o.page.text_content(".lw-warning")
    assert "[102, 258 deg]" in warn and "skips" in warn
    assert [m for m in o.messages if m[0] in ("error", "pageerror")] == []


def test_notebook_views_run_side_by_side(browser, tmp_path):
    """Two results' ``_repr_html_`` on one page (as in a notebook): each view animates on its
    own, with no error and no request."""
    fourbar = study_planar.analyze(io.load(ROOT / "examples" / "fourbar_paper001.toml"))
    press = sine_press.analyze(io.load(ROOT / "examples" / "sine_press.toml"))
    html = ("<!DOCTYPE html><html><head><meta charset='utf-8'></head><body>"
            + fourbar._repr_html_() + press.working_cycle._repr_html_() + "</body></html>")
    path = tmp_path / "notebook.html"
    path.write_text(html, encoding="utf-8")
    o = Opened.__new__(Opened)
    o.context = browser.new_context(offline=True)
    o.page = o.context.new_page()
    o.messages, o.requests = [], []
    o.page.on("console", lambda m: o.messages.append((m.type, m.text)))
    o.page.on("pageerror", lambda e: o.messages.append(("pageerror", str(e))))
    o.page.on("request", lambda r: o.requests.append(r.url))
    try:
        o.page.goto(path.resolve().as_uri())
        ids = o.page.eval_on_selector_all(".lw-view", "els => els.map(e => e.id)")
        assert len(ids) == 2 and ids[0] != ids[1]
        first = [o.page.evaluate(f"document.getElementById('{i}').linkwork.frame()")
                 for i in ids]
        for i, f in zip(ids, first, strict=True):
            o.page.wait_for_function(
                f"document.getElementById('{i}').linkwork.frame() != {f}", timeout=5000)
        assert [m for m in o.messages if m[0] in ("error", "warning", "pageerror")] == []
        assert o.requests == [path.resolve().as_uri()]
    finally:
        o.context.close()
