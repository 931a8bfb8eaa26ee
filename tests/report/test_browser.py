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
from linkwork.studies import synthesis as study_synthesis

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
    """Five assembled frames spread over the drawing shown."""
    shown = o.api("choice()")
    scene = o.data["scene"] if shown == 0 else o.data["alternatives"][shown - 1]
    valid = np.flatnonzero(np.array(scene["valid"]) == 1)
    return [int(valid[int(k)]) for k in np.linspace(0, valid.size - 1, 5)]


def _joint_points(kin: Any) -> dict[str, np.ndarray]:
    """Every non-prismatic joint's point from the engine [mm, (2, n)], by its drawn name."""
    mech = kin.mechanism
    pts = {}
    for j in mech.joints:
        if j.code == "P":
            continue
        qa, pb, _ = mech.joint_geometry(j)
        pm = kin.point(j.b, pb) if j.b != mech.frame.name else kin.point(j.a, qa)
        pts[f"joint {j.name}"] = np.stack([pm.x, pm.y]) * 1e3
    return pts


def _engine_points(stem: str) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The engine's (or closed form's) positions of named drawn circles [mm, (2, n)] and the
    positions of the frames [SI], computed here from the studies, not from the report."""
    path = PARTIAL if stem == "fourbar_partial" else ROOT / "examples" / f"{stem}.toml"
    doc = io.load(path)
    if isinstance(doc, io.PlanarFile):
        kin = study_planar.analyze(doc, on_failure="nan").kinematics
        if kin.mechanism.n_drivers > 1:      # the frames are the positions' indices
            return _joint_points(kin), np.arange(kin.n, dtype=float)
        return _joint_points(kin), np.asarray(kin.phi1)
    if isinstance(doc, io.SynthesisFile):      # the page shows the first path design first
        kin = study_synthesis.run(doc, "path").motion(0)
        return _joint_points(kin), np.asarray(kin.phi1)
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
        unit_f = {"deg": 180 / math.pi, "mm": 1e3, "": 1.0}[o.data["scene"]["unit"]]
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
    o.api(f"choose({chart['scene']})")                 # the drawing the chart refers to
    assert o.api("choice()") == chart["scene"]
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
    o.page.locator(f"#{chart['id']}").scroll_into_view_if_needed()
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
    assert cursor_x == pytest.approx(chart["px"][chart["f2s"][k2]], abs=0.05)  # frame's sample
    # where clicked, to a pixel, or to a frame's step where the chart has more samples
    nxt = chart["f2s"][min(k2 + 1, len(chart["f2s"]) - 1)]
    step = abs(chart["px"][nxt] - chart["px"][chart["f2s"][k2]])
    assert abs(cursor_x - chart["px"][target]) <= pixel + step


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


def _polyline(o: Opened, name: str) -> np.ndarray:
    """Vertices of the drawn polyline called ``name`` in the drawing's mm (y up), (k, 2);
    empty where it is not drawn at this frame."""
    pts = o.page.locator(f'polyline[data-name="{name}"]').first.get_attribute("points") or ""
    xy = np.array([[float(v) for v in p.split(",")] for p in pts.split()]).reshape(-1, 2)
    return xy * [1.0, -1.0]


@pytest.mark.parametrize("opened", ["crank_press"], indirect=True)
def test_force_elements_are_drawn_where_they_act(opened):
    """crank_press: the counterbalance spring from the frame point K to the ram's R, and the
    drawing force's arrow at the wrist pin B only where the study's value is not zero (its
    diagram acts while the ram goes down through its last 20 mm); the switch hides them."""
    o = opened
    o.api("pause()")
    st = study_planar.analyze(io.load(ROOT / "examples" / "crank_press.toml"))
    value = st.dynamics.load("drawing").value
    R = st.kinematics.point("ram", "R")
    B = st.kinematics.point("ram", "B")
    frames, q = o.data["scene"]["frames"], o.data["scene"]["q"]
    acting = [k for k, i in enumerate(frames) if value[i] != 0]
    idle = [k for k, i in enumerate(frames) if value[i] == 0]
    assert acting and idle
    for k in (acting[0], acting[len(acting) // 2], idle[0], idle[len(idle) // 2]):
        o.api(f"show({k})")
        i = frames[k]
        zig = _polyline(o, "spring counterbalance")
        assert zig[0] == pytest.approx((250.0, 0.0), abs=0.51 * q)
        assert zig[-1] == pytest.approx((R.x[i] * 1e3, R.y[i] * 1e3), abs=0.51 * q)
        arrow = _polyline(o, "load drawing")
        if value[i] != 0:
            assert arrow[1] == pytest.approx((B.x[i] * 1e3, B.y[i] * 1e3), abs=0.51 * q)
            assert arrow[1, 1] > arrow[0, 1]                # pushes the ram up
        else:
            assert arrow.size == 0                          # not drawn where it does not act
    visible = "e => getComputedStyle(e).display != 'none'"
    spring = o.page.locator('polyline[data-name="spring counterbalance"]')
    assert spring.evaluate(visible)
    o.page.locator("#lw-show-forces").uncheck()
    assert not spring.evaluate(visible)
    assert [m for m in o.messages if m[0] in ("error", "pageerror")] == []


@pytest.mark.parametrize("stem", ["loom_sixbar"])
def test_real_time_follows_the_machines_real_motion(browser, pages, stem):
    """With a page clock that only moves when told (Playwright's clock), each motor's "real
    time" plays the turn at the study's real crank speed: at any moment the frame shown is the
    last one the real motion has reached, the crank angle of the study's steady state at that
    time (interpolated over its own t and phi1) lies between this frame and the next, and the
    readout shows that frame's time and speed."""
    from linkwork.studies import dynamics as study_dynamics

    study = study_dynamics.run(io.load(ROOT / "examples" / f"{stem}.toml"))
    context = browser.new_context(offline=True, viewport={"width": 1400, "height": 900})
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    try:
        page.clock.install(time=0)
        page.goto(pages[stem].resolve().as_uri())
        page.clock.pause_at(10_000)
        api = "document.getElementById('lw').linkwork"
        data = json.loads(page.text_content("#lw-data"))["scene"]
        for m, choice in enumerate(study.choices):
            ss = choice.steady
            page.evaluate(f"{api}.show(0)")
            page.select_option("#lw-speed", f"t{m}")
            page.evaluate(f"{api}.play()")
            pos = np.array(data["pos"])                          # deg, the frames' angles
            t0 = np.interp(np.radians(pos[0]), ss.phi1, ss.t)
            seen = []
            for step in (90, 350, 420, 700, 260):               # ms; wraps past one period
                page.clock.run_for(step)
                k = page.evaluate(f"{api}.frame()")
                clock = page.evaluate(f"{api}.clock()")
                seen.append(k)
                t = np.append(ss.t - ss.t[0], ss.period)
                phi = np.degrees(np.append(ss.phi1, ss.phi1[0] + 2 * np.pi))
                at = np.interp((clock + t0) % ss.period, t, phi) % 360.0
                nxt = pos[k + 1] if k + 1 < pos.size else 360.0
                assert pos[k] - 1e-6 <= at < nxt + 0.05, (m, step, k, at)
                text = page.text_content("#lw-time")
                assert f"t = {data['timings'][m]['t'][k]:.3f} s" in text
            assert len(set(seen)) == len(seen)
            page.evaluate(f"{api}.pause()")
        assert errors == []
    finally:
        context.close()


@pytest.mark.parametrize("opened", ["synthesis_tasks"], indirect=True)
def test_synthesis_designs_are_chosen_and_each_drawn_by_the_engine(opened):
    """Every design of the synthesis file is a drawing: the chooser (and a click on a design's
    table row) shows that one and hides the others; the drawn joints at several frames are the
    engine's motion of that design (SynthesisStudy.motion, run here); a design's diagram has
    its cursor only while its design is shown, and a click on it shows its design."""
    o = opened
    o.api("pause()")
    doc = io.load(ROOT / "examples" / "synthesis_tasks.toml")
    designs = [(k, i) for k in ("path", "function", "motion")
               for i in range(len(study_synthesis.run(doc, k).designs))]
    labels = o.page.eval_on_selector_all("#lw-choice option", "els => els.map(e => e.text)")
    assert len(labels) == len(designs) == len(o.data["alternatives"]) + 1
    q = o.data["scene"]["q"]
    studies = {k: study_synthesis.run(doc, k) for k in ("path", "function", "motion")}
    f1 = len(studies["path"].designs)                   # function design 1's drawing
    for j in (1, f1, len(designs) - 1):                 # a path, a function, a motion design
        o.page.select_option("#lw-choice", str(j))      # a person choosing
        assert o.api("choice()") == j
        shown = o.page.eval_on_selector_all(
            "svg.lw-scene", "els => els.filter(e => e.style.display != 'none').map(e => e.id)")
        assert shown == [f"lw-v{j}-scene"]
        kind, i = designs[j]
        kin = studies[kind].motion(i)
        engine = _joint_points(kin)
        scene = o.data["alternatives"][j - 1]
        qj = scene["q"]
        for k in _frames_to_check(o):
            o.api(f"show({k})")
            f = scene["frames"][k]
            for name, xy in engine.items():
                loc = o.page.locator(f'#lw-v{j}-scene circle[data-name="{name}"]').first
                drawn = (float(loc.get_attribute("cx")), -float(loc.get_attribute("cy")))
                assert drawn == pytest.approx((xy[0, f], xy[1, f]), abs=0.51 * qj + 1e-6)
    # a design's row shows it
    row = o.page.locator("#lw-synthesis-motion-t0 tbody tr").nth(1)
    row.click()
    assert o.api("choice()") == len(designs) - len(studies["motion"].designs) + 1
    # the cursor of function design 1's error diagram: hidden unless that design is shown
    chart = next(c for c in o.data["charts"] if c["linked"] and not c["parametric"]
                 and c["scene"] == f1)
    cursor = o.page.locator(f"#{chart['id']}-cursor")
    o.api("show(10)")
    assert cursor.get_attribute("visibility") == "hidden"
    o.page.locator(f"#{chart['id']}").scroll_into_view_if_needed()
    box = o.page.locator(f"#{chart['id']}").bounding_box()
    o.page.mouse.click(box["x"] + 0.5 * box["width"], box["y"] + 0.5 * box["height"])
    assert o.api("choice()") == f1 and cursor.get_attribute("visibility") is None
    assert q > 0 and [m for m in o.messages if m[0] in ("error", "pageerror")] == []


def test_a_six_bar_synthesis_design_is_drawn_by_the_engine(browser, tmp_path):
    """A Stephenson III six-bar path task (tests/data/synthesis/stephenson_path.toml): each
    design, chosen, is drawn with every joint (C on the coupler, D, O6 included) at the
    engine's positions of that design (SynthesisStudy.motion, run here) at several frames; no
    error on the page; the section shot for review."""
    task = ROOT / "tests" / "data" / "synthesis" / "stephenson_path.toml"
    doc = io.load(task)
    html = report.write(report.build(doc, path=task), tmp_path / "six.html")
    study = study_synthesis.run(doc, "path")
    o = Opened(browser, html)
    try:
        o.api("pause()")
        assert len(o.data["alternatives"]) + 1 == len(study.designs)
        for j in range(len(study.designs)):
            o.page.select_option("#lw-choice", str(j))
            assert o.api("choice()") == j
            engine = _joint_points(study.motion(j))
            assert {"joint C", "joint D", "joint O6"} <= set(engine)
            scene = o.data["scene"] if j == 0 else o.data["alternatives"][j - 1]
            for k in _frames_to_check(o):
                o.api(f"show({k})")
                f = scene["frames"][k]
                for name, xy in engine.items():
                    svg = "#lw-scene" if j == 0 else f"#lw-v{j}-scene"
                    loc = o.page.locator(f'{svg} circle[data-name="{name}"]').first
                    drawn = (float(loc.get_attribute("cx")), -float(loc.get_attribute("cy")))
                    assert drawn == pytest.approx((xy[0, f], xy[1, f]),
                                                  abs=0.51 * scene["q"] + 1e-6), name
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        o.page.locator("#lw-synthesis-path").screenshot(
            path=str(SCREENSHOTS / "stephenson_path-synthesis-path.png"))
        assert [m for m in o.messages if m[0] in ("error", "pageerror")] == []
    finally:
        o.close()


SECTIONS = [("loom_sixbar", "dynamics"), ("sine_press", "dynamics"),
            ("synthesis_tasks", "synthesis-path"), ("synthesis_tasks", "synthesis-function"),
            ("synthesis_tasks", "synthesis-motion")]


@pytest.mark.parametrize(("stem", "key"), SECTIONS, ids=[f"{s}-{k}" for s, k in SECTIONS])
def test_screenshot_of_each_new_section(browser, pages, stem, key):
    """Machine dynamics and synthesis sections, each shot whole for review (test-output/
    screenshots/<file>-<section>.png), with no error on the page; the crank press with its
    drawing force acting."""
    o = Opened(browser, pages[stem])
    try:
        o.api("pause()")
        section = o.page.locator(f"#lw-{key}")
        assert section.count() == 1 and section.locator(".lw-error").count() == 0
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        shot = SCREENSHOTS / f"{stem}-{key}.png"
        section.screenshot(path=str(shot))
        assert shot.stat().st_size > 20_000
        assert [m for m in o.messages if m[0] in ("error", "pageerror")] == []
    finally:
        o.close()


def test_screenshot_of_the_force_elements_at_work(browser, pages):
    """crank_press at 260 deg: the drawing force acts (its arrow at B), the spring stretched."""
    o = Opened(browser, pages["crank_press"])
    try:
        pos = np.array(o.data["scene"]["pos"])
        o.api(f"show({int(np.argmin(np.abs(pos - 260.0)))})")
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        shot = SCREENSHOTS / "crank_press-forces.png"
        o.page.locator(".lw-player").screenshot(path=str(shot))
        assert shot.stat().st_size > 10_000
        assert o.page.locator('polyline[data-name="load drawing"]').get_attribute("points")
    finally:
        o.close()


@pytest.mark.parametrize("opened", ["excavator_boom"], indirect=True)
def test_several_drivers_read_out_each_drivers_coordinate(opened):
    """The excavator's three cylinders: the frames are the positions along their path; at
    every frame checked the readout gives each cylinder's pin-to-pin length of the engine
    there, and in real time the path takes the drivers' 4 s (s / v)."""
    o = opened
    o.api("pause()")
    kin = study_planar.analyze(io.load(ROOT / "examples" / "excavator_boom.toml")).kinematics
    scene = o.data["scene"]
    assert scene["unit"] == "" and [r["label"] for r in scene["readouts"]] == [
        "s boom_cyl", "s arm_cyl", "s bucket_cyl"]
    for k in _frames_to_check(o):
        o.api(f"show({k})")
        i = scene["frames"][k]
        text = o.page.text_content("#lw-drivers")
        want = ", ".join(f"s {j} = {kin.phi1[d, i] * 1e3:.1f} mm"
                         for d, j in enumerate(("boom_cyl", "arm_cyl", "bucket_cyl")))
        assert text == want
        assert o.page.text_content("#lw-pos") == f"position {i} of {kin.n - 1}"
    o.page.select_option("#lw-speed", "t0")
    o.api("show(40)")
    assert o.page.text_content("#lw-time").startswith("t = 2.000 s of 4.050 s")
    assert [m for m in o.messages if m[0] in ("error", "pageerror")] == []
