"""The synthesis part of the report (linkwork.report.synthesis): every design of every task of a
synthesis file is a drawing of the player, with the task's targets; each design's diagrams and
table row refer to its own drawing; the Pareto chart is the designs' metrics; a task that
fails is said in its section, a file whose every task fails is an error; a six-bar path
task's designs drawn whole (tests/data/synthesis: a planted Stephenson III and Watt II).

References: the studies run here directly (the same seeds give the same designs), the
closed-form coupler point of the path designs (synthesis.design.coupler_point) to 1e-12 m,
the engine's coupler angle at the poses' crank angles for the pose axis drawn on the coupler
(1e-9 rad); the six-bars' closed form of the two loops (synthesis.sixbar.sixbar_point) and
the links' lengths between the drawn joints (loop closure) to 1e-12 m.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from linkwork import io, report
from linkwork.errors import InfeasibleError
from linkwork.planar import kinematics
from linkwork.studies import synthesis as study_synthesis
from linkwork.studies.synthesis import design_table
from linkwork.synthesis import sixbar as S
from linkwork.synthesis.design import coupler_point

ROOT = Path(__file__).resolve().parents[2]
TASKS = ROOT / "examples" / "synthesis_tasks.toml"


@pytest.fixture(scope="module")
def built():
    doc = io.load(TASKS)
    page = report.build(doc, path=TASKS)
    studies = {k: study_synthesis.run(doc, k) for k in ("path", "function", "motion")}
    return page, studies


def _first(studies, kind):
    """Index of the kind's first design among the page's drawings."""
    order = ["path", "function", "motion"]
    return sum(len(studies[k].designs) for k in order[:order.index(kind)])


def test_every_design_is_a_drawing_and_the_path_ones_trace_their_coupler_curve(built):
    page, studies = built
    labels = [label for label, _ in page.choices]
    assert len(labels) == sum(len(s.designs) for s in studies.values())
    assert page.scene is page.choices[0][1]
    path = studies["path"]
    for i, d in enumerate(path.designs):
        label, scene = page.choices[i]
        assert label.startswith(f"path design {i + 1}: f = {d.error:.3g}")
        P = scene.shape("path coupler.P").xy                   # (n, 2)
        x, y, _ = coupler_point(scene.positions - d.params["theta0"], d.params, d.branch)
        np.testing.assert_allclose(P[:, 0], x, atol=1e-12)
        np.testing.assert_allclose(P[:, 1], y, atol=1e-12)
        for k, (tx, ty) in enumerate(path.result.points):     # the targets, numbered
            t = scene.shape(f"target {k + 1}")
            assert t.label == str(k + 1) and np.allclose(t.xy[0], (tx, ty), atol=0)


def test_the_pose_axis_on_the_coupler_lines_up_with_every_pose(built):
    page, studies = built
    motion = studies["motion"]
    poses = np.asarray(motion.result.poses)
    j0 = _first(studies, "motion")
    for i, d in enumerate(motion.designs):
        scene = page.choices[j0 + i][1]
        axis = scene.shape("pose axis on the coupler").xy     # (2, 2, n)
        drawn = np.arctan2(axis[1, 1] - axis[0, 1], axis[1, 0] - axis[0, 0])
        fb = d.fourbar
        kin = motion.motion(i)
        offset = drawn - np.asarray(kin.angle("coupler"))      # constant along the cycle
        assert np.ptp(np.unwrap(offset)) < 1e-9
        at = kinematics(d.mechanism(), fb.theta2 + fb.params["theta0"])
        gap = np.mod(at.angle("coupler") + offset[0] - poses[:, 2] + math.pi, 2 * math.pi)
        np.testing.assert_allclose(gap - math.pi, 0.0, atol=1e-9)
        for k in range(len(poses)):
            assert scene.shape(f"pose {k + 1} axis").xy.shape == (2, 2)


def test_each_designs_diagrams_and_row_refer_to_its_drawing(built):
    page, studies = built
    sections = {s.key: s for s in page.sections}
    for kind in ("path", "function", "motion"):
        sec = sections[f"synthesis-{kind}"]
        j0 = _first(studies, kind)
        n = len(studies[kind].designs)
        linked = [d for d in sec.diagrams if d.positions is not None
                  and d.title.startswith("design ")]
        assert [d.scene for d in linked] == list(range(j0, j0 + n))
        assert list(sec.tables[0].chooses) == list(range(j0, j0 + n))
    path = sections["synthesis-path"]
    for i in range(len(studies["path"].designs)):
        d = next(x for x in path.diagrams if x.title.startswith(f"design {i + 1}:"))
        P = page.choices[i][1].shape("path coupler.P").xy
        np.testing.assert_allclose(d.x, P[:, 0] * 1e3, rtol=1e-12)
        np.testing.assert_allclose(d.series[0][1], P[:, 1] * 1e3, rtol=1e-12)
        np.testing.assert_allclose(d.positions, page.choices[i][1].positions)


def test_pareto_chart_holds_the_designs_metrics(built):
    page, studies = built
    res = studies["path"].result
    sec = next(s for s in page.sections if s.key == "synthesis-path")
    chart = next(d for d in sec.diagrams if d.title.startswith("accuracy against dynamics"))
    for i, d in enumerate(res.designs):
        name, x, y, colour = chart.points[i]
        assert name == f"design {i + 1}" and colour == i
        assert x[0] == pytest.approx(math.log10(d.error)) and y[0] == d.forces["peak_torque"]
    front = chart.lines[0]
    assert front.name == "Pareto set" and len(front.x) == len(res.pareto)
    assert np.all(np.diff(front.x) >= 0)


def _task(tmp_path, body):
    p = tmp_path / "task.toml"
    p.write_text('type = "synthesis"\nname = "t"\n' + body)
    return p


FUNCTION = ('[function]\ny = "log10(x)"\nx_range = [1, 10]\n'
            'input = { start = "30 deg", span = "60 deg" }\n'
            'output = { start = "110 deg", span = "60 deg" }\nframe = "100 mm"\n')
IMPOSSIBLE = ('[path]\npoints = [[0.02, 0.02], [0.02, 0.025], [0.02, 0.03], [0.025, 0.035]]\n'
              'min_transmission = "89.5 deg"\n[search]\ncandidates = 256\nrefine = 2\n')


def test_a_failing_task_is_said_and_a_file_whose_every_task_fails_is_an_error(tmp_path):
    both = _task(tmp_path, IMPOSSIBLE + FUNCTION)
    page = report.build(io.load(both), path=both)
    sections = {s.key: s for s in page.sections}
    assert "transmission angle >= 89.5 deg" in sections["synthesis-path"].error
    assert not sections["synthesis-function"].error
    assert [label.split(":")[0] for label, _ in page.choices] == [
        "function design 1", "function design 2", "function design 3"]
    assert list(sections["synthesis-function"].tables[0].chooses) == [0, 1, 2]
    only = _task(tmp_path, IMPOSSIBLE)
    with pytest.raises(InfeasibleError, match=r"transmission angle >= 89\.5 deg"):
        report.build(io.load(only), path=only)


SIXBARS = ROOT / "tests" / "data" / "synthesis"


@pytest.fixture(scope="module", params=["stephenson", "watt"])
def sixbar(request):
    path = SIXBARS / f"{request.param}_path.toml"
    doc = io.load(path)
    return request.param, report.build(doc, path=path), study_synthesis.run(doc, "path")


def test_a_six_bar_design_is_drawn_whole_and_traces_its_point(sixbar):
    """A six-bar path task (tests/data/synthesis/*_path.toml, a planted Stephenson III and
    Watt II): every design is a drawing with all five moving links and the three fixed pivots;
    the drawn path of P is the closed form of the two loops (sixbar.sixbar_point, its own
    circle intersections) at the drawing's crank angles, to 1e-12 m; the drawn joints keep
    the links' lengths at every position (|CD| = r5, |O6 D| = r6, |AB| = r3, |O4 B| = r4, to
    1e-12 m: loop closure, independent of how the scene was built); the targets numbered."""
    kind, page, study = sixbar
    assert len(page.choices) == len(study.designs) >= 1
    for i, d in enumerate(study.designs):
        label, scene = page.choices[i]
        assert label.startswith(f"path design {i + 1}: f = {d.error:.3g}")
        names = {s.name for s in scene.shapes}
        assert {"crank", "coupler", "rocker", "link5", "link6", "joint O2", "joint O4",
                "joint O6", "joint A", "joint B", "joint C", "joint D"} <= names
        P = scene.shape("path link5.P").xy                     # (n, 2)
        x, y, ok = S.sixbar_point(scene.positions - d.params["theta0"], d.vector[None, :],
                                  [d.branches], kind)
        assert ok.all()
        np.testing.assert_allclose(P[:, 0], x[0], rtol=0, atol=1e-12)
        np.testing.assert_allclose(P[:, 1], y[0], rtol=0, atol=1e-12)
        j = {n: scene.shape(f"joint {n}").xy[0] for n in ("A", "B", "C", "D", "O4", "O6")}
        p = d.params
        for a, b, length in (("C", "D", p["r5"]), ("O6", "D", p["r6"]), ("A", "B", p["r3"]),
                             ("O4", "B", p["r4"])):
            np.testing.assert_allclose(np.hypot(*(j[a] - j[b])), length, rtol=0, atol=1e-12)
        for k, (tx, ty) in enumerate(study.result.points):
            assert np.allclose(scene.shape(f"target {k + 1}").xy[0], (tx, ty), atol=0)


def test_a_six_bar_section_links_its_diagrams_and_says_its_linkage(sixbar):
    """The six-bar's coupler-point diagrams follow its drawings (the drawn P, in mm), the
    ranked table is the command's (the six-bar's fourteen lengths and both branches, no Pareto
    column: a six-bar search is not judged by forces), the task table and the notes name the
    linkage and its parameters."""
    kind, page, study = sixbar
    name = {"stephenson": "Stephenson III six-bar", "watt": "Watt II six-bar"}[kind]
    sec = next(s for s in page.sections if s.key == "synthesis-path")
    assert not sec.error and sec.intro[0].startswith(f"{name}s: 8 target points")
    for i in range(len(study.designs)):
        dia = next(x for x in sec.diagrams if x.title.startswith(f"design {i + 1}:"))
        P = page.choices[i][1].shape("path link5.P").xy
        assert dia.scene == i
        np.testing.assert_allclose(dia.x, P[:, 0] * 1e3, rtol=1e-12)
        np.testing.assert_allclose(dia.series[0][1], P[:, 1] * 1e3, rtol=1e-12)
    table = sec.tables[0]
    assert table.head == design_table(study)[0] and "Pareto" not in table.head
    assert {"r5 [mm]", "x6 [mm]", "px [mm]", "branches B, D"} <= set(table.head)
    assert list(table.chooses) == list(range(len(study.designs)))
    task = next(t for t in page.inputs if t.caption == "[path] task")
    assert task.rows[0] == ["linkage", name]
    (title, text), = page.notes
    assert title == "path synthesis: conventions" and text.startswith("Six-bars:")
    assert ("on its coupler" if kind == "stephenson" else "on its rocker") in text
