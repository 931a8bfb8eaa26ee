"""The report (linkwork.report): every example makes a page from the studies' objects, the
partly assembled mechanism shows its ranges, and a renderer plugs in by registration.

The size of a page is bounded (the issue: a few MB at most for 360 positions); the numbers a
page shows are the studies' (compared here with the study run directly).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from linkwork import io, report
from linkwork.errors import AssemblyError
from linkwork.plot.html import Section, page_html
from linkwork.report.base import Renderer
from linkwork.studies import planar as study_planar

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))
PARTIAL = ROOT / "tests" / "data" / "partial" / "fourbar_partial.toml"

#: The largest page of a bundled example (the geared five-bar, 1801 positions, is about 1.7 MB).
MAX_BYTES = 2_500_000


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_every_example_makes_a_bounded_self_contained_page(path):
    doc = io.load(path)
    page = report.build(doc, path=path)
    html = page_html(page)
    assert len(html.encode()) < MAX_BYTES
    assert page.scene is not None and page.scene.valid.any()
    assert page.sections and not any(s.error for s in page.sections)
    assert page.version and re.fullmatch(r"\d{4}-\d\d-\d\d", page.date)
    assert page.source == path.read_text()          # the input as written, units and all
    assert page.inputs and page.notes
    assert "<script src" not in html and "<link" not in html


def test_planar_report_has_balance_and_reactions_sections_when_the_file_asks():
    doc = io.load(ROOT / "examples" / "loom_fourbar_spatial.toml")
    keys = [s.key for s in report.build(doc).sections]
    assert keys[0] == "planar"
    assert ("spatial" in doc.model_fields_set) == ("reactions" in keys)
    assert ("balance" in doc.model_fields_set) == ("balance" in keys)


def test_report_shows_the_study_numbers():
    """The extremes table is the study's peaks (no recomputation): same values, same
    positions."""
    path = ROOT / "examples" / "fourbar_paper001.toml"
    doc = io.load(path)
    study = study_planar.analyze(doc)
    page = report.build(doc, path=path)
    table = page.sections[0].tables[0]
    peaks = {p["name"]: p for p in study.peaks}
    for row, pos in zip(table.rows, table.positions, strict=True):
        if row[0] in peaks:
            assert pos == peaks[row[0]]["phi1"]
            value = peaks[row[0]]["value"]
            shown = float(row[1])
            if peaks[row[0]]["unit"] == "rad":
                value = np.degrees(value)
            assert shown == pytest.approx(value, rel=5e-4)


def test_a_partly_assembled_mechanism_is_reported_with_its_ranges():
    doc = io.load(PARTIAL)
    page = report.build(doc, path=PARTIAL)
    assert page.warnings and "[102, 258 deg]" in page.warnings[0]
    valid = page.scene.valid
    assert 0 < valid.sum() < valid.size
    deg = np.degrees(page.scene.positions)
    assert not valid[(deg > 103) & (deg < 257)].any()
    assert valid[(deg < 101) | (deg > 259)].all()


def test_a_mechanism_that_never_assembles_gives_an_error_not_a_page(tmp_path):
    text = PARTIAL.read_text().replace('length = "150 mm"', 'length = "10 mm"').replace(
        'length = "250 mm"', 'length = "10 mm"')  # |AC| >= 110 mm > 10 + 10 mm
    bad = tmp_path / "never.toml"
    bad.write_text(text)
    with pytest.raises(AssemblyError, match="at no position"):
        report.build(io.load(bad), path=bad)


def test_a_renderer_plugs_in_by_registration():
    doc = io.load(ROOT / "examples" / "fourbar_paper001.toml")
    extra = Renderer(key="extra", title="extra part", file_type=io.PlanarFile,
                     run=lambda d, o: d.name,
                     section=lambda study, o: Section("extra part", "extra",
                                                      intro=[f"of {study}"]))
    report.register(extra)
    try:
        sections = report.build(doc).sections
        assert sections[-1].key == "extra" and "Four-bar" in sections[-1].intro[0]
        failing = Renderer(key="extra", title="extra part", file_type=io.PlanarFile,
                           run=lambda d, o: (_ for _ in ()).throw(AssemblyError("no")),
                           section=lambda s, o: Section("x", "x"))
        report.register(failing)
        last = report.build(doc).sections[-1]
        assert last.error == "not computed: no"    # a failing part is shown, not fatal
    finally:
        report.register(extra)
        from linkwork.report import core
        core._RENDERERS[:] = [r for r in core._RENDERERS if r.key != "extra"]
    assert [r.key for r in report.renderers()] == [
        "planar", "balance", "reactions", "sine_press", "dynamics", "swashplate",
        "synthesis-path", "synthesis-function", "synthesis-motion"]


def test_several_drivers_are_reported_along_their_path():
    """The excavator's three cylinders: the diagrams run over the positions' index, each
    driver's force and coordinate drawn (the study's own arrays), the extremes give the
    position and every driver there, the table every driver's coordinate and force."""
    path = ROOT / "examples" / "excavator_boom.toml"
    doc = io.load(path)
    page = report.build(doc, path=path)
    study = study_planar.analyze(doc)
    sec = page.sections[0]
    q = next(d for d in sec.diagrams if d.title.startswith("driving forces Q"))
    assert q.xlabel == "position along the drivers' path"
    np.testing.assert_allclose(q.positions, np.arange(81))
    assert [n for n, _ in q.series] == ["Q boom_cyl", "Q arm_cyl", "Q bucket_cyl"]
    scale = np.max(np.abs(study.dynamics.Q)) / np.max(np.abs([v for _, v in q.series]))
    for k, (_, v) in enumerate(q.series):
        np.testing.assert_allclose(v * scale, study.dynamics.Q[k], rtol=1e-12)
    ext = sec.tables[0]
    assert ext.head[-2:] == ["position", "the drivers there"]
    first = ext.rows[0]
    assert first[0] == "Q boom_cyl max" and first[3] == "0"
    assert first[4] == "boom_cyl 1300.0 mm, arm_cyl 1450.0 mm, bucket_cyl 1300.0 mm"
    table = next(t for t in sec.tables if t.caption.startswith("driving torque, joint"))
    assert table.head[:6] == ["s boom_cyl [mm]", "s arm_cyl [mm]", "s bucket_cyl [mm]",
                              "Q boom_cyl [N]", "Q arm_cyl [N]", "Q bucket_cyl [N]"]
    assert table.positions == [float(round(k * 80 / 11)) for k in range(12)]
    assert [r[0] for r in page.inputs[2].rows[:2]] == ["driver (boom_cyl)",
                                                        "speed (boom_cyl)"]
