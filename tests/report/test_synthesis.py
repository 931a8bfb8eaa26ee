"""The synthesis part of the report (linkwork.report.synthesis): every design of every task of a
synthesis file is a drawing of the player, with the task's targets; each design's diagrams and
table row refer to its own drawing; the Pareto chart is the designs' metrics; a task that
fails is said in its section, a file whose every task fails is an error.

References: the studies run here directly (the same seeds give the same designs), the
closed-form coupler point of the path designs (synthesis.design.coupler_point) to 1e-12 m,
the engine's coupler angle at the poses' crank angles for the pose axis drawn on the coupler
(1e-9 rad).
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
