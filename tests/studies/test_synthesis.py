"""The synthesis study's motion of a design (linkwork.studies.synthesis.SynthesisStudy.motion):
the planar engine over the range the design runs gives what the synthesis found in closed
form.

References: the path generator's closed-form coupler point (synthesis.design.coupler_point,
an expression of the link lengths, independent of the engine's group solver) to 1e-12 m; the
function generator's output as the synthesis computed it (FunctionDesign.actual, Freudenstein's
closed form) to 1e-9 rad; a motion design reaches every pose (point to 1e-9 of the poses'
size, the coupler's angle a constant offset from the poses' angles).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from linkwork import io
from linkwork.planar import kinematics
from linkwork.studies import synthesis as study_synthesis
from linkwork.synthesis.design import coupler_point

TASKS = Path(__file__).resolve().parents[2] / "examples" / "synthesis_tasks.toml"


@pytest.fixture(scope="module")
def doc():
    return io.load(TASKS)


def test_path_design_motion_is_the_closed_form_coupler_curve(doc):
    st = study_synthesis.run(doc, "path")
    assert len(st.designs) >= 2 and st.result.pareto == tuple(range(len(st.designs)))
    for i, d in enumerate(st.designs):
        kin = st.motion(i, 181)
        phi = st.crank_angles(i, 181)
        assert np.array_equal(kin.phi1, phi) and kin.valid.all()
        x, y, ok = coupler_point(phi - d.params["theta0"], d.params, d.branch)
        P = kin.point("coupler", "P")
        assert ok.all()
        np.testing.assert_allclose(P.x, x, rtol=0, atol=1e-12)
        np.testing.assert_allclose(P.y, y, rtol=0, atol=1e-12)
        if d.checks.get("crank_rotates"):
            assert abs(abs(phi[-1] - phi[0]) - 2 * math.pi) < 1e-12


def test_function_design_motion_gives_its_output(doc):
    st = study_synthesis.run(doc, "function")
    for i, d in enumerate(st.designs):
        kin = st.motion(i, d.input.size)
        np.testing.assert_allclose(kin.phi1, d.input, rtol=0, atol=1e-12)
        psi = np.unwrap(kin.angle("rocker"))
        np.testing.assert_allclose(psi, d.actual + 2 * math.pi * np.round(
            (psi[0] - d.actual[0]) / (2 * math.pi)), rtol=0, atol=1e-9)


def test_motion_design_motion_passes_every_pose(doc):
    st = study_synthesis.run(doc, "motion")
    poses = np.asarray(st.result.poses)
    size = float(np.hypot(*np.ptp(poses[:, :2], axis=0)))
    for i, d in enumerate(st.designs):
        kin = st.motion(i)
        fb = d.fourbar
        assert kin.phi1[0] == pytest.approx(fb.theta2[0] + fb.params["theta0"], abs=1e-12)
        at = kinematics(d.mechanism(), fb.theta2 + fb.params["theta0"])
        P = at.point("coupler", "P")
        np.testing.assert_allclose(np.c_[P.x, P.y], poses[:, :2], atol=1e-9 * size)
        off = np.mod(at.angle("coupler") - poses[:, 2], 2 * math.pi)
        assert np.ptp(np.unwrap(off)) < 1e-9


def test_an_unknown_design_index_is_named(doc):
    from linkwork.errors import ParameterError

    st = study_synthesis.run(doc, "function")
    with pytest.raises(ParameterError, match=r"i = 3 is invalid: must be a design's index, 0 "
                                             r"to 2"):
        st.motion(3)
